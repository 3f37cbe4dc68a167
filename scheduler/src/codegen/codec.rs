//! The item codecs: the functions that move items between queue slots,
//! staging and values, written from an item's [`ItemLayout`]. Decoding reads
//! a claimed item straight from its queue slot (through
//! `sched_payload_load4`, which is coherent); encoding writes the
//! workgroup's private region of the staging buffer, which the runtime later
//! copies into the slots it reserved and publishes.

use crate::codegen::module::Function;
use crate::naming::{decode_name, encode_name};
use crate::plan::layout::{ItemLayout, Leaf, PACKET_WORDS, WordKind};

/// The packet component that holds word `word` of an item, e.g. `w1.z`.
fn packet_word(word: u32) -> String {
    let component = ["x", "y", "z", "w"][(word % PACKET_WORDS) as usize];
    format!("w{}.{component}", word / PACKET_WORDS)
}

/// The expression that turns the leaf's packet word into the field's type.
fn load(leaf: &Leaf) -> String {
    let word = packet_word(leaf.word);
    match leaf.kind {
        WordKind::Uint => word,
        WordKind::Sint => format!("bitcast<i32>({word})"),
        WordKind::Float => format!("bitcast<f32>({word})"),
    }
}

/// The expression that turns the field into a `u32`.
fn store(leaf: &Leaf) -> String {
    match leaf.kind {
        WordKind::Uint => format!("value{}", leaf.path),
        WordKind::Sint | WordKind::Float => format!("bitcast<u32>(value{})", leaf.path),
    }
}

/// The function that reads an `item` from its queue slot: load every packet,
/// then pick the fields out of them.
pub(crate) fn decode_function(item: &str, layout: &ItemLayout) -> Function {
    let mut decode = Function::new(decode_name(item))
        .doc(format!(
            "Reads a `{item}` from the queue slot at word `base`."
        ))
        .param("base", "u32")
        .returns(item);
    for k in 0..layout.packets() {
        decode.line(format!(
            "let w{k} = sched_payload_load4(base + {}u);",
            k * PACKET_WORDS
        ));
    }
    decode.line(format!("var value: {item};"));
    for leaf in &layout.leaves {
        decode.line(format!("value{} = {};", leaf.path, load(leaf)));
    }
    decode.line("return value;");
    decode
}

/// The function that writes an `item` into staging: fill zeroed packets field
/// by field, then store them whole.
pub(crate) fn encode_function(item: &str, layout: &ItemLayout) -> Function {
    let mut encode = Function::new(encode_name(item))
        .doc(format!("Writes a `{item}` into staging at word `base`."))
        .param("base", "u32")
        .param("item", item);
    encode.line("let value = item;");
    for k in 0..layout.packets() {
        encode.line(format!("var w{k} = vec4<u32>();"));
    }
    for leaf in &layout.leaves {
        encode.line(format!("{} = {};", packet_word(leaf.word), store(leaf)));
    }
    for k in 0..layout.packets() {
        encode.line(format!(
            "sched_staging_store4(base + {}u, w{k});",
            k * PACKET_WORDS
        ));
    }
    encode
}

/// The function that writes an `item` into the words of a join record from
/// control word `at` (joins only): every field's word, by relaxed atomic
/// stores (the control words are atomics). The words of the padding are
/// left as they are; they are copied but never read.
pub(crate) fn join_store_function(item: &str, layout: &ItemLayout) -> Function {
    let mut f = Function::new(crate::naming::join_store_name(item))
        .doc(format!(
            "Writes a `{item}` into the join record words from control word `at`."
        ))
        .param("at", "u32")
        .param("item", item);
    f.line("let value = item;");
    for leaf in &layout.leaves {
        f.line(format!(
            "atomicStore(&sched_control[at + {}u], {});",
            leaf.word,
            store(leaf)
        ));
    }
    f
}
