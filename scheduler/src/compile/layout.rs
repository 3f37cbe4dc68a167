//! Item layouts: checks the Rust type against naga's layout of its WGSL struct
//! and finds the 32-bit fields the item travels as (see `plan::layout`).

use naga::proc::Layouter;
use naga::{ArraySize, Handle, Module, ScalarKind, Type, TypeInner, VectorSize};

use crate::plan::layout::{ItemLayout, Leaf, WordKind};
use crate::{CompileError, ItemType};

/// Checks `item` against its parsed WGSL struct and returns its layout.
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

    let mut walker = FieldWalker {
        module,
        item,
        leaves: Vec::new(),
    };
    for member in members {
        let name = member.name.clone().unwrap_or_default();
        walker.walk(member.ty, &format!(".{name}"), member.offset / 4, &name)?;
    }
    Ok(ItemLayout::new(stride / 4, walker.leaves))
}

/// Walks an item's struct down to its 32-bit scalars, in declaration order.
struct FieldWalker<'a> {
    module: &'a Module,
    item: &'a ItemType,
    leaves: Vec<Leaf>,
}

impl FieldWalker<'_> {
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
        let kind = match kind {
            ScalarKind::Uint => WordKind::Uint,
            ScalarKind::Sint => WordKind::Sint,
            ScalarKind::Float => WordKind::Float,
            _ => {
                return Err(
                    self.unsupported(field, "booleans and abstract types are not host-shareable")
                );
            }
        };
        self.leaves.push(Leaf {
            path: path.to_owned(),
            word,
            kind,
        });
        Ok(())
    }

    fn walk(
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
                    self.walk(*base, &format!("{path}[{i}]"), word + i * stride / 4, field)?;
                }
                Ok(())
            }
            TypeInner::Struct { members, .. } => {
                for member in members {
                    let name = member.name.clone().unwrap_or_default();
                    self.walk(
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
