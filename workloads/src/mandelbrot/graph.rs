//! The two-procedure graph and the executor configuration that fits it:
//! queue capacities no run can exceed and, on drivers that cap loops, an
//! iteration budget that keeps the bodies' loops within the cap.

use scheduler::{
    Capacities, ExecutorConfig, Gpu, Graph, LoopBudget, Procedure, ProcedureId, Quirks, Resource,
};

use super::{
    BLOCK_BODY, BLOCK_THREADS, BORDER_WGSL, Block, ESCAPE_WGSL, MIN_SIZE, ROOT_SIZE, TILE_BODY,
    TILE_THREADS, Tile, View,
};

/// The graph of [`graph`], with the handles of its procedures.
#[derive(Debug)]
pub struct MandelbrotGraph {
    /// The graph, ready to compile.
    pub graph: Graph,
    /// The handle of `Tile`.
    pub tile: ProcedureId<Tile>,
    /// The handle of `Block`.
    pub block: ProcedureId<Block>,
}

/// The two-procedure graph. `Block` has the higher priority, so finished
/// squares leave the queues first.
pub fn graph(view: &View) -> MandelbrotGraph {
    let mut graph = Graph::new("mandelbrot (Mariani-Silver)");
    for (name, value) in view.constants() {
        graph.constant(name, value);
    }
    graph.library(ESCAPE_WGSL).library(BORDER_WGSL);
    graph.resource(Resource::storage::<[u32]>("counts").min_len(view.pixels() as u64));
    let tile = graph.procedure(
        Procedure::of::<Tile>("Tile")
            .initial(true)
            .threads_per_item(TILE_THREADS)
            .scratch_bytes(2 * 4 * TILE_THREADS)
            .body(TILE_BODY),
    );
    let block = graph.procedure(
        Procedure::of::<Block>("Block")
            .threads_per_item(BLOCK_THREADS)
            .priority(1)
            .body(BLOCK_BODY),
    );
    graph.connect_with_fan_out(&tile, &tile, 4);
    graph.connect(&tile, &block);
    MandelbrotGraph { graph, tile, block }
}

/// Queue capacities no run can exceed: every tile of every size, and every
/// block, at once.
pub fn capacities(view: &View) -> Capacities {
    let squares = |side: u32| (view.width / side) * (view.height / side);
    let mut tiles = 0;
    let mut side = ROOT_SIZE;
    while side >= MIN_SIZE {
        tiles += squares(side);
        side /= 2;
    }
    Capacities::default()
        .with("Tile", tiles)
        .with("Block", squares(MIN_SIZE))
}

/// The most loop iterations one thread runs in one chunk of a batch: a root
/// tile's share of the border (each pixel up to `max_iter + 1` turns), its
/// share of the fill and the reduction; or a block's one pixel.
pub fn loop_iterations_per_chunk(view: &View) -> u32 {
    let border = (4 * (ROOT_SIZE - 1)).div_ceil(TILE_THREADS) * (view.max_iter + 1);
    let tile = border + (ROOT_SIZE * ROOT_SIZE).div_ceil(TILE_THREADS) + TILE_THREADS;
    tile.max(view.max_iter + 1)
}

/// The iteration budget on a driver that caps loops (`budget`, llvmpipe:
/// every loop of an invocation ends once they ran 65,535 iterations
/// together, docs/scheduler.md "Loop limits"): a workgroup leaves after as
/// many batches as keep the bodies' loops within 60% of the driver's
/// budget, and never later than the scheduler's default would.
pub fn loop_safe_iteration_budget(view: &View, chunks_per_batch: u32, budget: &LoopBudget) -> u32 {
    (budget.driver_iterations / 5 * 3 / (loop_iterations_per_chunk(view) * chunks_per_batch.max(1)))
        .clamp(1, budget.batches)
}

/// The executor configuration for `chunks_per_batch`: [`capacities`], and
/// on drivers that cap loops [`loop_safe_iteration_budget`].
pub fn config(gpu: &Gpu, view: &View, chunks_per_batch: u32) -> ExecutorConfig {
    let quirks = Quirks::of(&gpu.adapter.get_info());
    ExecutorConfig {
        capacities: capacities(view),
        iteration_budget: quirks
            .loop_budget
            .map(|budget| loop_safe_iteration_budget(view, chunks_per_batch, &budget)),
        ..ExecutorConfig::default()
    }
}
