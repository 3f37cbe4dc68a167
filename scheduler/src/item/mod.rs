//! Item types: the payload a procedure consumes. Derive [`Item`] on the Rust
//! struct and its WGSL struct is generated from it, with the layouts checked
//! when the Rust crate compiles. A hand-written WGSL twin declared with
//! [`item_type!`](crate::item_type) stays possible. Either way the graph
//! compiler checks both layouts again with naga's layouter (size and field
//! offsets), so a mismatch is a compile error, not corrupt data.

#[cfg(feature = "glam")]
mod glam;
pub mod layout;
mod traits;
mod wgsl_type;

use std::any::type_name;
use std::collections::BTreeMap;

use crate::CompileError;

pub use traits::Item;
pub use wgsl_type::{WgslStructs, WgslType};

/// A `#[repr(C)]` [`bytemuck::Pod`] Rust type paired with its WGSL struct.
///
/// Get one with [`ItemType::of`] for a type that derives [`Item`], or with
/// [`item_type!`](crate::item_type) for a hand-written WGSL twin.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ItemType {
    pub(crate) wgsl_name: String,
    /// Every struct declaration of `wgsl_source` that can be emitted on its
    /// own, by name, dependencies first: a nested item shared by two item
    /// types is declared once in the generated module.
    pub(crate) structs: Vec<(String, String)>,
    pub(crate) wgsl_source: String,
    pub(crate) rust_name: &'static str,
    pub(crate) rust_size: usize,
    pub(crate) rust_fields: Vec<(String, usize)>,
}

impl ItemType {
    /// Describes `T` as the WGSL struct `wgsl_name` declared in `wgsl_source`.
    ///
    /// `fields` lists every field of the WGSL struct with the byte offset of the
    /// Rust field of the same name. Prefer [`ItemType::of`] with a derived
    /// [`Item`], or the [`item_type!`](crate::item_type) macro.
    pub fn new<T: bytemuck::Pod>(
        wgsl_name: impl Into<String>,
        wgsl_source: impl Into<String>,
        fields: &[(&str, usize)],
    ) -> Self {
        let (wgsl_name, wgsl_source) = (wgsl_name.into(), wgsl_source.into());
        Self {
            structs: vec![(wgsl_name.clone(), wgsl_source.clone())],
            wgsl_name,
            wgsl_source,
            rust_name: type_name::<T>(),
            rust_size: std::mem::size_of::<T>(),
            rust_fields: fields.iter().map(|(n, o)| ((*n).to_owned(), *o)).collect(),
        }
    }

    /// The item type of `T`, with the WGSL structs its derive generated.
    ///
    /// ```
    /// #[scheduler::item]
    /// struct Node { depth: u32, id: u32 }
    ///
    /// let node = scheduler::ItemType::of::<Node>();
    /// assert_eq!(node.wgsl_name(), "Node");
    /// assert_eq!(node.wgsl_source(), "struct Node { depth: u32, id: u32 }");
    /// ```
    pub fn of<T: Item>() -> Self {
        let mut structs = WgslStructs::default();
        T::wgsl_structs(&mut structs);
        let structs: Vec<(String, String)> = structs
            .into_entries()
            .into_iter()
            .map(|(name, source)| (name.to_owned(), source))
            .collect();
        Self {
            wgsl_name: T::WGSL_NAME.to_owned(),
            wgsl_source: structs
                .iter()
                .map(|(_, source)| source.as_str())
                .collect::<Vec<_>>()
                .join("\n"),
            structs,
            rust_name: type_name::<T>(),
            rust_size: std::mem::size_of::<T>(),
            rust_fields: T::rust_fields()
                .into_iter()
                .map(|(name, offset)| (name.to_owned(), offset))
                .collect(),
        }
    }

    /// The WGSL struct name.
    pub fn wgsl_name(&self) -> &str {
        &self.wgsl_name
    }

    /// The WGSL declarations: the item's struct and the structs it nests.
    pub fn wgsl_source(&self) -> &str {
        &self.wgsl_source
    }

