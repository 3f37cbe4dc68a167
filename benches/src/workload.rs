//! The synthetic spawn-tree workload: its item type, the WGSL shared by both
//! variants and the CPU reference.
//!
//! **Tree shape.** Ids are numbered like a binary heap: the single root has
//! id 0 and item `i` spawns `2i+1` and `2i+2` when they are below
//! `N = 2^items_log2`. Every id in `0..N` therefore runs exactly once, which
//! makes the item count exactly `N` (a complete tree of depth `items_log2 - 1`
//! plus one item at depth `items_log2`) without a second root. Depths are
//! carried in the item for realism; the work does not depend on them.

/// Hash rounds per item in the "fixed work" variant.
pub const FIXED_WORK: u32 = 64;

/// Largest supported `items_log2`: the flat dispatch launches `N / 256`
/// workgroups in one dimension, which must stay below 65 536.
pub const MAX_ITEMS_LOG2: u32 = 23;

/// Threads per workgroup of the flat kernel (fixed in `flat.wgsl`).
pub const FLAT_WORKGROUP_SIZE: u32 = 256;

/// The shared per-item work (WGSL).
pub const HASH_WGSL: &str = include_str!("../../shaders/benches/hash.wgsl");
/// One spawn-tree item: 8 words, 32 bytes.
#[scheduler::item]
#[derive(Debug, Default, PartialEq, Eq)]
pub struct SpawnItem {
    /// Heap id, also the index written in `out`.
    pub id: u32,
    /// Depth in the tree (root 0).
    pub depth: u32,
    /// The parent's id (the root's is `u32::MAX`).
    pub parent: u32,
    /// Padding up to 32 bytes.
    pub pad0: u32,
    /// Padding.
    pub pad1: u32,
    /// Padding.
    pub pad2: u32,
    /// Padding.
    pub pad3: u32,
    /// Padding.
    pub pad4: u32,
}

const _: () = assert!(std::mem::size_of::<SpawnItem>() == 32);

impl SpawnItem {
    /// The root item, id 0.
    pub fn root() -> Self {
        Self {
            parent: u32::MAX,
            ..Self::default()
        }
    }
}

/// One workload: how many items and how much work each does.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Workload {
    /// `log2` of the item count.
    pub items_log2: u32,
    /// Hash rounds per item ([`FIXED_WORK`] or 0).
    pub work: u32,
}

impl Workload {
    /// A workload, checking the size against [`MAX_ITEMS_LOG2`].
    pub fn new(items_log2: u32, work: u32) -> Result<Self, crate::BenchError> {
        if items_log2 > MAX_ITEMS_LOG2 {
            return Err(crate::BenchError::Config(format!(
                "items_log2 {items_log2} exceeds {MAX_ITEMS_LOG2} (the flat dispatch's grid limit)"
            )));
        }
        Ok(Self { items_log2, work })
    }

    /// Number of items, `2^items_log2`.
    pub fn items(&self) -> u32 {
        1 << self.items_log2
    }

    /// The constants `hash.wgsl` and the bodies use, in both variants.
    pub fn constants(&self) -> [(&'static str, u32); 2] {
        [("BENCH_WORK", self.work), ("BENCH_ITEMS", self.items())]
    }

    /// [`Workload::constants`] as WGSL, for the flat kernel's module (the
    /// megakernel declares them with `Graph::constant`).
    pub fn wgsl_constants(&self) -> String {
        self.constants()
            .iter()
            .map(|(name, value)| format!("const {name}: u32 = {value}u;\n"))
            .collect()
    }

    /// The CPU reference of `out`.
    pub fn reference(&self) -> Vec<u32> {
        (0..self.items()).map(|id| work(id, self.work)).collect()
    }
}

/// One round of the hash in `hash.wgsl` ("lowbias32").
pub fn hash(v: u32) -> u32 {
    let mut x = v;
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// `rounds` dependent hash rounds starting from `id`, as `bench_work` in WGSL.
pub fn work(id: u32, rounds: u32) -> u32 {
    (0..rounds).fold(id, |h, _| hash(h))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_work_is_the_identity() {
        assert_eq!(work(12345, 0), 12345);
    }

    #[test]
    fn rounds_compose() {
        assert_eq!(work(7, 3), hash(hash(hash(7))));
        assert_eq!(hash(0), 0);
        assert_ne!(hash(1), 1);
    }

    #[test]
    fn heap_numbering_covers_every_id_once() {
        let n = 1u32 << 10;
        let mut seen = vec![0u32; n as usize];
        let mut stack = vec![0u32];
        while let Some(i) = stack.pop() {
            seen[i as usize] += 1;
            for child in [2 * i + 1, 2 * i + 2] {
                if child < n {
                    stack.push(child);
                }
            }
        }
        assert!(seen.iter().all(|&c| c == 1));
    }
}
