use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

use super::*;
use crate::user_wgsl::UserWgslError;

const MARBLE: &str = "struct Parameters {
    Kd: f32,
    veins: vec3<f32>,
    octaves: u32,
    sharp: bool,
    offset: i32,
}
const DEFAULTS = Parameters(0.8, vec3<f32>(0.2, 0.1, 0.05), 4u, true, -2);

fn stripes(x: f32) -> f32 { return 0.5 + 0.5 * sin(x); }

fn surface(ctx: ShadingContext, params: Parameters) -> SurfaceOutput {
    let d = diffuse(ctx, ctx.N) * params.Kd + ambient();
    let c = mix(ctx.Cs, params.veins, stripes(ctx.P.x * f32(params.octaves)));
    return SurfaceOutput(c * d, ctx.Os);
}
";

/// A displacement shader with a helper named as MARBLE's.
const SWELL: &str = "struct Parameters { amount: f32, map: TextureId }
const DEFAULTS = Parameters(0.1, TextureId(0u));
fn stripes(x: f32) -> f32 { return 0.5 + 0.5 * sin(x); }
fn displacement(ctx: ShadingContext, params: Parameters) -> vec3<f32> {
    let h = params.amount * stripes(ctx.s) * texture(ctx, params.map, ctx.s, ctx.t).r;
    return ctx.P + ctx.N * h;
}
";

/// The function a file defines makes it a surface or a displacement
/// shader; a displacement returns a point; a file is one shader.
#[test]
fn the_entry_function_says_what_a_shader_is() {
    let swell = shader(SWELL).expect("a displacement shader checks");
    assert_eq!(swell.kind, ShaderKind::Displacement);
    assert!(swell.takes_parameters);
    assert_eq!(shader(MARBLE).unwrap().kind, ShaderKind::Surface);
    assert!(matches!(
        shader("fn displacement(ctx: ShadingContext) -> f32 { return 0.0; }"),
        Err(SurfaceShaderError::Signature {
            kind: ShaderKind::Displacement
        })
    ));
    let both = format!(
        "{SWELL}\nfn surface(ctx: ShadingContext) -> SurfaceOutput {{ return SurfaceOutput(ctx.Cs, ctx.Os); }}"
    );
    assert!(matches!(shader(&both), Err(SurfaceShaderError::TwoEntries)));
    let error = shader("fn shade() {}").unwrap_err().to_string();
    assert!(
        error.contains("fn surface") && error.contains("fn displacement"),
        "{error}"
    );
}

/// A `TextureId` the scene does not give reads no texture (an id past
/// every texture), whatever `DEFAULTS` says: id 0 could be another
/// parameter's texture.
#[test]
fn a_texture_parameter_left_out_reads_nothing() {
    let swell = shader(SWELL).unwrap();
    let (slots, _) = pack_parameters(&swell, &BTreeMap::new(), no_textures, no_shadows).unwrap();
    assert_eq!(slots[1][0].to_bits(), NO_TEXTURE);
    assert_eq!(slots[0][0], 0.1);
}

fn no_textures(_: &str, _: &crate::texture::TextureDesc) -> Result<u32, SurfaceShaderError> {
    panic!("no texture parameter here")
}

fn no_shadows(_: &str, _: &ShadowDesc) -> Result<[f32; 4], SurfaceShaderError> {
    panic!("no shadow map parameter here")
}

fn shader(source: &str) -> Result<SurfaceShader, SurfaceShaderError> {
    SurfaceShader::from_source(Path::new("test.wgsl"), source.to_owned())
}

#[test]
fn parameters_and_defaults_are_reflected() {
    let shader = shader(MARBLE).expect("the shader checks");
    let names: Vec<(&str, ParameterKind)> = shader
        .parameters
        .iter()
        .map(|p| (p.name.as_str(), p.kind))
        .collect();
    assert_eq!(
        names,
        [
            ("Kd", ParameterKind::Float),
            ("veins", ParameterKind::Vec3),
            ("octaves", ParameterKind::Uint),
            ("sharp", ParameterKind::Bool),
            ("offset", ParameterKind::Int),
        ]
    );
    assert_eq!(shader.parameters[0].default, [0.8, 0.0, 0.0, 0.0]);
    assert_eq!(shader.parameters[1].default, [0.2, 0.1, 0.05, 0.0]);
    assert_eq!(shader.parameters[2].default[0].to_bits(), 4);
    assert_eq!(shader.parameters[3].default[0], 1.0);
    assert_eq!(shader.parameters[4].default[0].to_bits().cast_signed(), -2);
    assert!(shader.takes_parameters);
}

