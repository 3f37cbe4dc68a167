//! Item layouts as data: where each 32-bit field of an item lies among the
//! words it travels as, and the struct declarations typed scratch and typed
//! resources add. `compile::layout` derives them from naga's layout of the
//! item's struct; `codegen::codec` turns them into the codec functions.
//!
//! Items travel as 32-bit words, moved in packets of four (`vec4<u32>`): a
//! slot is the item's words rounded up to whole packets. One vector access
//! costs llvmpipe one per-lane loop instead of four (it scalarizes every
//! storage access), and is one 16-byte access on a GPU.

/// Words per packet: items move as `vec4<u32>`.
pub(crate) const PACKET_WORDS: u32 = 4;

/// How a 32-bit field converts to and from the `u32` word it travels as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum WordKind {
    /// A `u32`: the word itself.
    Uint,
    /// An `i32`: bit-cast.
    Sint,
    /// An `f32`: bit-cast.
    Float,
}

/// One 32-bit field of an item: where it lives and how it converts.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Leaf {
    /// Path from the item, e.g. `.p[3].x`.
    pub path: String,
    /// Word offset in the item.
    pub word: u32,
    /// Its scalar type.
    pub kind: WordKind,
}

/// The checked layout of one item type.
#[derive(Clone, Debug)]
pub(crate) struct ItemLayout {
    /// Words of the item itself (naga's array stride / 4).
    pub words: u32,
    /// Words of its slot: `words` rounded up to whole packets.
    pub slot_words: u32,
    /// Every 32-bit field, in declaration order.
    pub leaves: Vec<Leaf>,
}

impl ItemLayout {
    /// The layout of an item of `words` words with these fields.
    pub(crate) fn new(words: u32, leaves: Vec<Leaf>) -> Self {
        Self {
            words,
            slot_words: words.div_ceil(PACKET_WORDS) * PACKET_WORDS,
            leaves,
        }
    }

    /// Packets of one slot.
    pub(crate) fn packets(&self) -> u32 {
        self.slot_words / PACKET_WORDS
    }
}

/// Struct declarations a typed scratch or a typed resource needs and no item
/// type declares.
#[derive(Debug)]
pub(crate) struct ExtraStructs {
    /// The section title in the generated module.
    pub(crate) title: String,
    /// The procedure or resource that needs them (for error locations).
    pub(crate) origin: String,
    /// The declarations.
    pub(crate) text: String,
}
