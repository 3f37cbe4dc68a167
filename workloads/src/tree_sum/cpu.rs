//! The CPU reference of the tree sum: the same tree, built and summed
//! recursively.

use std::collections::HashMap;

use super::{TreeParams, child_key, child_level, children, value};

/// What a node's subtree is determined by: its key, depth and level.
pub type Shape = (u32, u32, u32);

/// The tree's totals: nodes, inner nodes (joins), and the root's sum.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Totals {
    /// Every node.
    pub nodes: u64,
    /// Nodes with children: one join each.
    pub inner: u64,
    /// The root's subtree sum.
    pub root_sum: u32,
    /// The deepest level.
    pub depth: u32,
}

/// Every node's subtree sum by its [`Shape`], with the tree's totals.
pub fn subtree_sums(params: &TreeParams) -> (HashMap<Shape, u32>, Totals) {
    let mut sums = HashMap::new();
    let mut totals = Totals::default();
    // An explicit stack: the spine may be deep. (shape, children visited)
    let mut stack: Vec<(Shape, bool)> = vec![((params.root_key, 0, 0), false)];
    while let Some((shape, expanded)) = stack.pop() {
        let (key, depth, level) = shape;
        let n = children(params, key, depth, level);
        if !expanded {
            totals.nodes += 1;
            totals.depth = totals.depth.max(depth);
            if n > 0 {
                totals.inner += 1;
            }
            stack.push((shape, true));
            for i in 0..n {
                stack.push(((child_key(key, i), depth + 1, child_level(level, i)), false));
            }
            continue;
        }
        let mut total = value(key);
        for i in 0..n {
            total =
                total.wrapping_add(sums[&(child_key(key, i), depth + 1, child_level(level, i))]);
        }
        sums.insert(shape, total);
    }
    totals.root_sum = sums[&(params.root_key, 0, 0)];
    (sums, totals)
}

/// The tree's totals.
pub fn cpu_reference(params: &TreeParams) -> Totals {
    subtree_sums(params).1
}
