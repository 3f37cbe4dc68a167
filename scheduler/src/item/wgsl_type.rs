//! Rust types with a WGSL twin of known layout: the building blocks of a
//! derived [`Item`](crate::Item).

use crate::wgsl_layout::round_up;

/// A Rust type with a WGSL twin, and that twin's layout.
///
/// Implemented for `u32`, `i32`, `f32`, fixed arrays `[T; N]` of such types,
/// glam's `Vec2`, `Vec3`, `Vec4`, `UVec2`, `UVec3`, `UVec4`, `IVec2`,
/// `IVec3`, `IVec4`, `Mat2` and `Mat4` (feature `glam`, on by default), and every type that derives
/// [`Item`](crate::Item). The alignment and size are consts so that the
/// derive can compare them with Rust's layout at compile time; a wrong
/// manual implementation is caught again by the naga layout check when a
/// graph compiles.
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no WGSL twin that `#[derive(Item)]` knows",
    label = "not a WGSL-shareable field type",
    note = "fields may be u32, i32, f32, [T; N] of those, glam Vec2/Vec3/Vec4 (and their U/I forms), Mat2/Mat4, or structs that derive `Item`"
)]
pub trait WgslType {
    /// Alignment of the WGSL type in bytes (WGSL's `AlignOf`).
    const WGSL_ALIGN: usize;
    /// Size of the WGSL type in bytes (WGSL's `SizeOf`).
    const WGSL_SIZE: usize;

    /// The WGSL type, e.g. `vec4<f32>` or `array<u32, 3>`.
    fn wgsl_type() -> String;

    /// Adds the declarations of the structs this type needs, dependencies
    /// first; nothing for built-in types.
    fn wgsl_structs(_structs: &mut WgslStructs) {}
}

/// WGSL struct declarations in dependency order, each struct once.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct WgslStructs {
    entries: Vec<(&'static str, String)>,
}

impl WgslStructs {
    /// Adds the declaration of struct `name` unless it is already there.
    pub fn push(&mut self, name: &'static str, declaration: String) {
        if !self.entries.iter().any(|(n, _)| *n == name) {
            self.entries.push((name, declaration));
        }
    }

    /// The `(name, declaration)` pairs in the order they were added.
    pub fn entries(&self) -> &[(&'static str, String)] {
        &self.entries
    }

    pub(crate) fn into_entries(self) -> Vec<(&'static str, String)> {
        self.entries
    }
}

macro_rules! scalar {
    ($($rust:ty => $wgsl:literal),*) => {$(
        impl WgslType for $rust {
            const WGSL_ALIGN: usize = 4;
            const WGSL_SIZE: usize = 4;

            fn wgsl_type() -> String {
                $wgsl.to_owned()
            }
        }
    )*};
}

scalar!(u32 => "u32", i32 => "i32", f32 => "f32");

/// WGSL's `array<E, N>`: the element's alignment, and a stride of its size
/// rounded up to that alignment.
impl<T: WgslType, const N: usize> WgslType for [T; N] {
    const WGSL_ALIGN: usize = T::WGSL_ALIGN;
    const WGSL_SIZE: usize = N * round_up(T::WGSL_SIZE, T::WGSL_ALIGN);

    fn wgsl_type() -> String {
        format!("array<{}, {N}>", T::wgsl_type())
    }

    fn wgsl_structs(structs: &mut WgslStructs) {
        T::wgsl_structs(structs);
    }
}
