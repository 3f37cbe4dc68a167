//! glam's vectors and matrices whose size matches their WGSL twin. Their Rust
//! alignment may be smaller (`UVec4` is 4-byte aligned, `vec4<u32>` 16): the
//! derive's offset assertions reject a field that would land elsewhere.
//! glam's 3-vectors and 3x3 matrices have no twin (WGSL pads `vec3` to 16
//! bytes of alignment), so they have no implementation.

use super::WgslType;

macro_rules! glam_type {
    ($($rust:ty => $wgsl:literal, $align:literal, $size:literal);* $(;)?) => {$(
        impl WgslType for $rust {
            const WGSL_ALIGN: usize = $align;
            const WGSL_SIZE: usize = $size;

            fn wgsl_type() -> String {
                $wgsl.to_owned()
            }
        }
    )*};
}

glam_type! {
    glam::Vec2 => "vec2<f32>", 8, 8;
    glam::Vec4 => "vec4<f32>", 16, 16;
    glam::UVec2 => "vec2<u32>", 8, 8;
    glam::UVec4 => "vec4<u32>", 16, 16;
    glam::IVec2 => "vec2<i32>", 8, 8;
    glam::IVec4 => "vec4<i32>", 16, 16;
    glam::Mat2 => "mat2x2<f32>", 8, 16;
    glam::Mat4 => "mat4x4<f32>", 16, 64;
}
