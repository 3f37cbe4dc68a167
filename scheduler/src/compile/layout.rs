//! Item layouts: checks the Rust type against naga's layout of its WGSL struct
//! and generates the functions that move items between queues and values.
//!
//! Items travel as 32-bit words, moved in packets of four (`vec4<u32>`): a
//! slot is the item's words rounded up to whole packets. One vector access
//! costs llvmpipe one per-lane loop instead of four (it scalarizes every
//! storage access), and is one 16-byte access on a GPU. Decoding reads a
//! claimed item straight from its queue slot (through `sched_payload_load4`,
//! which is coherent); encoding writes the workgroup's private region of the
//! staging buffer, which the runtime later copies into the slots it reserved
//! and publishes.

use naga::proc::Layouter;
use naga::{ArraySize, Handle, Module, ScalarKind, Type, TypeInner, VectorSize};

use crate::codegen::module::Function;
use crate::{CompileError, ItemType};

/// The checked layout of one item type and its codec functions.
#[derive(Clone, Debug)]
pub(crate) struct ItemLayout {
    /// Words of the item itself (naga's array stride / 4).
    pub words: u32,
    /// Words of its slot: `words` rounded up to whole packets.
    pub slot_words: u32,
    pub decode: Function,
    pub encode: Function,
}

/// Name of the function that reads an item of `item` from its queue slot.
pub(crate) fn decode_name(item: &str) -> String {
    format!("sched_decode_{item}")
}

/// Name of the function that writes an item of `item` into staging.
pub(crate) fn encode_name(item: &str) -> String {
    format!("sched_encode_{item}")
}

pub(crate) fn analyze(
    item: &ItemType,
    module: &Module,
    layouter: &Layouter,
) -> Result<ItemLayout, CompileError> {
    let mismatch = |detail: String| CompileError::ItemLayoutMismatch {
        item: item.wgsl_name.clone(),
        rust: item.rust_name.to_owned(),
        detail,
    };
    let (handle, members) = module
        .types
        .iter()
        .find_map(|(handle, ty)| match &ty.inner {
            TypeInner::Struct { members, .. } if ty.name.as_deref() == Some(&item.wgsl_name) => {
                Some((handle, members))
            }
            _ => None,
        })
        .ok_or_else(|| {
            mismatch(format!(
                "its WGSL source declares no struct named `{}`",
                item.wgsl_name
            ))
        })?;

    let stride = layouter[handle].to_stride();
    if stride as usize != item.rust_size {
        return Err(mismatch(format!(
            "Rust size_of is {} bytes but the WGSL array stride is {stride} bytes",
            item.rust_size
        )));
    }
    for member in members {
        let name = member.name.clone().unwrap_or_default();
        match item.rust_fields.iter().find(|(n, _)| *n == name) {
            None => {
                return Err(mismatch(format!(
                    "WGSL field `{name}` has no Rust field listed"
                )));
            }
            Some((_, offset)) if *offset != member.offset as usize => {
                return Err(mismatch(format!(
                    "field `{name}` is at byte {offset} in Rust but at byte {} in WGSL",
                    member.offset
                )));
            }
            Some(_) => {}
        }
    }
    if let Some((name, _)) = item
        .rust_fields
        .iter()
        .find(|(n, _)| !members.iter().any(|m| m.name.as_deref() == Some(n)))
    {
        return Err(mismatch(format!(
            "Rust field `{name}` does not exist in the WGSL struct"
        )));
    }

    let mut decode = Function::new(decode_name(&item.wgsl_name))
        .doc(format!(
            "Reads a `{}` from the queue slot at word `base`.",
            item.wgsl_name
        ))
        .param("base", "u32")
        .returns(&item.wgsl_name);
    let mut encode = Function::new(encode_name(&item.wgsl_name))
        .doc(format!(
            "Writes a `{}` into staging at word `base`.",
            item.wgsl_name
        ))
        .param("base", "u32")
        .param("item", &item.wgsl_name);

    let mut emitter = Emitter {
        module,
        item,
        leaves: Vec::new(),
    };
    for member in members {
        let name = member.name.clone().unwrap_or_default();
        emitter.emit(member.ty, &format!(".{name}"), member.offset / 4, &name)?;
    }
    let words = stride / 4;
    let packets = words.div_ceil(PACKET_WORDS);
    // Decode: load every packet, then pick the fields out of them.
    for k in 0..packets {
        decode.line(format!(
            "let w{k} = sched_payload_load4(base + {}u);",
            k * PACKET_WORDS
        ));
    }
    decode.line(format!("var value: {};", item.wgsl_name));
    for leaf in &emitter.leaves {
        decode.line(format!(
            "value{} = {};",
            leaf.path,
            leaf.load.replace("{}", &packet_word(leaf.word))
        ));
    }
    decode.line("return value;");
    // Encode: fill zeroed packets field by field, then store them whole.
    encode.line("let value = item;");
    for k in 0..packets {
        encode.line(format!("var w{k} = vec4<u32>();"));
    }
    for leaf in &emitter.leaves {
        encode.line(format!("{} = {};", packet_word(leaf.word), leaf.store));
    }
    for k in 0..packets {
        encode.line(format!(
            "sched_staging_store4(base + {}u, w{k});",
            k * PACKET_WORDS
        ));
    }
    Ok(ItemLayout {
        words,
        slot_words: packets * PACKET_WORDS,
        decode,
        encode,
    })
}