#[test]
fn scene_values_replace_defaults_and_unknown_names_warn() {
    let shader = shader(MARBLE).unwrap();
    let given = BTreeMap::from([
        ("Kd".to_owned(), ShaderValue::Number(0.25)),
        ("octaves".to_owned(), ShaderValue::Number(7.0)),
        ("veinz".to_owned(), ShaderValue::Number(1.0)),
    ]);
    let (slots, warnings) = pack_parameters(&shader, &given, no_textures, no_shadows).unwrap();
    assert_eq!(slots[0][0], 0.25);
    assert_eq!(slots[1], [0.2, 0.1, 0.05, 0.0], "the default stays");
    assert_eq!(slots[2][0].to_bits(), 7);
    assert_eq!(
        warnings,
        [ParameterWarning {
            name: "veinz".to_owned()
        }]
    );
    for (name, value) in [
        ("Kd", ShaderValue::Text("x".to_owned())),
        ("veins", ShaderValue::Numbers(vec![1.0, 2.0])),
        ("octaves", ShaderValue::Number(1.5)),
        ("octaves", ShaderValue::Number(-1.0)),
        ("sharp", ShaderValue::Number(1.0)),
        ("Kd", ShaderValue::Number(1e300)),
    ] {
        let given = BTreeMap::from([(name.to_owned(), value.clone())]);
        let error = pack_parameters(&shader, &given, no_textures, no_shadows)
            .expect_err("a value that does not fit");
        assert!(
            error.to_string().contains(name),
            "{name} {value:?}: {error}"
        );
    }
}

#[test]
fn errors_name_the_line_in_the_users_text() {
    let source = "fn surface(ctx: ShadingContext) -> SurfaceOutput {\n    let x: f32 = 1u;\n    return SurfaceOutput(ctx.Cs, ctx.Os);\n}\n";
    match shader(source) {
        Err(SurfaceShaderError::Wgsl(UserWgslError::Invalid { line, .. })) => assert_eq!(line, 2),
        other => panic!("{other:?}"),
    }
}

#[test]
fn the_renderers_buffers_are_out_of_reach() {
    for name in [
        "framebuffer",
        "stats",
        "lights",
        "frame",
        "height_texels",
        "shader_parameter",
    ] {
        let source = format!(
            "fn surface(ctx: ShadingContext) -> SurfaceOutput {{\n    let x = {name};\n    return SurfaceOutput(ctx.Cs, ctx.Os);\n}}\n"
        );
        match shader(&source) {
            Err(SurfaceShaderError::Wgsl(UserWgslError::OutsideName {
                name: found, line, ..
            })) => {
                assert_eq!((found.as_str(), line), (name, 2));
            }
            other => panic!("{name}: {other:?}"),
        }
    }
    let global = "var<private> counter: u32;\nfn surface(ctx: ShadingContext) -> SurfaceOutput { return SurfaceOutput(ctx.Cs, ctx.Os); }\n";
    assert!(matches!(
        shader(global),
        Err(SurfaceShaderError::Wgsl(UserWgslError::Global {
            line: 1,
            ..
        }))
    ));
}

#[test]
fn a_missing_or_wrong_entry_point_is_named() {
    assert!(matches!(
        shader(
            "fn shade(ctx: ShadingContext) -> SurfaceOutput { return SurfaceOutput(ctx.Cs, ctx.Os); }"
        ),
        Err(SurfaceShaderError::MissingEntry)
    ));
    assert!(matches!(
        shader("fn surface(ctx: ShadingContext) -> vec3<f32> { return ctx.Cs; }"),
        Err(SurfaceShaderError::Signature { .. })
    ));
    assert!(matches!(
        shader(
            "struct Parameters { m: mat3x3<f32> }\nfn surface(ctx: ShadingContext, params: Parameters) -> SurfaceOutput { return SurfaceOutput(ctx.Cs, ctx.Os); }"
        ),
        Err(SurfaceShaderError::ParameterType { line: 1, .. })
    ));
    let redefined = "fn ambient() -> vec3<f32> { return vec3<f32>(1.0); }\nfn surface(ctx: ShadingContext) -> SurfaceOutput { return SurfaceOutput(ctx.Cs, ctx.Os); }";
    let error = shader(redefined).expect_err("a redefined interface name");
    assert!(error.to_string().contains("ambient"), "{error}");
}

