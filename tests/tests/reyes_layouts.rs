//! The Rust twins of the Reyes megakernel's resource structs (`Frame`,
//! `Object`, `Light`) agree with the WGSL ones, member by member: naga lays
//! out the generated module, and every WGSL member must sit at the offset of
//! the Rust field of its name.
//! (A Rust `pad: [u32; 3]` where WGSL had `aov` and `depth_range` once
//! passed every size check and silently left the AOV at 0.)

use std::mem::{offset_of, size_of};

use reyes::gpu::buffers::{FrameUniform, LightData};
use reyes::gpu::objects::ObjectData;

/// The members of WGSL struct `name` in `module`: names and byte offsets,
/// and the struct's size.
fn wgsl_struct(module: &naga::Module, name: &str) -> (Vec<(String, u32)>, u32) {
    let ty = module
        .types
        .iter()
        .find(|(_, ty)| ty.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("no struct {name} in the megakernel"))
        .1;
    let naga::TypeInner::Struct { members, span } = &ty.inner else {
        panic!("{name} is not a struct");
    };
    let members = members
        .iter()
        .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
        .collect();
    (members, *span)
}

/// Checks that WGSL struct `name` has exactly the members `twins` (WGSL
/// name, offset of the Rust field it mirrors) and the Rust struct's size.
fn assert_twins(module: &naga::Module, name: &str, rust_size: usize, twins: &[(&str, usize)]) {
    let (members, span) = wgsl_struct(module, name);
    assert_eq!(span as usize, rust_size, "{name}: WGSL size vs Rust size");
    let listed: Vec<&str> = twins.iter().map(|(n, _)| *n).collect();
    let found: Vec<&str> = members.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        found, listed,
        "{name}: the WGSL members and the Rust twins listed here"
    );
    for ((member, offset), (_, rust_offset)) in members.iter().zip(twins) {
        assert_eq!(
            *offset as usize, *rust_offset,
            "{name}.{member}: WGSL offset {offset}, Rust offset {rust_offset}"
        );
    }
}

#[test]
fn the_resource_structs_match_their_rust_twins() {
    let compiled = reyes::gpu::graph::compile(scheduler::wgpu::Features::empty())
        .expect("the Reyes graph compiles");
    let module = naga::front::wgsl::parse_str(compiled.wgsl()).expect("the megakernel parses");

    macro_rules! same_names {
        ($rust:ty: $($field:ident),* $(,)?) => {
            [$((stringify!($field), offset_of!($rust, $field))),*]
        };
    }
    let uvt = offset_of!(FrameUniform, uvt);
    let origin = offset_of!(FrameUniform, origin);
    let frame: Vec<(&str, usize)> = same_names!(FrameUniform:
        view_proj, eye, dice_threshold, width, height, spp, k, max_split_depth, sampling,
        jitter, light_count, ambient, specular_strength, shininess, dicing, clip_pad,
        aperture, focus, pixel_scale, time_lens)
    .into_iter()
    .chain([
        ("uvt_simple", uvt),
        ("uvt_interleave", uvt + 4),
        ("uvt_pixel", uvt + 8),
        ("uvt_inverse", uvt + 12),
    ])
    .chain(same_names!(FrameUniform: interleave_tuples))
    .chain([("origin_x", origin), ("origin_y", origin + 4)])
    .chain(same_names!(FrameUniform: micropolygon_side, patch_floats, aov, depth_range, smooth_shading))
    .collect();
    assert_twins(&module, "Frame", size_of::<FrameUniform>(), &frame);

    let object = same_names!(ObjectData:
        albedo, displace_kind, map_offset, map_width, map_height, displace_scale,
        displace_bound, tiling, front, motion, moving, motion_stretch, pad1, pad2);
    assert_twins(&module, "Object", size_of::<ObjectData>(), &object);

    let light = same_names!(LightData: to_light, radiance);
    assert_twins(&module, "Light", size_of::<LightData>(), &light);
}
