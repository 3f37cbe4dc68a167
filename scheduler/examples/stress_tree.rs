//! Stress test of the queue protocol: a binary tree of 2^20 items whose items
//! carry a checksum. Prints any item that arrives corrupted.
use scheduler::*;
#[scheduler::item]
struct Node {
    depth: u32,
    id: u32,
    check: u32,
    pad: u32,
}
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let gpu = Gpu::new(&Default::default())?;
    let mut g = Graph::new("tree");
    g.constant("DEPTH", 19u32);
    g.resource(Resource::storage::<[Atomic<u32>]>("log").min_len(65));
    let grow = g.procedure(Procedure::of::<Node>("Grow").initial(true).body("if (valid) {
    if (item.check != (item.id ^ (item.depth * 2654435761u) ^ 0xa5a5a5a5u)) {
        let n = atomicAdd(&log[0], 1u);
        if (n < 16u) { atomicStore(&log[1u + n * 4u], item.depth); atomicStore(&log[2u + n * 4u], item.id); atomicStore(&log[3u + n * 4u], item.check); atomicStore(&log[4u + n * 4u], item.pad); }
        return;
    }
    if (item.depth < DEPTH) {
        for (var c = 0u; c < 2u; c += 1u) {
            let id = 2u * item.id + c;
            let depth = item.depth + 1u;
            enqueue_Grow(Node(depth, id, id ^ (depth * 2654435761u) ^ 0xa5a5a5a5u, 7u));
        }
    }
}"));
    g.connect_with_fan_out(&grow, &grow, 2);
    let feats = if std::env::var("ATOMIC").is_ok() {
        wgpu::Features::empty()
    } else {
        recommended_features(&gpu.device)
    };
    let c = g.compile(&CompileOptions {
        features: feats,
        ..Default::default()
    })?;
    let root = Node {
        depth: 0,
        id: 1,
        check: 1 ^ 0xa5a5a5a5,
        pad: 7,
    };
    for run in 0..4 {
        let mut e = Executor::new(
            &gpu.device,
            &gpu.queue,
            &c,
            &ExecutorConfig {
                workgroups: Some(
                    std::env::var("WGS")
                        .map(|s| s.parse().unwrap())
                        .unwrap_or(2),
                ),
                iteration_budget: std::env::var("B").ok().map(|b| b.parse().unwrap()),
                capacities: Capacities::uniform(1 << 20),
                ..Default::default()
            },
        )?;
        e.create_buffer("log", 65)?;
        let r = e.run(&Seeds::new().add(&grow, &[root]), &[]);
        let l = e.read::<u32>("log")?;
        if l[0] > 0 || r.is_err() {
            println!(
                "run {run}: {} corrupted; first: {:x?}; {:?}",
                l[0],
                &l[1..1 + 4 * l[0].min(6) as usize],
                r.map(|r| r.total_executed()).map_err(|e| e.to_string())
            );
        }
    }
    Ok(())
}