/// Two shaders with the same helper names and the standard interface make
/// one module that naga validates.
#[test]
fn several_shaders_live_side_by_side_in_one_module() {
    let plain = shader(
        "fn stripes(x: f32) -> f32 { return x; }\nfn surface(ctx: ShadingContext) -> SurfaceOutput { return SurfaceOutput(ctx.Cs * stripes(ctx.u), ctx.Os); }",
    )
    .unwrap();
    let swell = shader(SWELL).unwrap();
    let shaders = [
        Arc::new(shader(MARBLE).unwrap()),
        Arc::new(plain),
        Arc::new(swell),
    ];
    let library = megakernel_wgsl(&shaders);
    assert!(library.contains("fn surface0_stripes(") && library.contains("fn surface1_stripes("));
    assert!(library.contains("fn displacement2_stripes("));
    assert!(library.contains("const DISPLACEMENT_SHADERS: bool = true;"));
    // Each dispatcher calls only its own kind.
    let displacement_dispatch = &library[library.find("fn user_displacement(").unwrap()..];
    assert!(
        displacement_dispatch.contains("case 2u") && !displacement_dispatch.contains("case 0u")
    );
    assert!(megakernel_wgsl(&shaders[..2]).contains("const DISPLACEMENT_SHADERS: bool = false;"));
    // The module as the megakernel holds it, with the interface's host side
    // stubbed out and the parameters read from a buffer.
    let module = format!(
        "{library}\n{}\n{}\n{}\n{}\nfn shader_parameter(slot: u32) -> vec4<f32> {{ return vec4<f32>(f32(slot)); }}\nfn constant(ctx: ShadingContext) -> SurfaceOutput {{ return SurfaceOutput(ctx.Cs, ctx.Os); }}\nconst MAX_SPECULAR_EXPONENT: f32 = 1e4;",
        include_str!("../../../shaders/reyes/library_math.wgsl"),
        include_str!("../../../shaders/reyes/surface_api.wgsl"),
        include_str!("../../../shaders/reyes/surface_host_stub.wgsl"),
        include_str!("../../../shaders/reyes/surface_api_shadow.wgsl"),
    );
    let parsed = naga::front::wgsl::parse_str(&module)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(&module)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&parsed)
    .expect("the library validates");
}

/// A `TextureId` parameter takes a file, or a table with the texture's
/// colour space and wrap modes, which reach the texture set.
#[test]
fn a_texture_parameter_takes_a_file_or_a_table() {
    use crate::texture::{ColorSpace, TextureDesc, Wrap};
    let shader = shader(
        "struct Parameters { map: TextureId, Kd: f32 }\n\
         fn surface(ctx: ShadingContext, params: Parameters) -> SurfaceOutput {\n\
             return SurfaceOutput(texture(ctx, params.map, ctx.s, ctx.t).rgb * params.Kd, ctx.Os);\n\
         }",
    )
    .unwrap();
    assert_eq!(shader.parameters[0].kind, ParameterKind::Texture);
    let given: BTreeMap<String, ShaderValue> = toml::from_str(
        "map = { path = \"wood.exr\", color_space = \"linear\", wrap_s = \"clamp\", wrap_t = \"black\" }\nKd = 0.5",
    )
    .expect("the table parses");
    let mut seen = Vec::new();
    let (slots, _) = pack_parameters(
        &shader,
        &given,
        |_, desc: &TextureDesc| {
            seen.push(desc.clone());
            Ok(7)
        },
        no_shadows,
    )
    .unwrap();
    assert_eq!(slots[0][0].to_bits(), 7, "the texture's index");
    assert_eq!(
        seen,
        [TextureDesc {
            path: "wood.exr".into(),
            color_space: ColorSpace::Linear,
            wrap_s: Wrap::Clamp,
            wrap_t: Wrap::Black,
        }]
    );
    let plain: BTreeMap<String, ShaderValue> = toml::from_str("map = \"wood.png\"").unwrap();
    seen.clear();
    pack_parameters(
        &shader,
        &plain,
        |_, desc: &TextureDesc| {
            seen.push(desc.clone());
            Ok(0)
        },
        no_shadows,
    )
    .unwrap();
    assert_eq!(seen, [TextureDesc::new("wood.png")]);
    let wrong: BTreeMap<String, ShaderValue> = toml::from_str("map = 3.0").unwrap();
    let error = pack_parameters(&shader, &wrong, |_, _: &TextureDesc| Ok(0), no_shadows)
        .expect_err("a number");
    assert!(error.to_string().contains("map"), "{error}");
}

