//! A hierarchical sum over a tree that the same run builds top-down and
//! sums bottom-up with joins ([`scheduler::Graph::join`]): `Split` visits a
//! node, gives it ids for its children and opens a join whose record,
//! a [`Refit`], names the node and its children; the children are `Split`s
//! again. Once every descendant has finished, `Refit` adds the node's value
//! to its children's sums. The sums flow up through the `nodes` resource,
//! indexed by node id.
//!
//! The tree's shape is random but fixed by its parameters: a node's
//! children depend only on its key (a hash of the path from the root), its
//! depth and its distance from the spine, so the CPU builds the same tree
//! ([`cpu_reference`]). A spine runs from the root to the deepest level
//! with 1 to `fan` children per node; its other children start bushes that
//! end [`BUSH_LEVELS`] levels below the spine, with 0 to `fan` children per
//! node. Node ids come from an atomic counter, so they differ from run to
//! run; the check compares every node's sum with the CPU's sum of the
//! subtree its key, depth and level describe. Sums are wrapping `u32`s, so
//! they do not depend on the order of the additions.

mod cpu;
mod run;
mod two_pass;
mod wgsl;

pub use two_pass::{TwoPass, TwoPassRun};
pub use wgsl::SPLIT_BODY;

pub use crate::Checked;
pub use cpu::Totals;
pub use cpu::{Shape, cpu_reference, subtree_sums};
pub use run::{
    NODE_WORDS, RESOURCES, TreeSumGraph, check, compare, executor, graph, options, prepare, run,
    seeds,
};

/// The most children a node has (the graph's fan-out of `Split`).
pub const MAX_FAN: u32 = 16;
/// Levels below the spine at which bushes end, unless the parameters say
/// otherwise ([`TreeParams::bush_levels`]).
pub const BUSH_LEVELS: u32 = 2;

/// A node to visit: its id (index into the resources), key, and shape:
/// its depth, and its level (0 on the spine, else levels below it) shifted
/// left by 8. Three words, so that in a graph with joins the join word
/// shares the item's packet (a fourth word would double the slot).
#[scheduler::item]
#[derive(Debug)]
#[expect(
    missing_docs,
    reason = "field docs would become WGSL comments in the generated module; the struct's doc describes the fields"
)]
pub struct Node {
    pub id: u32,
    pub key: u32,
    pub shape: u32,
}

/// A join's record: the node to sum, its key, and its children's ids
/// `first..first + count`.
#[scheduler::item]
#[derive(Debug)]
#[expect(
    missing_docs,
    reason = "field docs would become WGSL comments in the generated module; the struct's doc describes the fields"
)]
pub struct Refit {
    pub id: u32,
    pub key: u32,
    pub first: u32,
    pub count: u32,
}

/// The parameters of a tree: the spine's depth, the most children per node
/// (1 to [`MAX_FAN`]), the levels below the spine at which bushes end, and
/// the root's key.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TreeParams {
    /// Depth of the deepest leaves (the spine's length).
    pub depth: u32,
    /// The most children of a node.
    pub fan: u32,
    /// Levels below the spine at which bushes end ([`BUSH_LEVELS`] in the
    /// tests; more make a much larger tree).
    pub bush_levels: u32,
    /// The root's key.
    pub root_key: u32,
}

impl TreeParams {
    /// A tree with bushes of [`BUSH_LEVELS`] levels.
    pub fn new(depth: u32, fan: u32, root_key: u32) -> Self {
        Self {
            depth,
            fan,
            bush_levels: BUSH_LEVELS,
            root_key,
        }
    }

    /// As the `params` resource holds them: depth, fan, bush levels.
    pub fn words(&self) -> [u32; 3] {
        [self.depth, self.fan, self.bush_levels]
    }
}

/// The hash that shapes the tree (lowbias32), as the WGSL computes it.
pub fn hash(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// How many children a node has.
pub fn children(params: &TreeParams, key: u32, depth: u32, level: u32) -> u32 {
    if depth >= params.depth {
        return 0;
    }
    let h = hash(key);
    if level == 0 {
        1 + h % params.fan
    } else if level >= params.bush_levels {
        0
    } else {
        h % (params.fan + 1)
    }
}

/// The key of child `i` of the node with key `key`.
pub fn child_key(key: u32, i: u32) -> u32 {
    hash(key.wrapping_mul(31).wrapping_add(i + 1))
}

/// The level of child `i` of a node at `level`: the first child of a spine
/// node continues the spine.
pub fn child_level(level: u32, i: u32) -> u32 {
    if level == 0 && i == 0 { 0 } else { level + 1 }
}

/// A node's own value.
pub fn value(key: u32) -> u32 {
    hash(key ^ 0x5bd1_e995) % 1000
}
