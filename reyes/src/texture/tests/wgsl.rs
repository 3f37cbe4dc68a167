//! The WGSL twin: its constants are the Rust codes, its struct has the Rust
//! layout, and it validates (the GPU comparison is `tests/tests/texture_gpu.rs`).

use scheduler::Item;

use super::*;

/// The value of `const NAME: u32 = Nu;` in `source`.
fn wgsl_constant(source: &str, name: &str) -> u32 {
    let line = source
        .lines()
        .find(|l| l.starts_with(&format!("const {name}: u32 = ")))
        .unwrap_or_else(|| panic!("no constant {name}"));
    line.rsplit(' ')
        .next()
        .unwrap()
        .trim_end_matches(';')
        .trim_end_matches('u')
        .parse()
        .unwrap()
}

#[test]
fn wrap_codes_match_the_wgsl() {
    for (wrap, name) in [
        (Wrap::Periodic, "TEXTURE_WRAP_PERIODIC"),
        (Wrap::Clamp, "TEXTURE_WRAP_CLAMP"),
        (Wrap::Black, "TEXTURE_WRAP_BLACK"),
    ] {
        assert_eq!(wgsl_constant(TEXTURE_WGSL, name), wrap.code(), "{name}");
    }
}

#[test]
fn the_anisotropy_limit_matches_the_wgsl() {
    assert_eq!(
        wgsl_constant(TEXTURE_WGSL, "TEXTURE_MAX_ANISOTROPY"),
        MAX_ANISOTROPY
    );
}

#[test]
fn the_library_validates_with_its_globals() {
    assert_eq!(std::mem::size_of::<TextureInfo>(), 32);
    let source = format!(
        "{}\n@group(0) @binding(0) var<storage, read> texture_infos: array<TextureInfo>;\n\
         @group(0) @binding(1) var<storage, read> texels: array<vec2<u32>>;\n\
         fn texture_count() -> u32 {{ return arrayLength(&texture_infos); }}\n\
         fn texture_info(id: u32) -> TextureInfo {{ return texture_infos[id]; }}\n\
         fn texture_packed_count() -> u32 {{ return arrayLength(&texels); }}\n\
         fn texture_packed(at: u32) -> vec2<u32> {{ return texels[at]; }}\n{TEXTURE_WGSL}",
        TextureInfo::wgsl_declarations()
    );
    let module = naga::front::wgsl::parse_str(&source)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{e:?}"));
    assert!(
        module
            .functions
            .iter()
            .any(|(_, f)| f.name.as_deref() == Some("texture_sample"))
    );
}

/// `texture_half` of the WGSL, transcribed: the integer decoding of an f16.
fn wgsl_half(bits: u32) -> f32 {
    let sign = (bits & 0x8000) << 16;
    let exponent = (bits >> 10) & 0x1f;
    let mantissa = bits & 0x3ff;
    if exponent == 0 {
        return f32::from_bits(sign | (mantissa as f32 * 2f32.powi(-24)).to_bits());
    }
    f32::from_bits(sign | ((exponent + 112) << 23) | (mantissa << 13))
}

#[test]
fn the_wgsl_f16_decoding_is_exact_for_every_finite_half() {
    for bits in 0..=u16::MAX {
        let half = half::f16::from_bits(bits);
        if half.is_finite() {
            assert_eq!(
                wgsl_half(u32::from(bits)).to_bits(),
                half.to_f32().to_bits(),
                "{bits:#06x}"
            );
        }
    }
    // And the decoding the texel buffer uses is the same.
    let packed = mipmap::pack(Vec4::new(-0.0, 1e-6, 3.25, -65504.0));
    let unpacked = mipmap::unpack(packed);
    for (k, word) in [
        packed[0] & 0xffff,
        packed[0] >> 16,
        packed[1] & 0xffff,
        packed[1] >> 16,
    ]
    .into_iter()
    .enumerate()
    {
        assert_eq!(wgsl_half(word).to_bits(), unpacked[k].to_bits());
    }
}
