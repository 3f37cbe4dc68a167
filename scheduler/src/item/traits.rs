//! The [`Item`] trait: a Rust struct that states its WGSL twin itself.

use super::WgslType;

/// A Rust struct that is also a WGSL struct: the payload of a procedure, or
/// any struct shared with WGSL (a uniform, a storage element).
///
/// Derive it, and state each item type once:
///
/// ```
/// #[scheduler::item]
/// struct Hop {
///     node: u32,
///     level: u32,
/// }
///
/// use scheduler::Item;
/// assert_eq!(Hop::wgsl_struct(), "struct Hop { node: u32, level: u32 }");
/// ```
///
/// `#[scheduler::item]` adds `#[repr(C)]` and derives `Clone`, `Copy`,
/// `bytemuck::Pod`, `bytemuck::Zeroable` (through [`scheduler::bytemuck`](crate::bytemuck),
/// so your crate needs no `bytemuck` dependency) and `Item`, skipping any the
/// struct already derives. A struct that derives `Pod` itself can derive
/// `Item` alone:
///
/// ```
/// #[repr(C)]
/// #[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable, scheduler::Item)]
/// struct Sample {
///     position: glam::Vec4,
///     weights: [f32; 3],
///     id: u32,
/// }
///
/// use scheduler::Item;
/// assert_eq!(
///     Sample::wgsl_struct(),
///     "struct Sample { position: vec4<f32>, weights: array<f32, 3>, id: u32 }"
/// );
/// ```
///
/// # Field types and layout
///
/// Fields are `u32`, `i32`, `f32`, fixed arrays `[T; N]`, glam's `Vec2`,
/// `Vec3`, `Vec4`, `UVec2`, `UVec3`, `UVec4`, `IVec2`, `IVec3`, `IVec4`,
/// `Mat2` and `Mat4`, and other
/// structs that derive `Item` (declared once in the generated module, before
/// the structs that use them). Every [`WgslType`] is accepted.
///
/// WGSL aligns some types more than Rust does (`vec4<u32>` to 16 bytes where
/// `UVec4` is 4-byte aligned, `vec2<f32>` to 8), and rounds a struct's size up
/// to its largest alignment. Where WGSL would insert padding that Rust does
/// not, **the crate does not compile**: the derive asserts that every field
/// has the same offset and size in both, and so does the struct. Write the
/// padding as fields (`_pad: [u32; 3]`), as in WGSL itself:
///
/// ```compile_fail,E0080
/// #[scheduler::item]
/// struct Misaligned {
///     id: u32,
///     // WGSL puts this at byte 16, Rust at byte 4: rejected.
///     position: scheduler::glam::UVec4,
/// }
/// ```
///
/// The same holds for the end of the struct: a `vec4<u32>` makes WGSL round
/// the size up to a multiple of 16, which Rust does not do for the 4-byte
/// aligned `UVec4`, so 12 bytes of padding are missing here:
///
/// ```compile_fail,E0080
/// #[scheduler::item]
/// struct Unpadded {
///     position: scheduler::glam::UVec4,
///     id: u32,
/// }
/// ```
///
/// A glam 3-vector is 12 bytes in both, but WGSL aligns `vec3` to 16 bytes:
/// it is accepted where WGSL would place it too (at a multiple of 16, as in
/// `eye: Vec3, threshold: f32`), and an array of them is rejected (WGSL
/// strides `vec3` by 16 bytes).
///
/// `bool` (not host-shareable), `Vec3A` and the 3x3 matrices (16-byte
/// columns in WGSL), 64-bit and 8/16-bit types are rejected with a message
/// saying what to use instead:
///
/// ```compile_fail
/// #[scheduler::item]
/// struct Flagged {
///     flag: bool,
/// }
/// ```
///
/// The struct must be `#[repr(C)]`, not generic, and have named fields;
/// its WGSL name is its Rust name unless `#[wgsl(name = "Other")]` says
/// otherwise. A long struct is declared one field per line, each under its
/// `///` documentation as WGSL comments. When a graph compiles, naga's
/// layouter checks the generated struct against the Rust layout once more.
///
/// ```
/// #[scheduler::item]
/// #[wgsl(name = "Camera")]
/// struct CameraUniform {
///     eye: scheduler::glam::Vec3,
///     near: f32,
/// }
///
/// use scheduler::Item;
/// assert_eq!(CameraUniform::wgsl_struct(), "struct Camera { eye: vec3<f32>, near: f32 }");
/// ```
///
/// A 3-vector where WGSL would move it is rejected like any other field:
///
/// ```compile_fail,E0080
/// #[scheduler::item]
/// struct Shifted {
///     near: f32,
///     // WGSL puts this at byte 16, Rust at byte 4.
///     eye: scheduler::glam::Vec3,
/// }
/// ```
///
/// The derive lays structs out by the storage rules; a struct used as a
/// `var<uniform>` must also meet the uniform rules (array strides of 16
/// bytes), which naga checks when the module is validated.
#[diagnostic::on_unimplemented(
    message = "`{Self}` is not an item type",
    note = "derive it: `#[scheduler::item]` on the struct, or `#[derive(scheduler::Item)]` next to `bytemuck::Pod`"
)]
pub trait Item: bytemuck::Pod + WgslType {
    /// The WGSL struct name (the Rust name).
    const WGSL_NAME: &'static str;

    /// The WGSL declaration of this struct alone, e.g.
    /// `struct Node { depth: u32, id: u32 }`.
    fn wgsl_struct() -> String;

    /// The Rust byte offset of every field, in declaration order.
    fn rust_fields() -> Vec<(&'static str, usize)>;

    /// The declarations of this struct and of every struct it nests,
    /// dependencies first, each once: what a graph library needs to use it.
    fn wgsl_declarations() -> String {
        let mut structs = super::WgslStructs::default();
        Self::wgsl_structs(&mut structs);
        structs
            .entries()
            .iter()
            .map(|(_, source)| source.as_str())
            .collect::<Vec<_>>()
            .join("\n")
    }
}
