//! Breadth-first search levels as a scheduler workload with two procedures:
//!
//! * `Visit` (one thread per item) claims a node for a level with `atomicMin`
//!   and, if that improved the node's level, enqueues one `Expand`;
//! * `Expand` (four threads per item, splitting the adjacency list) enqueues a
//!   `Visit` for every neighbour whose level would improve.
//!
//! Nothing orders the levels, so a node can be visited first at a level that
//! is too high and improved later; the final levels are still the exact BFS
//! distances (argued at the body of `Expand`, in this module's `graph.rs`)
//! and are compared with a CPU BFS element for element. The scheduler's own
//! counters are checked against counters the bodies keep: every improving
//! visit enqueues exactly one `Expand`, and `Visit` receives exactly the
//! enqueues `Expand` made.
//!
//! The parts live in their own files: the problem and the CPU reference
//! here, the graph ([`graph`]) and a checked GPU run ([`run`]) beside it. The
//! example `scheduler/examples/bfs.rs` runs it from the command line.

mod graph;
mod run;

use std::collections::VecDeque;

use rand::{Rng, SeedableRng, rngs::StdRng};

pub use crate::Checked;
pub use graph::{BfsGraph, capacities, graph};
pub use run::run;

/// Level of a node no source reaches.
pub const UNREACHED: u32 = u32::MAX;
/// Threads that share one node's adjacency list in `Expand`.
pub const EXPAND_THREADS: u32 = 4;
/// Counter words the bodies keep (see [`Counters`]).
const COUNTER_WORDS: usize = 3;

/// A node with the level it is reached at; the item of both procedures.
#[scheduler::item]
#[derive(Debug)]
#[expect(
    missing_docs,
    reason = "field docs would become WGSL comments in the generated module; the struct\'s doc describes the fields"
)]
pub struct Hop {
    pub node: u32,
    pub level: u32,
}

/// An undirected graph in compressed sparse row form.
#[derive(Clone, Debug)]
pub struct Csr {
    /// `adjacency[row_start[v]..row_start[v + 1]]` are the neighbours of v.
    pub row_start: Vec<u32>,
    /// Every node's neighbours, row after row.
    pub adjacency: Vec<u32>,
}

impl Csr {
    /// A random multigraph on `nodes` nodes with `nodes * degree / 2`
    /// undirected edges between uniformly drawn distinct endpoints (average
    /// degree `degree`; duplicate edges are kept, they are harmless).
    pub fn random(seed: u64, nodes: u32, degree: u32) -> Self {
        assert!(nodes >= 2);
        let mut rng = StdRng::seed_from_u64(seed);
        let edges = nodes as usize * degree as usize / 2;
        let mut pairs = Vec::with_capacity(edges);
        while pairs.len() < edges {
            let (u, v) = (rng.random_range(0..nodes), rng.random_range(0..nodes));
            if u != v {
                pairs.push((u, v));
            }
        }
        let mut lists = vec![Vec::new(); nodes as usize];
        for &(u, v) in &pairs {
            lists[u as usize].push(v);
            lists[v as usize].push(u);
        }
        let mut row_start = Vec::with_capacity(nodes as usize + 1);
        let mut adjacency = Vec::with_capacity(2 * edges);
        row_start.push(0);
        for list in &lists {
            adjacency.extend_from_slice(list);
            row_start.push(adjacency.len() as u32);
        }
        Self {
            row_start,
            adjacency,
        }
    }

    /// Nodes in the graph.
    pub fn nodes(&self) -> u32 {
        self.row_start.len() as u32 - 1
    }

    /// The neighbours of node `v` (with repeats for duplicate edges).
    pub fn neighbours(&self, v: u32) -> &[u32] {
        &self.adjacency
            [self.row_start[v as usize] as usize..self.row_start[v as usize + 1] as usize]
    }

    /// The largest number of neighbours of any node.
    pub fn max_degree(&self) -> u32 {
        (0..self.nodes())
            .map(|v| self.neighbours(v).len() as u32)
            .max()
            .unwrap_or(0)
    }
}

/// One BFS problem: a graph and its sources (level 0).
#[derive(Clone, Debug)]
pub struct Problem {
    /// The graph searched.
    pub graph: Csr,
    /// The nodes at level 0 (repeats allowed).
    pub sources: Vec<u32>,
}

impl Problem {
    /// A random graph of average degree 4 with `sources` random sources.
    pub fn random(seed: u64, nodes: u32, sources: usize) -> Self {
        let graph = Csr::random(seed, nodes, 4);
        let mut rng = StdRng::seed_from_u64(seed ^ 0x5eed);
        let sources = (0..sources).map(|_| rng.random_range(0..nodes)).collect();
        Self { graph, sources }
    }
}

/// The CPU reference: multi-source BFS.
pub fn cpu_levels(problem: &Problem) -> Vec<u32> {
    let mut levels = vec![UNREACHED; problem.graph.nodes() as usize];
    let mut frontier = VecDeque::new();
    for &s in &problem.sources {
        if levels[s as usize] != 0 {
            levels[s as usize] = 0;
            frontier.push_back(s);
        }
    }
    while let Some(u) = frontier.pop_front() {
        let next = levels[u as usize] + 1;
        for &v in problem.graph.neighbours(u) {
            if levels[v as usize] == UNREACHED {
                levels[v as usize] = next;
                frontier.push_back(v);
            }
        }
    }
    levels
}

/// Counters the bodies keep, read back after the run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Visits whose `atomicMin` lowered the node's level (each enqueued an `Expand`).
    pub improving_visits: u32,
    /// `Visit`s that `Expand` enqueued.
    pub visit_enqueues: u32,
    /// `Expand`s that found their level already beaten and did nothing.
    pub stale_expands: u32,
}
