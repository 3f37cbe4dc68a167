//! Item layouts: checks the Rust type against naga's layout of its WGSL struct
//! and generates the functions that move items between queues and values.
//!
//! Items travel as 32-bit words. Both codecs work on the workgroup's private
//! region of the staging buffer with plain loads and stores: decoding reads the
//! inbox the runtime copied the claimed items into, encoding writes the staging
//! area the runtime later publishes. Only the runtime touches the shared queues.

use naga::proc::Layouter;
use naga::{ArraySize, Handle, Module, ScalarKind, Type, TypeInner, VectorSize};

use crate::codegen::module::Function;
use crate::{CompileError, ItemType};

/// The checked layout of one item type and its codec functions.
#[derive(Clone, Debug)]
pub(crate) struct ItemLayout {
    pub words: u32,
    pub decode: Function,
    pub encode: Function,
}

/// Name of the function that reads an item of `item` from a queue slot.
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
            "Reads a `{}` from the inbox at word `base`.",
            item.wgsl_name
        ))
        .param("base", "u32")
        .returns(&item.wgsl_name);
    decode.line(format!("var value: {};", item.wgsl_name));
    let mut encode = Function::new(encode_name(&item.wgsl_name))
        .doc(format!(
            "Writes a `{}` into staging at word `base`.",
            item.wgsl_name
        ))
        .param("base", "u32")
        .param("item", &item.wgsl_name);
    encode.line("var value = item;");

    let mut emitter = Emitter {
        module,
        item,
        decode: &mut decode,
        encode: &mut encode,
    };
    for member in members {
        let name = member.name.clone().unwrap_or_default();
        let offset = Offset {
            words: member.offset / 4,
            terms: Vec::new(),
        };
        emitter.emit(member.ty, &format!(".{name}"), &offset, "", &name)?;
    }
    decode.line("return value;");
    Ok(ItemLayout {
        words: stride / 4,
        decode,
        encode,
    })
}

/// A word offset: a constant plus `loop variable * stride` terms.
#[derive(Clone)]
struct Offset {
    words: u32,
    terms: Vec<String>,
}

impl Offset {
    fn plus(&self, words: u32) -> Self {
        Self {
            words: self.words + words,
            terms: self.terms.clone(),
        }
    }

    fn render(&self) -> String {
        let mut out = format!("base + {}u", self.words);
        for term in &self.terms {
            out.push_str(" + ");
            out.push_str(term);
        }
        out
    }
}

struct Emitter<'a> {
    module: &'a Module,
    item: &'a ItemType,
    decode: &'a mut Function,
    encode: &'a mut Function,
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
        offset: &Offset,
        indent: &str,
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
        let word = offset.render();
        let read = format!("sched_staging[{word}]");
        self.decode.line(format!(
            "{indent}value{path} = {};",
            load.replace("{}", &read)
        ));
        self.encode
            .line(format!("{indent}sched_staging[{word}] = {store};"));
        Ok(())
    }

    fn emit(
        &mut self,
        ty: Handle<Type>,
        path: &str,
        offset: &Offset,
        indent: &str,
        field: &str,
    ) -> Result<(), CompileError> {
        match &self.module.types[ty].inner {
            TypeInner::Scalar(s) => self.leaf(s.kind, s.width, path, offset, indent, field),
            TypeInner::Vector { size, scalar } => {
                for (i, c) in ["x", "y", "z", "w"].iter().take(*size as usize).enumerate() {
                    self.leaf(
                        scalar.kind,
                        scalar.width,
                        &format!("{path}.{c}"),
                        &offset.plus(i as u32),
                        indent,
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
                            &offset.plus(c * column_words + r),
                            indent,
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
                    self.emit(
                        *base,
                        &format!("{path}[{i}]"),
                        &offset.plus(i * stride / 4),
                        indent,
                        field,
                    )?;
                }
                Ok(())
            }
            TypeInner::Struct { members, .. } => {
                for member in members {
                    let name = member.name.clone().unwrap_or_default();
                    self.emit(
                        member.ty,
                        &format!("{path}.{name}"),
                        &offset.plus(member.offset / 4),
                        indent,
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