/// The same bound holds for a user surface shader's functions (and only
/// theirs: the interface that follows the user's text is not counted).
#[test]
fn a_surface_shader_past_the_memory_limit_is_refused() {
    let shader = |body: &str| {
        SurfaceShader::from_source(
            std::path::Path::new("s.wgsl"),
            format!(
                "fn surface(ctx: ShadingContext) -> SurfaceOutput {{\n{body}    return SurfaceOutput(ctx.Cs, ctx.Os);\n}}\n"
            ),
        )
    };
    match shader("    var big: array<f32, 1000000>;\n    big[0] = 1.0;\n") {
        Err(SurfaceShaderError::Wgsl(UserWgslError::Memory(m))) => assert_eq!(
            (m.function.as_str(), m.name.as_str(), m.line),
            ("surface", "big", 2)
        ),
        other => panic!("{other:?}"),
    }
    shader("").expect("a plain shader passes: the interface is not counted");
}

const SHADOWED: &str = "struct Parameters { key: ShadowId, fill: ShadowId, Kd: f32 }
fn surface(ctx: ShadingContext, params: Parameters) -> SurfaceOutput {
    let lit = (1.0 - shadow(params.key, ctx.P)) * (1.0 - 0.5 * shadow(params.fill, ctx.P));
    return SurfaceOutput(ctx.Cs * lit * params.Kd, ctx.Os);
}";

/// A 4 x 2 map looking down -z from the origin, every texel at depth 2.
fn small_map() -> crate::shadow::ShadowMap {
    crate::shadow::ShadowMap {
        width: 4,
        height: 2,
        depths: vec![2.0; 8],
        world_to_camera: glam::Mat4::IDENTITY,
        world_to_clip: glam::Mat4::orthographic_rh(-1.0, 1.0, -1.0, 1.0, 0.1, 10.0),
    }
}

fn write_map(dir: &Path, name: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    let bytes = crate::shadow::file::encode(&small_map(), "shadow").unwrap();
    std::fs::write(&path, bytes).unwrap();
    path
}

/// A `ShadowId` parameter takes a file or a shadow table; its slot holds
/// the map, the lookup grid's side, the region (width plus blur times the
/// map's larger side) and the bias. One left out names no map.
#[test]
fn a_shadow_parameter_packs_its_map_and_filter() {
    let shader = shader(SHADOWED).unwrap();
    let kinds: Vec<_> = shader.parameters.iter().map(|p| p.kind).collect();
    assert_eq!(
        kinds,
        [
            ParameterKind::Shadow,
            ParameterKind::Shadow,
            ParameterKind::Float
        ]
    );
    assert_eq!(
        ShadowSlot::from_slot(shader.parameters[0].default),
        ShadowSlot::NONE
    );
    let given: BTreeMap<String, ShaderValue> = toml::from_str(
        "key = { path = \"key.shad\", samples = 9, filter_width = 2, blur = 0.25, bias = 0.5 }\nKd = 1",
    )
    .expect("the table parses");
    let mut seen = Vec::new();
    let map = small_map();
    let (slots, _) = pack_parameters(&shader, &given, no_textures, |name, desc| {
        seen.push((name.to_owned(), desc.clone()));
        Ok(ShadowSlot::new(3, &map, &desc.filter()).to_slot())
    })
    .unwrap();
    assert_eq!(seen.len(), 1);
    assert_eq!(seen[0].0, "key");
    let key = ShadowSlot::from_slot(slots[0]);
    assert_eq!(
        key,
        ShadowSlot {
            map: 3,
            side: 3,
            region: 2.0 + 0.25 * 4.0,
            bias: 0.5
        }
    );
    assert_eq!(
        ShadowSlot::from_slot(slots[1]).map,
        NO_SHADOW,
        "fill is left out"
    );
    // A bare file, and a table of the file alone, take the defaults.
    for text in ["key = \"key.shad\"", "key = { path = \"key.shad\" }"] {
        let given: BTreeMap<String, ShaderValue> = toml::from_str(text).unwrap();
        let mut filter = None;
        pack_parameters(&shader, &given, no_textures, |_, desc| {
            assert_eq!(desc.path, Path::new("key.shad"));
            filter = Some(desc.filter());
            Ok(ShadowSlot::NONE.to_slot())
        })
        .unwrap();
        assert_eq!(
            filter,
            Some(crate::shadow::ShadowFilter::default()),
            "{text}"
        );
    }
}

