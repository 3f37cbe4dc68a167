//! The per-object GPU table (surface, motion and displacement parameters, twin of the
//! WGSL `Object` struct) and the layout of the scene's height maps in the
//! `height_texels` buffer.

use std::sync::Arc;

use super::abi::{displace, surface};
use crate::shading::PreparedSurface;
use crate::displacement::{HeightMap, HeightSource};
use crate::prepare::PreparedScene;

/// One object, WGSL struct `Object`.
#[scheduler::item]
#[wgsl(name = "Object")]
#[derive(Debug, PartialEq)]
pub struct ObjectData {
    /// Linear RGB colour, RenderMan's `Cs` (w unused).
    pub color: glam::Vec4,
    /// `plastic`'s `specularcolor` (w unused).
    pub specular_color: glam::Vec4,
    /// DISPLACE_NONE, DISPLACE_IMAGE, DISPLACE_SINES or
    /// DISPLACE_SHADER ([`displace`]).
    pub displace_kind: u32,
    /// First texel of the object's height map in the texel buffer.
    pub map_offset: u32,
    /// Height-map width in texels.
    pub map_width: u32,
    /// Height-map height in texels.
    pub map_height: u32,
    /// World units per unit of height (a shader's: the factor on its offset).
    pub displace_scale: f32,
    /// Displacement bound in world units (0 without displacement).
    pub displace_bound: f32,
    /// Repetitions of the source per patch.
    pub tiling: f32,
    /// [`crate::prepare::PreparedObject::front`]: the sign of the front's
    /// `dP/du x dP/dv` for a one-sided object, 0 for a two-sided one.
    pub front: f32,
    /// Open to close world positions ([`crate::motion::ObjectMotion::matrix`]);
    /// identity when the object does not move.
    pub motion: glam::Mat4,
    /// 1 when the object moves.
    pub moving: u32,
    /// [`crate::motion::ObjectMotion::stretch`] (1 when not moving).
    pub motion_stretch: f32,
    /// The surface shader, SURFACE_* ([`surface`]).
    pub surface: u32,
    /// `roughness` (`metal`, `plastic`).
    pub roughness: f32,
    /// `Ka`.
    pub ka: f32,
    /// `Kd`.
    pub kd: f32,
    /// `Ks`.
    pub ks: f32,
    /// The side of a micropolygon at the object's shading rate, in pixels
    /// ([`crate::prepare::PreparedScene::object_dicing`]).
    pub micropolygon_side: f32,
    /// The object's dice threshold in pixels.
    pub dice_threshold: f32,
    /// A user shader's index (SURFACE_USER).
    pub user_shader: u32,
    /// The first of a user shader's parameter slots (FrameUniform::parameter_floats).
    pub parameters: u32,
    /// A displacement shader's index (DISPLACE_SHADER).
    pub displace_shader: u32,
    /// The first of a displacement shader's parameter slots.
    pub displace_parameters: u32,
    /// [`crate::displacement::ShaderDisplacement::orientation`] (1 for
    /// other sources).
    pub displace_orientation: f32,
    /// 1 when the object's patches are stored shared, in model space
    /// ([`crate::prepare::PreparedObject::placement`]).
    pub placed: u32,
    /// Padding.
    pub pad3: u32,
    /// The model-to-world matrix of shared patches (identity otherwise).
    pub placement: glam::Mat4,
}

impl ObjectData {
    /// Stores `prepared`'s code and parameters (unused ones stay 0).
    fn set_surface(&mut self, prepared: &PreparedSurface) {
        self.surface = surface::code(prepared);
        match *prepared {
            PreparedSurface::Constant => {}
            PreparedSurface::Matte { ka, kd } | PreparedSurface::DefaultSurface { ka, kd } => {
                (self.ka, self.kd) = (ka, kd);
            }
            PreparedSurface::Metal { ka, ks, roughness } => {
                (self.ka, self.ks, self.roughness) = (ka, ks, roughness);
            }
            PreparedSurface::Plastic {
                ka,
                kd,
                ks,
                roughness,
                specular_color,
            } => {
                (self.ka, self.kd, self.ks, self.roughness) = (ka, kd, ks, roughness);
                self.specular_color = specular_color.extend(0.0);
            }
            PreparedSurface::User { shader, parameters } => {
                (self.user_shader, self.parameters) = (shader, parameters);
            }
        }
    }
}

