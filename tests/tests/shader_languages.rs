//! Every generated module (`tests::generated_modules`: the test graphs under
//! every option set, the examples, every Reyes variant, the resolve pass)
//! through each of naga's writers: SPIR-V (Vulkan), MSL (Metal), HLSL (DX12)
//! and GLSL ES 3.10 (GL, one shader per entry point), the translations wgpu
//! makes on each backend. Translation must succeed everywhere; `spirv-val`
//! and `glslangValidator` must accept the SPIR-V and the GLSL; the MSL and
//! HLSL of the default Reyes variant and of the Mandelbrot example are
//! snapshotted, so a change to them is reviewed.

use std::path::{Path, PathBuf};
use std::process::Command;

use naga::back::{glsl, hlsl, msl, spv};
use naga::valid::{ModuleInfo, ValidationFlags, Validator};
use tests::generated_modules::{self, GeneratedModule};

/// The module parsed and validated, or a panic naming it.
fn parse(module: &GeneratedModule) -> (naga::Module, ModuleInfo) {
    let parsed = naga::front::wgsl::parse_str(&module.wgsl)
        .unwrap_or_else(|e| panic!("{}: {}", module.name, e.emit_to_string(&module.wgsl)));
    let info = Validator::new(ValidationFlags::all(), module.capabilities())
        .validate(&parsed)
        .unwrap_or_else(|e| panic!("{}: {}", module.name, e.emit_to_string(&module.wgsl)));
    (parsed, info)
}

/// The module in every language: SPIR-V words, MSL, HLSL, and GLSL per
/// entry point (name, text), or why GLSL could not be written.
struct Translations {
    spirv: Vec<u32>,
    msl: String,
    hlsl: String,
    glsl: Result<Vec<(String, String)>, String>,
    /// What [`expected_glsl_refusal`] declares for the module.
    glsl_refusal: Option<&'static str>,
}

/// Why the GLSL writer is expected to refuse `module`, if it is: the
/// per-backend difference, declared rather than skipped. wgpu's GL backend
/// offers no 64-bit integers (`SHADER_INT64`), and naga's GLSL writer has no
/// 64-bit scalars, so the Reyes variants whose depth test is a 64-bit
/// `atomicMin` cannot run on GL; those whose test uses 32-bit atomics (the
/// two-pass test the renderer takes on GL, and the second-nearest depth)
/// can (docs/scheduler.md, "Portability").
fn expected_glsl_refusal(parsed: &naga::Module) -> Option<&'static str> {
    let wide = |scalar: &naga::Scalar| scalar.width == 8;
    let uses_64_bits = parsed.types.iter().any(|(_, ty)| match &ty.inner {
        naga::TypeInner::Scalar(scalar) | naga::TypeInner::Atomic(scalar) => wide(scalar),
        naga::TypeInner::Vector { scalar, .. } => wide(scalar),
        _ => false,
    });
    uses_64_bits.then_some(
        "A scalar with an unsupported width was requested: Scalar { kind: Uint, width: 8 }",
    )
}

fn translate(module: &GeneratedModule) -> Result<Translations, String> {
    let (parsed, info) = parse(module);
    let spirv = spv::write_vec(&parsed, &info, &spv::Options::default(), None)
        .map_err(|e| format!("SPIR-V: {e}"))?;
    // Metal 2.1: the oldest that wgpu's Metal backend asks for atomics on
    // device memory with.
    let msl_options = msl::Options {
        lang_version: (2, 1),
        ..msl::Options::default()
    };
    let (msl, _) = msl::write_string(
        &parsed,
        &info,
        &msl_options,
        &msl::PipelineOptions::default(),
    )
    .map_err(|e| format!("MSL: {e}"))?;
    let mut hlsl = String::new();
    hlsl::Writer::new(
        &mut hlsl,
        &hlsl::Options::default(),
        &hlsl::PipelineOptions::default(),
    )
    .write(&parsed, &info, None)
    .map_err(|e| format!("HLSL: {e}"))?;
    Ok(Translations {
        spirv,
        msl,
        hlsl,
        glsl: translate_glsl(&parsed, &info),
        glsl_refusal: expected_glsl_refusal(&parsed),
    })
}

/// GLSL ES 3.10 of each entry point, as wgpu's GL backend writes it.
fn translate_glsl(
    parsed: &naga::Module,
    info: &ModuleInfo,
) -> Result<Vec<(String, String)>, String> {
    let mut glsl = Vec::new();
    for entry in &parsed.entry_points {
        let mut text = String::new();
        let pipeline = glsl::PipelineOptions {
            shader_stage: entry.stage,
            entry_point: entry.name.clone(),
            multiview: None,
        };
        glsl::Writer::new(
            &mut text,
            parsed,
            info,
            &glsl::Options::default(),
            &pipeline,
            naga::proc::BoundsCheckPolicies::default(),
        )
        .and_then(|mut writer| writer.write())
        .map_err(|e| format!("{e}"))?;
        glsl.push((entry.name.clone(), text));
    }
    Ok(glsl)
}