/// Values that are no shadow map, and filters that cannot be used, are
/// named errors.
#[test]
fn a_shadow_parameter_refuses_what_is_no_map() {
    let shader = shader(SHADOWED).unwrap();
    for (text, expected) in [
        ("key = 3.0", "ShadowId"),
        (
            "key = { path = \"key.shad\", color_space = \"linear\" }",
            "ShadowId",
        ),
        ("key = { path = \"key.shad\", blur = -0.1 }", "blur"),
        ("key = { path = \"key.shad\", bias = nan }", "bias"),
    ] {
        let given: BTreeMap<String, ShaderValue> = toml::from_str(text).unwrap();
        let error = pack_parameters(&shader, &given, no_textures, no_shadows)
            .expect_err("not a usable map");
        let message = error.to_string();
        assert!(
            message.contains("key") && message.contains(expected),
            "{text}: {message}"
        );
    }
}

/// The table reads each map file once, relative to the scene, records the
/// `ShadowId` slots, and hands the GPU the maps' table entries; a missing
/// file names the parameter and the path.
#[test]
fn the_shader_table_reads_each_map_once_and_the_gpu_finds_it() {
    let dir = std::env::temp_dir().join(format!("reyes-shadow-param-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let shader_file = dir.join("shadowed.wgsl");
    std::fs::write(&shader_file, SHADOWED).unwrap();
    write_map(&dir, "key.shad");
    write_map(&dir, "fill.shad");
    let mut table = ShaderTable::default();
    let mut textures = crate::texture::TextureSet::default();
    // A light's map is there first.
    let mut maps = vec![small_map()];
    let both: BTreeMap<String, ShaderValue> =
        toml::from_str("key = \"key.shad\"\nfill = \"fill.shad\"").unwrap();
    let key_only: BTreeMap<String, ShaderValue> = toml::from_str("key = \"key.shad\"").unwrap();
    for values in [&both, &key_only] {
        table
            .add(
                &shader_file,
                ShaderKind::Surface,
                values,
                &mut textures,
                &mut maps,
                Some(&dir),
            )
            .unwrap();
    }
    assert_eq!(maps.len(), 3, "each file read once");
    assert_eq!(table.shadow_files.len(), 2);
    assert_eq!(table.shadow_slots, [0, 1, 3, 4]);
    let map_of = |slot: usize| ShadowSlot::from_slot(table.parameters[slot]).map;
    // The values are read in name order: fill, then key.
    assert_eq!(
        [map_of(0), map_of(1), map_of(3), map_of(4)],
        [2, 1, 2, NO_SHADOW]
    );
    assert!(table.looks_up_shadow_maps(&maps));
    assert!(
        !table.looks_up_shadow_maps(&[]),
        "the viewer's maps dropped"
    );
    let gpu = table.gpu_parameters(maps.len(), |map| 1000 + 24 * map);
    let gpu_map = |slot: usize| ShadowSlot::from_slot(gpu[slot]).map;
    assert_eq!(
        [gpu_map(0), gpu_map(1), gpu_map(3), gpu_map(4)],
        [1048, 1024, 1048, NO_SHADOW]
    );
    assert_eq!(gpu[2], table.parameters[2], "other slots are left alone");
    // Without the maps (the viewer's shadows off), no slot names one.
    let none = table.gpu_parameters(0, |map| map);
    assert!(
        table
            .shadow_slots
            .iter()
            .all(|&s| ShadowSlot::from_slot(none[s as usize]).map == NO_SHADOW)
    );
    let missing: BTreeMap<String, ShaderValue> = toml::from_str("fill = \"gone.shad\"").unwrap();
    let error = table
        .add(
            &shader_file,
            ShaderKind::Surface,
            &missing,
            &mut textures,
            &mut maps,
            Some(&dir),
        )
        .expect_err("no such map");
    let message = error.to_string();
    assert!(
        message.contains("fill") && message.contains("gone.shad"),
        "{message}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