/// Words per packet: items move as `vec4<u32>`.
pub(crate) const PACKET_WORDS: u32 = 4;

/// The packet component that holds word `word` of an item, e.g. `w1.z`.
fn packet_word(word: u32) -> String {
    let component = ["x", "y", "z", "w"][(word % PACKET_WORDS) as usize];
    format!("w{}.{component}", word / PACKET_WORDS)
}

/// One 32-bit field of an item: where it lives and how it converts.
struct Leaf {
    /// Path from the item, e.g. `.p[3].x`.
    path: String,
    /// Word offset in the item.
    word: u32,
    /// Expression that turns a `u32` (the `{}`) into the field's type.
    load: String,
    /// Expression that turns the field into a `u32`.
    store: String,
}

struct Emitter<'a> {
    module: &'a Module,
    item: &'a ItemType,
    leaves: Vec<Leaf>,
}

impl Emitter<'_> {
    fn unsupported(&self, field: &str, detail: &str) -> CompileError {
        CompileError::UnsupportedItemField {
            item: self.item.wgsl_name.clone(),
            field: field.to_owned(),
            detail: detail.to_owned(),
        }
    }

    fn leaf(
        &mut self,
        kind: ScalarKind,
        width: u8,
        path: &str,
        word: u32,
        field: &str,
    ) -> Result<(), CompileError> {
        if width != 4 {
            return Err(
                self.unsupported(field, "only 32-bit scalars (u32, i32, f32) can be queued")
            );
        }
        let (load, store) = match kind {
            ScalarKind::Uint => ("{}".to_owned(), format!("value{path}")),
            ScalarKind::Sint => (
                "bitcast<i32>({})".to_owned(),
                format!("bitcast<u32>(value{path})"),
            ),
            ScalarKind::Float => (
                "bitcast<f32>({})".to_owned(),
                format!("bitcast<u32>(value{path})"),
            ),
            _ => {
                return Err(
                    self.unsupported(field, "booleans and abstract types are not host-shareable")
                );
            }
        };
        self.leaves.push(Leaf {
            path: path.to_owned(),
            word,
            load,
            store,
        });
        Ok(())
    }

    fn emit(
        &mut self,
        ty: Handle<Type>,
        path: &str,
        word: u32,
        field: &str,
    ) -> Result<(), CompileError> {
        match &self.module.types[ty].inner {
            TypeInner::Scalar(s) => self.leaf(s.kind, s.width, path, word, field),
            TypeInner::Vector { size, scalar } => {
                for (i, c) in ["x", "y", "z", "w"].iter().take(*size as usize).enumerate() {
                    self.leaf(
                        scalar.kind,
                        scalar.width,
                        &format!("{path}.{c}"),
                        word + i as u32,
                        field,
                    )?;
                }
                Ok(())
            }
            TypeInner::Matrix {
                columns,
                rows,
                scalar,
            } => {
                let column_words = if *rows == VectorSize::Bi { 2 } else { 4 };
                for c in 0..*columns as u32 {
                    for r in 0..*rows as u32 {
                        self.leaf(
                            scalar.kind,
                            scalar.width,
                            &format!("{path}[{c}][{r}]"),
                            word + c * column_words + r,
                            field,
                        )?;
                    }
                }
                Ok(())
            }
            TypeInner::Array {
                base,
                size: ArraySize::Constant(count),
                stride,
            } => {
                // Written out element by element, not as a loop: llvmpipe's loop
                // limiter could cut a loop short (docs/scheduler.md, "Loop limits").
                for i in 0..count.get() {
                    self.emit(*base, &format!("{path}[{i}]"), word + i * stride / 4, field)?;
                }
                Ok(())
            }
            TypeInner::Struct { members, .. } => {
                for member in members {
                    let name = member.name.clone().unwrap_or_default();
                    self.emit(
                        member.ty,
                        &format!("{path}.{name}"),
                        word + member.offset / 4,
                        field,
                    )?;
                }
                Ok(())
            }
            _ => Err(self.unsupported(
                field,
                "atomics, runtime-sized arrays, pointers and textures cannot be queued",
            )),
        }
    }
}
