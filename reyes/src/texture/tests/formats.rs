//! Each format and channel layout loads to the expected linear values; the
//! colour spaces; deduplication; the errors, each naming the file.

use image::{ColorType, ImageFormat};

use super::*;

/// Channel value `k` (0-based) of texel `(x, y)` of the test images, as a
/// fraction of the channel's range: distinct per texel and channel.
fn fraction(x: u32, y: u32, k: u32) -> f64 {
    f64::from((x * 7 + y * 13 + k * 29) % 64 + 1) / 65.0
}

const W: u32 = 5;
const H: u32 = 3;

/// Writes a `W x H` image of `color` with [`fraction`] values (scaled to
/// the integer range) as `name` in `format`.
fn write_image(dir: &Path, name: &str, color: ColorType, format: ImageFormat) -> PathBuf {
    let channels = u32::from(color.channel_count());
    let per_channel = color.bytes_per_pixel() / color.channel_count();
    let mut bytes = Vec::new();
    for y in 0..H {
        for x in 0..W {
            for k in 0..channels {
                let f = fraction(x, y, k);
                match per_channel {
                    1 => bytes.push((f * 255.0).round() as u8),
                    2 => bytes.extend(((f * 65535.0).round() as u16).to_ne_bytes()),
                    _ => bytes.extend((f as f32 * 4.0).to_ne_bytes()),
                }
            }
        }
    }
    let path = dir.join(name);
    image::save_buffer_with_format(&path, &bytes, W, H, color, format).unwrap();
    path
}

