//! The GPU layout of a [`super::TextureSet`]: one [`TextureInfo`] per
//! texture and the texels of every mip chain in one flat buffer, read by
//! `texture_sample` in `shaders/reyes/library_texture.wgsl`.

/// `shaders/reyes/library_texture.wgsl`: `texture_sample` and its helpers.
/// The module using it declares the [`TextureInfo`] struct
/// (`TextureInfo::wgsl_declarations()`, or a graph resource of
/// `[TextureInfo]`) and two read-only storage buffers,
/// `texture_infos: array<TextureInfo>` and `texels: array<vec2<u32>>`.
pub const TEXTURE_WGSL: &str = include_str!("../../../shaders/reyes/library_texture.wgsl");

/// One texture, WGSL struct `TextureInfo` (32 bytes).
///
/// Level `k` starts at texel `offset + sum of the sizes of levels 0..k` of
/// the texel buffer; its size follows from `width` and `height`
/// (`super::mipmap`), so the WGSL walks the levels instead of reading a
/// second table.
#[scheduler::item]
#[wgsl(name = "TextureInfo")]
#[derive(Debug, PartialEq, Eq)]
pub struct TextureInfo {
    /// First texel of level 0 in the texel buffer.
    pub offset: u32,
    /// Level-0 width in texels.
    pub width: u32,
    /// Level-0 height in texels.
    pub height: u32,
    /// Number of mip levels (down to 1 x 1).
    pub levels: u32,
    /// Wrap mode along s, [`super::Wrap::code`].
    pub wrap_s: u32,
    /// Wrap mode along t, [`super::Wrap::code`].
    pub wrap_t: u32,
    /// Padding (to 32 bytes).
    pub pad0: u32,
    /// Padding.
    pub pad1: u32,
}

impl TextureInfo {
    /// The entry of a frame without textures: a 1 x 1 texture whose only
    /// texel is [`DUMMY_TEXELS`]' (transparent black), so that no buffer is
    /// empty.
    pub const DUMMY: TextureInfo = TextureInfo {
        offset: 0,
        width: 1,
        height: 1,
        levels: 1,
        wrap_s: 0,
        wrap_t: 0,
        pad0: 0,
        pad1: 0,
    };
}

/// The texel buffer of a frame without textures: one zero texel.
pub const DUMMY_TEXELS: &[[u32; 2]] = &[[0, 0]];
