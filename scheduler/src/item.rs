//! Item types: the payload a procedure consumes, declared once in Rust and once
//! in WGSL. The compiler checks that both layouts agree (size and field offsets)
//! using naga's layouter, so a mismatch is a compile error, not corrupt data.

use std::any::type_name;

/// A `#[repr(C)]` [`bytemuck::Pod`] Rust type paired with its WGSL struct.
///
/// Build one with [`item_type!`](crate::item_type), which records the Rust field
/// offsets with `core::mem::offset_of!`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ItemType {
    pub(crate) wgsl_name: String,
    pub(crate) wgsl_source: String,
    pub(crate) rust_name: &'static str,
    pub(crate) rust_size: usize,
    pub(crate) rust_fields: Vec<(String, usize)>,
}

impl ItemType {
    /// Describes `T` as the WGSL struct `wgsl_name` declared in `wgsl_source`.
    ///
    /// `fields` lists every field of the WGSL struct with the byte offset of the
    /// Rust field of the same name. Prefer the [`item_type!`](crate::item_type) macro.
    pub fn new<T: bytemuck::Pod>(
        wgsl_name: impl Into<String>,
        wgsl_source: impl Into<String>,
        fields: &[(&str, usize)],
    ) -> Self {
        Self {
            wgsl_name: wgsl_name.into(),
            wgsl_source: wgsl_source.into(),
            rust_name: type_name::<T>(),
            rust_size: std::mem::size_of::<T>(),
            rust_fields: fields.iter().map(|(n, o)| ((*n).to_owned(), *o)).collect(),
        }
    }

    /// The WGSL struct name.
    pub fn wgsl_name(&self) -> &str {
        &self.wgsl_name
    }

    /// The size of the Rust type in bytes.
    pub fn size(&self) -> usize {
        self.rust_size
    }
}

/// Declares an [`ItemType`] for a Rust struct and its WGSL twin.
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