    /// The size of the Rust type in bytes.
    pub fn size(&self) -> usize {
        self.rust_size
    }
}

/// The item structs already written into a generated module, so that a
/// struct nested in several item types is declared once.
#[derive(Debug, Default)]
pub(crate) struct Declared {
    structs: BTreeMap<String, String>,
}

impl Declared {
    /// The declarations of `item` not written yet (item types come in sorted
    /// order, so this is deterministic). Two different declarations under
    /// one name are an error: one of them would be silently dropped.
    pub(crate) fn fresh(&mut self, item: &ItemType) -> Result<String, CompileError> {
        let text = self.fresh_structs(&item.structs).map_err(|name| {
            CompileError::ItemLayoutMismatch {
                item: item.wgsl_name.clone(),
                rust: item.rust_name.to_owned(),
                detail: format!(
                    "it declares a WGSL struct `{name}` that another item type declares differently"
                ),
            }
        })?;
        if text.is_empty() {
            return Ok(format!(
                "// `{}` is declared above, nested in another item type.",
                item.wgsl_name
            ));
        }
        Ok(text)
    }

    /// The declarations of `structs` not written yet, joined by newlines, or
    /// the name of a struct declared differently before.
    pub(crate) fn fresh_structs(&mut self, structs: &[(String, String)]) -> Result<String, String> {
        let mut text = Vec::new();
        for (name, source) in structs {
            match self.structs.get(name) {
                Some(existing) if existing == source => {}
                Some(_) => return Err(name.clone()),
                None => {
                    self.structs.insert(name.clone(), source.clone());
                    text.push(source.as_str());
                }
            }
        }
        Ok(text.join("\n"))
    }
}

/// Declares an [`ItemType`] for a Rust struct and a hand-written WGSL twin.
///
/// Prefer deriving [`Item`], which writes the twin for you; this macro stays
/// for WGSL that a derive cannot express. The naga layout check still
/// compares the two when the graph compiles.
///
/// ```
/// use scheduler::item_type;
/// #[repr(C)]
/// #[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
/// struct Node { id: u32, depth: u32, value: f32, _pad: u32 }
///
/// let item = item_type!(Node, "struct Node { id: u32, depth: u32, value: f32, _pad: u32 }",
///                       [id, depth, value, _pad]);
/// assert_eq!(item.size(), 16);
/// ```
///
/// The WGSL struct must carry the same name as the Rust type.
#[macro_export]
macro_rules! item_type {
    ($ty:ident, $wgsl:expr, [$($field:ident),* $(,)?]) => {
        $crate::ItemType::new::<$ty>(
            stringify!($ty),
            $wgsl,
            &[$((stringify!($field), ::core::mem::offset_of!($ty, $field))),*],
        )
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[crate::item]
    struct Inner {
        value: f32,
    }

    #[crate::item]
    struct Outer {
        inner: [Inner; 2],
        count: u32,
    }

    #[test]
    fn nested_structs_are_declared_once_dependencies_first() {
        let outer = ItemType::of::<Outer>();
        assert_eq!(
            outer.structs,
            [
                ("Inner".to_owned(), "struct Inner { value: f32 }".to_owned()),
                (
                    "Outer".to_owned(),
                    "struct Outer { inner: array<Inner, 2>, count: u32 }".to_owned()
                ),
            ]
        );
        let mut declared = Declared::default();
        assert_eq!(declared.fresh(&outer).unwrap(), outer.wgsl_source);
        // `Inner` is already there when its own item type comes.
        let inner = declared.fresh(&ItemType::of::<Inner>()).unwrap();
        assert!(inner.starts_with("// `Inner` is declared above"), "{inner}");
    }

    #[test]
    fn rust_offsets_are_recorded_for_the_naga_check() {
        let outer = ItemType::of::<Outer>();
        assert_eq!(
            outer.rust_fields,
            [("inner".to_owned(), 0), ("count".to_owned(), 8)]
        );
        assert_eq!(outer.size(), 12);
    }
}
