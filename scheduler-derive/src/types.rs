//! Field types that have no WGSL twin with the same layout, rejected by name
//! so that the error says what to use instead. Everything else is left to the
//! `WgslType` bound, whose own message covers unknown types.

use syn::{Type, spanned::Spanned};

/// Checks one field type; arrays are checked through to their element type.
pub(crate) fn check(ty: &Type) -> syn::Result<()> {
    match ty {
        Type::Array(array) => check(&array.elem),
        Type::Group(group) => check(&group.elem),
        Type::Paren(paren) => check(&paren.elem),
        Type::Path(path) => match path.path.segments.last() {
            Some(last) => match advice(&last.ident.to_string()) {
                Some(advice) => Err(syn::Error::new(ty.span(), advice)),
                None => Ok(()),
            },
            None => Ok(()),
        },
        Type::Tuple(_) => Err(syn::Error::new(
            ty.span(),
            "#[derive(Item)]: tuples have no WGSL layout; use a nested struct that derives `Item`",
        )),
        Type::Reference(_) | Type::Ptr(_) | Type::Slice(_) => Err(syn::Error::new(
            ty.span(),
            "#[derive(Item)]: items are plain data; references, pointers and slices cannot be fields",
        )),
        _ => Ok(()),
    }
}

/// What to use instead of a type whose WGSL layout differs from Rust's.
fn advice(ident: &str) -> Option<&'static str> {
    Some(match ident {
        "bool" => {
            "#[derive(Item)]: `bool` is not host-shareable in WGSL (its size is unspecified); use `u32` holding 0 or 1"
        }
        "Vec3A" => {
            "#[derive(Item)]: `Vec3A` is 16 bytes, WGSL's `vec3<f32>` 12 (aligned to 16); use `Vec3` followed by a 4-byte field, or `Vec4`"
        }
        "Mat3" | "Mat3A" => {
            "#[derive(Item)]: WGSL's `mat3x3<f32>` pads each column to 16 bytes; use `Mat4` or `[Vec4; 3]`"
        }
        "u8" | "i8" | "u16" | "i16" | "u64" | "i64" | "u128" | "i128" | "usize" | "isize"
        | "f64" => {
            "#[derive(Item)]: WGSL items hold 32-bit scalars only; use `u32`, `i32` or `f32`"
        }
        "DVec2" | "DVec3" | "DVec4" | "DMat2" | "DMat3" | "DMat4" | "I64Vec2" | "I64Vec3"
        | "I64Vec4" | "U64Vec2" | "U64Vec3" | "U64Vec4" => {
            "#[derive(Item)]: WGSL has no 64-bit vectors; use the 32-bit glam types"
        }
        _ => return None,
    })
}
