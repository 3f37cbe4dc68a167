//! The Rust structs the Reyes megakernel shares with WGSL (`Frame`,
//! `Object`, `Light`, `PatchItem`, `InputPatch`) agree with the module's, member by member:
//! naga lays out the generated module, and every WGSL member must sit at the
//! offset of the Rust field of its name. The structs are generated from the
//! Rust ones by `#[scheduler::item]`, which checks the layout when the crate
//! compiles; this is the independent check by naga's layouter.
//! (A Rust `pad: [u32; 3]` where WGSL had `aov` and `depth_range` once
//! passed every size check and silently left the AOV at 0.)

use std::mem::size_of;

use reyes::gpu::buffers::{FrameUniform, LightData};
use reyes::gpu::graph::{InputPatch, PatchItem};
use reyes::gpu::objects::ObjectData;
use scheduler::Item;
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

/// The WGSL struct of `T` in `module` has `T`'s fields at `T`'s offsets.
fn assert_item<T: Item>(module: &naga::Module) {
    let fields = T::rust_fields();
    let twins: Vec<(&str, usize)> = fields.iter().map(|(n, o)| (*n, *o)).collect();
    assert_twins(module, T::WGSL_NAME, size_of::<T>(), &twins);
}

#[test]
fn the_shared_structs_match_their_rust_definitions() {
    let compiled = reyes::gpu::graph::compile(scheduler::wgpu::Features::empty())
        .expect("the Reyes graph compiles");
    let module = naga::front::wgsl::parse_str(compiled.wgsl()).expect("the megakernel parses");
    assert_item::<FrameUniform>(&module);
    assert_item::<ObjectData>(&module);
    assert_item::<LightData>(&module);
    assert_item::<PatchItem>(&module);
    assert_item::<InputPatch>(&module);
    // The names the shaders use.
    let names = [
        FrameUniform::WGSL_NAME,
        ObjectData::WGSL_NAME,
        LightData::WGSL_NAME,
        PatchItem::WGSL_NAME,
        InputPatch::WGSL_NAME,
    ];
    assert_eq!(
        names,
        ["Frame", "Object", "Light", "PatchItem", "InputPatch"]
    );
}

/// The resolve shader validates, and its uniform matches the Rust struct.
#[test]
fn the_resolve_shader_validates_and_its_uniform_matches() {
    let source = reyes::gpu::resolve::resolve_wgsl();
    assert!(source.starts_with("// "), "a header comment first");
    let module = naga::front::wgsl::parse_str(&source)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .expect("the resolve shader validates");
    assert_item::<reyes::gpu::resolve::ResolveParams>(&module);
}