/// What is wrong with `translations`: a GLSL result other than the one
/// [`expected_glsl_refusal`] declares.
fn glsl_problem(translations: &Translations) -> Option<String> {
    match (&translations.glsl, translations.glsl_refusal) {
        (Ok(_), None) => None,
        (Err(e), Some(expected)) if e == expected => None,
        (Err(e), _) => Some(format!("GLSL: {e}")),
        (Ok(_), Some(expected)) => Some(format!(
            "GLSL was expected to be refused ({expected}) but was written: \
             update expected_glsl_refusal and the portability table"
        )),
    }
}

#[test]
fn every_generated_module_translates_to_every_shading_language() {
    let modules = generated_modules::all();
    let mut failures = Vec::new();
    let mut refused = 0;
    for module in &modules {
        match translate(module) {
            Ok(translations) => {
                refused += usize::from(translations.glsl_refusal.is_some());
                failures
                    .extend(glsl_problem(&translations).map(|e| format!("{}: {e}", module.name)));
            }
            Err(e) => failures.push(format!("{}: {e}", module.name)),
        }
    }
    eprintln!(
        "{} modules into SPIR-V, MSL and HLSL; {} into GLSL too, {refused} refused by GLSL as declared",
        modules.len(),
        modules.len() - refused
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Runs `tool` on `file`; its output on failure.
fn check_with(tool: &str, args: &[&str], file: &Path) -> Result<(), String> {
    let output = Command::new(tool)
        .args(args)
        .arg(file)
        .output()
        .unwrap_or_else(|e| {
            panic!(
                "{tool}: {e}. Install Debian's spirv-tools and glslang-tools \
                 (.ci/run does), or set SKIP_SHADER_TOOLS=1 to mark this test ignored"
            )
        });
    if output.status.success() {
        Ok(())
    } else {
        Err(format!(
            "{tool} {}: {}{}",
            file.display(),
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        ))
    }
}

/// A fresh directory for this test's files.
fn scratch_dir() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("shader-languages-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a scratch directory");
    dir
}

#[test]
#[cfg_attr(
    skip_shader_tools,
    ignore = "SKIP_SHADER_TOOLS=1: spirv-val and glslangValidator not run"
)]
fn spirv_val_and_glslang_accept_every_translation() {
    let dir = scratch_dir();
    let modules = generated_modules::all();
    let mut failures = Vec::new();
    let mut glsl_shaders = 0;
    for (index, module) in modules.iter().enumerate() {
        let translations = translate(module).unwrap_or_else(|e| panic!("{}: {e}", module.name));
        let spirv = dir.join(format!("module{index}.spv"));
        std::fs::write(&spirv, bytemuck::cast_slice(&translations.spirv)).unwrap();
        if let Err(e) = check_with("spirv-val", &["--target-env", "vulkan1.1"], &spirv) {
            failures.push(format!("{}: {e}", module.name));
        }
        for (entry, text) in translations.glsl.iter().flatten() {
            // glslangValidator takes the stage from the extension.
            let glsl = dir.join(format!("module{index}-{entry}.comp"));
            std::fs::write(&glsl, text).unwrap();
            glsl_shaders += 1;
            if let Err(e) = check_with("glslangValidator", &[], &glsl) {
                failures.push(format!("{} ({entry}): {e}", module.name));
            }
        }
    }
    eprintln!(
        "spirv-val checked {} modules, glslangValidator {glsl_shaders} GLSL shaders",
        modules.len()
    );
    let _ = std::fs::remove_dir_all(&dir);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The MSL and HLSL of the default Reyes frame's megakernel and of the
/// Mandelbrot example: no compiler for them runs here, so their text is
/// reviewed instead.
#[test]
fn snapshots_of_the_metal_and_direct3d_translations() {
    let reyes_default = generated_modules::reyes_variants()
        .into_iter()
        .find(|m| m.name == format!("reyes {}", reyes::gpu::KernelVariant::default()))
        .expect("the default variant is generated");
    let mandelbrot = generated_modules::examples()
        .into_iter()
        .find(|m| m.name == "mandelbrot")
        .expect("the Mandelbrot example is generated");
    for (name, module) in [("reyes_default", reyes_default), ("mandelbrot", mandelbrot)] {
        let translations = translate(&module).unwrap_or_else(|e| panic!("{name}: {e}"));
        insta::assert_snapshot!(format!("{name}_msl"), translations.msl);
        insta::assert_snapshot!(format!("{name}_hlsl"), translations.hlsl);
    }
}