/// The linear RGBA the loader should produce from [`write_image`]'s
/// texel, for a source of `channels` channels and `per_channel` bytes.
fn expected(x: u32, y: u32, channels: u32, per_channel: u8, srgb: bool) -> [f64; 4] {
    let value = |k: u32| match per_channel {
        1 => (fraction(x, y, k) * 255.0).round() / 255.0,
        2 => (fraction(x, y, k) * 65535.0).round() / 65535.0,
        _ => f64::from(fraction(x, y, k) as f32 * 4.0),
    };
    let decode = |c: f64| {
        if !srgb {
            c
        } else if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    match channels {
        1 => [decode(value(0)), decode(value(0)), decode(value(0)), 1.0],
        2 => [
            decode(value(0)),
            decode(value(0)),
            decode(value(0)),
            value(1),
        ],
        3 => [decode(value(0)), decode(value(1)), decode(value(2)), 1.0],
        _ => [
            decode(value(0)),
            decode(value(1)),
            decode(value(2)),
            value(3),
        ],
    }
}

fn check_image(set: &TextureSet, id: TextureId, color: ColorType, srgb: bool, what: &str) {
    let channels = u32::from(color.channel_count());
    let per_channel = color.bytes_per_pixel() / color.channel_count();
    let info = set.info(id).unwrap();
    assert_eq!((info.width, info.height, info.levels), (W, H, 3), "{what}");
    for y in 0..H {
        for x in 0..W {
            let got = stored(set, id, x, y);
            let want = expected(x, y, channels, per_channel, srgb);
            for k in 0..4 {
                assert_f16_close(got[k], want[k], &format!("{what} ({x}, {y}) channel {k}"));
            }
        }
    }
}

#[test]
fn every_format_and_layout_loads() {
    let dir = scratch("formats");
    let cases = [
        (ColorType::L8, ImageFormat::Png, "png"),
        (ColorType::La8, ImageFormat::Png, "png"),
        (ColorType::Rgb8, ImageFormat::Png, "png"),
        (ColorType::Rgba8, ImageFormat::Png, "png"),
        (ColorType::L16, ImageFormat::Png, "png"),
        (ColorType::La16, ImageFormat::Png, "png"),
        (ColorType::Rgb16, ImageFormat::Png, "png"),
        (ColorType::Rgba16, ImageFormat::Png, "png"),
        (ColorType::Rgb32F, ImageFormat::OpenExr, "exr"),
        (ColorType::Rgba32F, ImageFormat::OpenExr, "exr"),
        (ColorType::L8, ImageFormat::Tiff, "tif"),
        (ColorType::Rgb8, ImageFormat::Tiff, "tif"),
        (ColorType::Rgba8, ImageFormat::Tiff, "tif"),
        (ColorType::L16, ImageFormat::Tiff, "tif"),
        (ColorType::Rgb16, ImageFormat::Tiff, "tif"),
        (ColorType::Rgba16, ImageFormat::Tiff, "tiff"),
        (ColorType::Rgba32F, ImageFormat::Tiff, "tiff"),
    ];
    for (color, format, extension) in cases {
        let name = format!("{color:?}.{extension}");
        let path = write_image(&dir, &name, color, format);
        let mut set = TextureSet::default();
        // Auto: sRGB for 8-bit sources only.
        let eight_bit = color.bytes_per_pixel() / color.channel_count() == 1;
        let id = add(&mut set, &path, ColorSpace::Auto).unwrap();
        check_image(&set, id, color, eight_bit, &format!("{name}, auto"));
        // Explicitly linear: the values as stored.
        let id = add(&mut set, &path, ColorSpace::Linear).unwrap();
        check_image(&set, id, color, false, &format!("{name}, linear"));
    }
}

#[test]
fn half_float_exr_loads() {
    let dir = scratch("half");
    let path = dir.join("half.exr");
    let value =
        |x: usize, y: usize, k: usize| f16::from_f64(((x * 3 + y * 5 + k) as f64 - 4.0) * 0.37);
    exr::prelude::write_rgba_file(&path, 4, 3, |x, y| {
        (
            value(x, y, 0),
            value(x, y, 1),
            value(x, y, 2),
            value(x, y, 3),
        )
    })
    .unwrap();
    let mut set = TextureSet::default();
    let id = add(&mut set, &path, ColorSpace::Auto).unwrap();
    for y in 0..3 {
        for x in 0..4 {
            let got = stored(&set, id, x, y);
            for k in 0..4 {
                // Half in, half stored: exact, negative values included.
                assert_eq!(
                    got[k],
                    f32::from(value(x as usize, y as usize, k)),
                    "({x}, {y}) {k}"
                );
            }
        }
    }
}

#[test]
fn srgb_decoding_follows_the_formula() {
    let dir = scratch("srgb");
    // Every 8-bit code, with a constant alpha of 128 (never decoded).
    let bytes: Vec<u8> = (0..=255u8).flat_map(|c| [c, 255 - c, c / 2, 128]).collect();
    let path = dir.join("ramp.png");
    image::save_buffer(&path, &bytes, 256, 1, ColorType::Rgba8).unwrap();
    let mut set = TextureSet::default();
    let auto = add(&mut set, &path, ColorSpace::Auto).unwrap();
    let srgb = add(&mut set, &path, ColorSpace::Srgb).unwrap();
    let linear = add(&mut set, &path, ColorSpace::Linear).unwrap();
    // Auto decodes an 8-bit source as Srgb does.
    let formula = |c: u8| {
        let c = f64::from(c) / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    for x in 0..256u32 {
        let codes = [x as u8, 255 - x as u8, x as u8 / 2];
        for id in [auto, srgb] {
            let got = stored(&set, id, x, 0);
            for k in 0..3 {
                assert_f16_close(
                    got[k],
                    formula(codes[k]),
                    &format!("code {} channel {k}", codes[k]),
                );
            }
            assert_f16_close(got.w, 128.0 / 255.0, "alpha");
        }
        let got = stored(&set, linear, x, 0);
        assert_f16_close(got.x, f64::from(x) / 255.0, "linear");
    }
    // 16-bit sources decode only when told to.
    let path16 = dir.join("grey16.png");
    image::save_buffer(&path16, &40000u16.to_ne_bytes(), 1, 1, ColorType::L16).unwrap();
    let decoded = add(&mut set, &path16, ColorSpace::Srgb).unwrap();
    let plain = add(&mut set, &path16, ColorSpace::Auto).unwrap();
    let c = 40000.0 / 65535.0;
    assert_f16_close(
        stored(&set, decoded, 0, 0).x,
        ((c + 0.055) / 1.055f64).powf(2.4),
        "16-bit sRGB",
    );
    assert_f16_close(stored(&set, plain, 0, 0).x, c, "16-bit auto");
}

#[test]
fn sixteen_bit_sources_keep_more_than_eight_bits() {
    let dir = scratch("sixteen");
    // Consecutive 16-bit codes in the dark end (and some in the bright end),
    // where an 8-bit source could not tell them apart.
    let codes: Vec<u16> = (256..512).chain(60000..60256).collect();
    let bytes: Vec<u8> = codes.iter().flat_map(|c| c.to_ne_bytes()).collect();
    let path = dir.join("ramp16.png");
    image::save_buffer(&path, &bytes, codes.len() as u32, 1, ColorType::L16).unwrap();
    let mut set = TextureSet::default();
    let id = add(&mut set, &path, ColorSpace::Auto).unwrap();
    let values: Vec<f32> = (0..codes.len() as u32)
        .map(|x| stored(&set, id, x, 0).x)
        .collect();
    for (x, (&code, &got)) in codes.iter().zip(&values).enumerate() {
        assert_f16_close(
            got,
            f64::from(code) / 65535.0,
            &format!("code {code} at {x}"),
        );
    }
    // In the dark end f16 is finer than 1/65535: every code stays distinct.
    assert!(values[..256].windows(2).all(|w| w[0] < w[1]), "{values:?}");
    // Near 1, f16 keeps 11 significant bits: the 256 codes, one 8-bit step,
    // still take 8 distinct values.
    let mut bright = values[256..].to_vec();
    bright.dedup();
    assert!(bright.len() >= 8, "{} distinct values", bright.len());
}

#[test]
fn duplicates_share_ids_and_texels() {
    let dir = scratch("dedup");
    let path = write_image(&dir, "a.png", ColorType::Rgb8, ImageFormat::Png);
    let mut set = TextureSet::default();
    let first = set.add(&TextureDesc::new(&path)).unwrap();
    let bytes = set.packed_bytes();
    // The same file by another spelling of its path.
    let other_spelling = dir
        .join(".")
        .join("..")
        .join(dir.file_name().unwrap())
        .join("a.png");
    assert_eq!(set.add(&TextureDesc::new(&other_spelling)).unwrap(), first);
    assert_eq!(set.packed_bytes(), bytes);
    // Other wrap modes: a new id over the same texels.
    let clamped = set
        .add(&TextureDesc::new(&path).with_wrap(Wrap::Clamp))
        .unwrap();
    assert_ne!(clamped, first);
    assert_eq!(set.packed_bytes(), bytes);
    assert_eq!(
        set.info(clamped).unwrap().offset,
        set.info(first).unwrap().offset
    );
    assert_eq!(set.info(clamped).unwrap().wrap_s, Wrap::Clamp.code());
    // Another colour space: new texels.
    let linear = add(&mut set, &path, ColorSpace::Linear).unwrap();
    assert_eq!(set.packed_bytes(), 2 * bytes);
    assert_eq!(set.len(), 3);
    assert_eq!(set.path(linear), Some(path.as_path()));
    // 5 x 3, 2 x 1, 1 x 1.
    assert_eq!(bytes, (15 + 2 + 1) * TEXEL_BYTES);
}

#[test]
fn a_missing_file_is_named() {
    let dir = scratch("missing");
    let path = dir.join("nowhere").join("wood.png");
    let error = TextureSet::default()
        .add(&TextureDesc::new(&path))
        .unwrap_err();
    assert!(
        matches!(&error, TextureError::Missing { path: p } if *p == path),
        "{error:?}"
    );
    assert_eq!(error.path(), path);
    assert!(error.to_string().contains("wood.png"), "{error}");
}

#[test]
fn corrupt_files_are_decode_errors_naming_the_file() {
    let dir = scratch("corrupt");
    let good = write_image(&dir, "good.png", ColorType::Rgb8, ImageFormat::Png);
    let bytes = std::fs::read(&good).unwrap();
    let truncated = dir.join("truncated.png");
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
    let text = dir.join("text.png");
    std::fs::write(&text, "not an image").unwrap();
    let bmp = dir.join("image.bmp");
    std::fs::write(&bmp, b"BM\x3a\0\0\0\0\0\0\0\x36\0\0\0").unwrap();
    for path in [truncated, text, bmp] {
        let error = TextureSet::default()
            .add(&TextureDesc::new(&path))
            .unwrap_err();
        assert!(
            matches!(&error, TextureError::Decode { .. }),
            "{path:?}: {error:?}"
        );
        assert_eq!(error.path(), path);
        let name = path.file_name().unwrap().to_str().unwrap();
        assert!(error.to_string().contains(name), "{error}");
    }
    // A directory is refused by the input layer, and named too.
    let error = TextureSet::default()
        .add(&TextureDesc::new(&dir))
        .unwrap_err();
    assert!(matches!(&error, TextureError::Input(_)), "{error:?}");
    assert_eq!(error.path(), dir);
}

#[test]
fn non_finite_texels_are_refused() {
    let dir = scratch("nonfinite");
    let path = dir.join("nan.exr");
    exr::prelude::write_rgba_file(&path, 3, 2, |x, y| {
        let v = if (x, y) == (2, 1) { f32::NAN } else { 0.5 };
        (v, 0.5f32, 0.5f32, 1.0f32)
    })
    .unwrap();
    let error = TextureSet::default()
        .add(&TextureDesc::new(&path))
        .unwrap_err();
    assert!(
        matches!(error, TextureError::NonFinite { x: 2, y: 1, .. }),
        "{error:?}"
    );
    assert!(error.to_string().contains("nan.exr"), "{error}");
}

#[test]
fn over_budget_is_refused_before_decoding_naming_the_sizes() {
    let dir = scratch("budget");
    let path = dir.join("big.png");
    image::save_buffer(&path, &vec![7u8; 64 * 64], 64, 64, ColorType::L8).unwrap();
    // 64 x 64 with its chain: 5461 texels, 43688 bytes.
    let needed = mipmap::chain_texels(64, 64) * TEXEL_BYTES;
    assert_eq!(needed, 43688);
    let mut set = TextureSet::new(TextureBudget { bytes: needed });
    let first = set.add(&TextureDesc::new(&path)).unwrap();
    // A second chain does not fit; the same texture again needs nothing.
    assert_eq!(set.add(&TextureDesc::new(&path)).unwrap(), first);
    let error = add(&mut set, &path, ColorSpace::Linear).unwrap_err();
    match &error {
        TextureError::OverBudget {
            path: p,
            needed: n,
            used,
            budget,
        } => assert_eq!((p, *n, *used, *budget), (&path, needed, needed, needed)),
        other => panic!("{other:?}"),
    }
    let message = error.to_string();
    assert!(
        message.contains("big.png") && message.contains("43688 bytes"),
        "{message}"
    );
    // The failed add changed nothing.
    assert_eq!((set.len(), set.packed_bytes()), (1, needed));
    // The check comes from the header alone: a file whose pixel data is
    // garbage is refused for its size, not for its data.
    let mut header_only = std::fs::read(&path).unwrap();
    let cut = header_only.len() - 20;
    header_only.truncate(cut);
    let broken = dir.join("broken.png");
    std::fs::write(&broken, &header_only).unwrap();
    let error = TextureSet::new(TextureBudget { bytes: 1000 })
        .add(&TextureDesc::new(&broken))
        .unwrap_err();
    assert!(
        matches!(error, TextureError::OverBudget { .. }),
        "{error:?}"
    );
}

#[test]
fn oversized_images_are_refused_from_the_header() {
    let dir = scratch("large");
    let path = dir.join("wide.png");
    let width = MAX_TEXTURE_SIDE + 1;
    image::save_buffer(&path, &vec![0u8; width as usize], width, 1, ColorType::L8).unwrap();
    let error = TextureSet::default()
        .add(&TextureDesc::new(&path))
        .unwrap_err();
    assert!(
        matches!(error, TextureError::TooLarge { width: w, height: 1, max: MAX_TEXTURE_SIDE, .. } if w == width),
        "{error:?}"
    );
    assert!(error.to_string().contains("wide.png"), "{error}");
}

#[test]
fn descriptions_read_renderman_names() {
    let desc: TextureDesc = toml::from_str(
        "path = \"wood.tif\"\ncolor_space = \"srgb\"\nwrap_s = \"black\"\nwrap_t = \"clamp\"",
    )
    .unwrap();
    assert_eq!(
        desc,
        TextureDesc {
            path: "wood.tif".into(),
            color_space: ColorSpace::Srgb,
            wrap_s: Wrap::Black,
            wrap_t: Wrap::Clamp,
        }
    );
    let plain: TextureDesc = toml::from_str("path = \"a.png\"").unwrap();
    assert_eq!(plain, TextureDesc::new("a.png"));
    assert!(toml::from_str::<TextureDesc>("path = \"a.png\"\nwrap_s = \"repeat\"").is_err());
}
