//! glam's vectors and matrices whose size matches their WGSL twin. Their Rust
//! alignment may be smaller (`UVec4` is 4-byte aligned, `vec4<u32>` 16,
//! `Vec3` 4 where `vec3<f32>` is 16): the derive's offset assertions reject a
//! field that would land elsewhere, and its size assertions an array of
//! 3-vectors (WGSL strides them by 16 bytes, Rust by 12). A `Vec3` is
//! therefore accepted where WGSL would put it too: at a multiple of 16,
//! followed by a 4-byte field or padding. `Vec3A` (16 bytes) and the 3x3
//! matrices (WGSL pads each column) have no twin, so no implementation.

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
    glam::Vec3 => "vec3<f32>", 16, 12;
    glam::Vec4 => "vec4<f32>", 16, 16;
    glam::UVec2 => "vec2<u32>", 8, 8;
    glam::UVec3 => "vec3<u32>", 16, 12;
    glam::UVec4 => "vec4<u32>", 16, 16;
    glam::IVec2 => "vec2<i32>", 8, 8;
    glam::IVec3 => "vec3<i32>", 16, 12;
    glam::IVec4 => "vec4<i32>", 16, 16;
    glam::Mat2 => "mat2x2<f32>", 8, 16;
    glam::Mat4 => "mat4x4<f32>", 16, 64;
}