/// The objects' GPU data and the height maps they use, concatenated.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjectTables {
    /// One entry per object.
    pub objects: Vec<ObjectData>,
    /// The distinct height maps, in the order their texels are laid out.
    pub maps: Vec<Arc<HeightMap>>,
    /// Total texels of `maps`.
    pub texels: usize,
}

impl ObjectTables {
    /// Builds the tables of `scene`; a map shared by several objects (the
    /// same `Arc`) is stored once.
    pub fn new(scene: &PreparedScene) -> Self {
        let mut maps: Vec<Arc<HeightMap>> = Vec::new();
        let mut offsets: Vec<usize> = Vec::new();
        let mut texels = 0usize;
        let objects = scene
            .objects
            .iter()
            .map(|object| {
                let dicing = scene.object_dicing(object);
                let mut data = ObjectData {
                    color: object.color.extend(0.0),
                    specular_color: glam::Vec4::ZERO,
                    displace_kind: displace::NONE,
                    map_offset: 0,
                    map_width: 0,
                    map_height: 0,
                    displace_scale: 0.0,
                    displace_bound: 0.0,
                    tiling: 1.0,
                    front: object.front.unwrap_or(0.0),
                    motion: glam::Mat4::IDENTITY,
                    moving: 0,
                    motion_stretch: 1.0,
                    surface: surface::CONSTANT,
                    roughness: 0.0,
                    ka: 0.0,
                    kd: 0.0,
                    ks: 0.0,
                    micropolygon_side: dicing.micropolygon_side(),
                    dice_threshold: dicing.dice_threshold(),
                    user_shader: 0,
                    parameters: 0,
                    displace_shader: 0,
                    displace_parameters: 0,
                    displace_orientation: 1.0,
                    placed: u32::from(object.placement.is_some()),
                    pad3: 0,
                    placement: object.placement.unwrap_or(glam::Mat4::IDENTITY),
                };
                if let Some(prepared) = &object.surface {
                    data.set_surface(prepared);
                }
                if let Some(motion) = &object.motion {
                    data.motion = motion.matrix;
                    data.moving = 1;
                    data.motion_stretch = motion.stretch;
                }
                let Some(d) = &object.displacement else {
                    return data;
                };
                data.displace_scale = d.scale;
                data.displace_bound = d.bound;
                data.tiling = d.tiling;
                data.displace_kind = match &d.source {
                    HeightSource::Image(map) => {
                        let index = maps.iter().position(|m| Arc::ptr_eq(m, map));
                        let index = index.unwrap_or_else(|| {
                            maps.push(map.clone());
                            offsets.push(texels);
                            texels += map.texels.len();
                            maps.len() - 1
                        });
                        // Texel counts are bounded by the device check in the renderer.
                        data.map_offset = offsets[index] as u32;
                        data.map_width = map.width;
                        data.map_height = map.height;
                        displace::IMAGE
                    }
                    HeightSource::Sines => displace::SINES,
                    HeightSource::Shader(shader) => {
                        data.displace_shader = shader.reference.shader;
                        data.displace_parameters = shader.reference.parameters;
                        data.displace_orientation = shader.orientation;
                        displace::SHADER
                    }
                };
                data
            })
            .collect();
        Self {
            objects,
            maps,
            texels,
        }
    }

    /// Bytes of the texel buffer (at least one texel: a binding may not be empty).
    pub fn texel_bytes(&self) -> u64 {
        4 * self.texels.max(1) as u64
    }

    /// Whether the maps are the same `Arc`s in the same order (no re-upload needed).
    pub fn same_maps(&self, other: &Self) -> bool {
        self.maps.len() == other.maps.len()
            && self
                .maps
                .iter()
                .zip(&other.maps)
                .all(|(a, b)| Arc::ptr_eq(a, b))
    }
}
