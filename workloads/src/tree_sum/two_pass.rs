//! The tree sum without joins, for comparison: one run builds the tree
//! top-down (`Split`, which records each node's children), the host groups
//! the inner nodes by depth, and one run per level sums them bottom-up
//! (`Level`, the same body as `Refit`), from the deepest level to the root.
//! The two graphs share their resources through buffers of their own.

use std::error::Error;
use std::time::{Duration, Instant};

use scheduler::wgpu;
use scheduler::{
    Binding, CompileOptions, Executor, ExecutorConfig, Gpu, Procedure, ProcedureId, Resource,
    Seeds, Strategy,
};

use super::cpu::subtree_sums;
use super::run::{NODE_WORDS, compare, graph_with_resources as graph};
use super::wgsl::{REFIT_BODY, SPLIT_BODY};
use super::{MAX_FAN, Node, Refit, TreeParams};

/// What [`SPLIT_BODY`] does instead of opening a join: record the
/// children's ids in `links`.
const OPEN: &str = "_ = join_open_Refit(Refit(item.id, item.key, first, n));";
const RECORD: &str = "links[2u * item.id] = first;
            links[2u * item.id + 1u] = n;";

/// The resources both graphs bind, with the build graph's `links`.
const SHARED: [&str; 4] = ["params", "nodes", "fires", "counters"];

/// The two executors and the buffers they share.
#[derive(Debug)]
pub struct TwoPass {
    build: Executor,
    build_node: ProcedureId<Node>,
    level: Executor,
    level_refit: ProcedureId<Refit>,
}

/// One two-pass run: the disagreements with the CPU, a summary, the GPU
/// time of all its runs and the host's time from the first submission to
/// the last read-back (the grouping by level included).
#[derive(Debug)]
pub struct TwoPassRun {
    /// Every disagreement with the CPU, empty when the sums are right.
    pub mismatches: Vec<String>,
    /// What was summed.
    pub summary: String,
    /// Runs made: the build, then one per level with inner nodes.
    pub runs: u32,
    /// GPU time of every run together, when the device has timestamps.
    pub gpu_time: Option<Duration>,
    /// Host time of the whole.
    pub wall_time: Duration,
}

impl TwoPass {
    /// Compiles both graphs for `gpu` and makes their executors.
    pub fn new(gpu: &Gpu, config: &ExecutorConfig) -> Result<Self, Box<dyn Error>> {
        let options = CompileOptions::with_features(scheduler::recommended_features(&gpu.device));
        let mut build_graph = graph("tree build");
        build_graph.resource(Resource::storage::<[u32]>("links"));
        let build_node = build_graph.procedure(
            Procedure::of::<Node>("Split")
                .initial(true)
                .body(SPLIT_BODY.replace(OPEN, RECORD)),
        );
        build_graph.connect_with_fan_out(&build_node, &build_node, MAX_FAN);
        let mut level_graph = graph("tree level sum");
        let level_refit = level_graph.procedure(
            Procedure::of::<Refit>("Level")
                .initial(true)
                .body(REFIT_BODY),
        );
        let build = Executor::new(
            &gpu.device,
            &gpu.queue,
            &build_graph.compile(&options)?,
            config,
        )?;
        let level = Executor::new(
            &gpu.device,
            &gpu.queue,
            &level_graph.compile(&options)?,
            config,
        )?;
        Ok(Self {
            build,
            build_node,
            level,
            level_refit,
        })
    }

    /// Builds and sums the tree of `params` under `strategy` and compares
    /// the sums with the CPU.
    pub fn run(
        &mut self,
        gpu: &Gpu,
        params: &TreeParams,
        strategy: Strategy,
    ) -> Result<TwoPassRun, Box<dyn Error>> {
        let nodes = subtree_sums(params).1.nodes;
        let words = |name: &str| -> u64 {
            match name {
                "params" => 3,
                "nodes" => nodes * u64::from(NODE_WORDS),
                "counters" => 3,
                "links" => 2 * nodes,
                _ => nodes,
            }
        };
        let mut buffers: Vec<(&str, wgpu::Buffer)> = Vec::new();
        for name in SHARED.into_iter().chain(["links"]) {
            let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(name),
                size: 4 * words(name),
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            // wgpu creates buffers zeroed; `params` gets its words.
            if name == "params" {
                gpu.queue
                    .write_buffer(&buffer, 0, &params.words().map(u32::to_le_bytes).concat());
            }
            buffers.push((name, buffer));
        }
        let buffer = |name: &str| -> &wgpu::Buffer {
            &buffers
                .iter()
                .find(|(n, _)| *n == name)
                .expect("every buffer was created above")
                .1
        };
        let read = |name: &str| read_words(gpu, buffer(name));
        let bind = |names: &[&'static str]| -> Vec<Binding<'_>> {
            names
                .iter()
                .map(|&name| Binding::buffer(name, buffer(name)))
                .collect()
        };
        let start = Instant::now();
        let mut gpu_time = Some(Duration::ZERO);
        let mut add = |time: Option<Duration>| {
            gpu_time = gpu_time.zip(time).map(|(a, b)| a + b);
        };
        let root = Node {
            id: 0,
            key: params.root_key,
            shape: 0,
        };
        let build_bindings = bind(&["params", "nodes", "fires", "counters", "links"]);
        let report = self.build.run_with(
            strategy,
            &Seeds::new().add(&self.build_node, &[root]),
            &build_bindings,
        )?;
        add(report.gpu_time);
        let mut runs = 1;

        // The host groups the inner nodes by depth.
        let used = (read("counters")?[0] + 1) as usize;
        let node_words = read("nodes")?;
        let links = read("links")?;
        let mut levels: Vec<Vec<Refit>> = vec![Vec::new(); params.depth as usize + 1];
        for id in 0..used.min(nodes as usize) {
            let node = &node_words[id * NODE_WORDS as usize..][..NODE_WORDS as usize];
            let count = links[2 * id + 1];
            if count > 0 {
                levels[(node[2] & 0xff) as usize].push(Refit {
                    id: id as u32,
                    key: node[1],
                    first: links[2 * id],
                    count,
                });
            }
        }
        let level_bindings = bind(&SHARED);
        for level in levels.iter().rev().filter(|l| !l.is_empty()) {
            let report = self.level.run_with(
                strategy,
                &Seeds::new().add(&self.level_refit, level),
                &level_bindings,
            )?;
            add(report.gpu_time);
            runs += 1;
        }
        let wall_time = start.elapsed();
        let (mismatches, summary) =
            compare(params, &read("nodes")?, &read("fires")?, &read("counters")?);
        Ok(TwoPassRun {
            mismatches,
            summary,
            runs,
            gpu_time,
            wall_time,
        })
    }
}

/// The words of `buffer`, read back.
fn read_words(gpu: &Gpu, buffer: &wgpu::Buffer) -> Result<Vec<u32>, Box<dyn Error>> {
    let bytes =
        scheduler::readback::read_buffer(&gpu.device, &gpu.queue, buffer, Duration::from_secs(60))?;
    Ok(bytes
        .chunks_exact(4)
        .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]))
        .collect())
}
