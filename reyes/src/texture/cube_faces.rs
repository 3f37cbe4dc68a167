//! Cube-face environment maps (RenderMan's `MakeCubeFaceEnvironment`):
//! six pictures looking along the world axes, resampled into one
//! latitude-longitude map ([`super::environment`]), which `environment()`
//! reads as it reads any.
//!
//! The faces are the RenderMan Interface Specification 3.2's: picture `px`
//! looks along +x with +y up and -z to the right, and so on ([`FACES`]),
//! each with the full horizontal field of view `fov` (90 degrees: the
//! faces meet at their edges; more: they overlap, and each direction takes
//! the face it looks most straight into). A direction of the
//! latitude-longitude map, `(cos lon cos lat, sin lon cos lat, sin lat)`,
//! is projected into that face and read bilinearly there (texel centres
//! at half-integers, clamped at the edges).

use std::f32::consts::{PI, TAU};
use std::path::Path;

use glam::{Vec3, Vec4};

use super::load::{LinearImage, decode, read};
use super::{ColorSpace, TextureError};

/// The largest face side read (a face of 4096 x 4096 float texels is
/// 256 MiB, six of them 1.5 GiB).
pub const MAX_FACE_SIDE: u32 = 4096;

/// The widest latitude-longitude map made (4096 x 2048 texels, 128 MiB).
pub const MAX_LATLONG_WIDTH: u32 = 4096;

/// One face of the cube: where its picture looks, which way is up in it,
/// and which way is right (RenderMan's table for `MakeCubeFaceEnvironment`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceAxes {
    /// The direction the picture looks along.
    pub forward: Vec3,
    /// The direction of its top.
    pub up: Vec3,
    /// The direction of its right edge.
    pub right: Vec3,
}

/// The faces in the request's order: `px nx py ny pz nz`.
pub const FACES: [FaceAxes; 6] = [
    FaceAxes {
        forward: Vec3::X,
        up: Vec3::Y,
        right: Vec3::NEG_Z,
    },
    FaceAxes {
        forward: Vec3::NEG_X,
        up: Vec3::Y,
        right: Vec3::Z,
    },
    FaceAxes {
        forward: Vec3::Y,
        up: Vec3::NEG_Z,
        right: Vec3::X,
    },
    FaceAxes {
        forward: Vec3::NEG_Y,
        up: Vec3::Z,
        right: Vec3::X,
    },
    FaceAxes {
        forward: Vec3::Z,
        up: Vec3::Y,
        right: Vec3::X,
    },
    FaceAxes {
        forward: Vec3::NEG_Z,
        up: Vec3::Y,
        right: Vec3::NEG_X,
    },
];

/// The faces' names in the request's order, for messages.
pub const FACE_NAMES: [&str; 6] = ["px", "nx", "py", "ny", "pz", "nz"];

/// A face's picture: linear RGBA, row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub struct FacePicture {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// The texels.
    pub texels: Vec<Vec4>,
}

impl FacePicture {
    /// Reads the picture at `path` (PNG, OpenEXR or TIFF, as textures are
    /// read; 8-bit pictures are taken as sRGB, others as linear), at most
    /// [`MAX_FACE_SIDE`] on a side.
    pub fn read(path: &Path) -> Result<FacePicture, TextureError> {
        let bytes = read(path)?;
        let admit = |width: u32, height: u32| {
            if width > MAX_FACE_SIDE || height > MAX_FACE_SIDE {
                return Err(TextureError::TooLarge {
                    path: path.to_path_buf(),
                    width,
                    height,
                    max: MAX_FACE_SIDE,
                });
            }
            Ok(())
        };
        let (
            LinearImage {
                width,
                height,
                texels,
            },
            _,
        ) = decode(&bytes, path, ColorSpace::Auto, admit)?;
        Ok(FacePicture {
            width,
            height,
            texels,
        })
    }

    /// The bilinear reading at continuous texel coordinates `(x, y)`,
    /// clamped to the edges.
    fn bilinear(&self, x: f32, y: f32) -> Vec4 {
        let at = |i: i64, j: i64| {
            let i = i.clamp(0, i64::from(self.width) - 1) as usize;
            let j = j.clamp(0, i64::from(self.height) - 1) as usize;
            self.texels[j * self.width as usize + i]
        };
        let (x, y) = (x - 0.5, y - 0.5);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (i, j) = (x0 as i64, y0 as i64);
        let top = at(i, j).lerp(at(i + 1, j), fx);
        let bottom = at(i, j + 1).lerp(at(i + 1, j + 1), fx);
        top.lerp(bottom, fy)
    }
}

/// What the cube of `faces` (in [`FACES`]' order), each taken with the
/// full horizontal field of view `fov_degrees`, shows along the direction
/// `d` (not zero).
pub fn cube_lookup(faces: &[FacePicture; 6], fov_degrees: f32, d: Vec3) -> Vec4 {
    let (index, axes) = FACES
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.forward.dot(d).total_cmp(&b.1.forward.dot(d)))
        .expect("six faces");
    let face = &faces[index];
    let depth = axes.forward.dot(d);
    let half = (0.5 * fov_degrees.to_radians()).tan();
    // Where d meets the picture plane one unit ahead, in units of its
    // half width (and of its half height, for a picture as high as its
    // aspect makes it).
    let x = d.dot(axes.right) / depth / half;
    let aspect = face.height as f32 / face.width as f32;
    let y = d.dot(axes.up) / depth / (half * aspect);
    face.bilinear(
        (0.5 + 0.5 * x) * face.width as f32,
        (0.5 - 0.5 * y) * face.height as f32,
    )
}

/// The latitude-longitude map of the cube of `faces`: `2 n x n` texels for
/// faces `n / 2` texels wide (at most [`MAX_LATLONG_WIDTH`] wide), each the
/// cube's reading along its centre's direction.
pub fn latlong_from_faces(faces: &[FacePicture; 6], fov_degrees: f32) -> FacePicture {
    let face_width = faces.iter().map(|f| f.width).max().unwrap_or(1);
    let width = (4 * face_width).clamp(2, MAX_LATLONG_WIDTH);
    let height = (width / 2).max(1);
    let texels = (0..width * height)
        .map(|k| {
            let (i, j) = (k % width, k / width);
            let longitude = TAU * (i as f32 + 0.5) / width as f32;
            let latitude = 0.5 * PI - PI * (j as f32 + 0.5) / height as f32;
            let d = Vec3::new(
                longitude.cos() * latitude.cos(),
                longitude.sin() * latitude.cos(),
                latitude.sin(),
            );
            cube_lookup(faces, fov_degrees, d)
        })
        .collect();
    FacePicture {
        width,
        height,
        texels,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A face of one colour, `side` texels square.
    fn plain(side: u32, color: Vec4) -> FacePicture {
        FacePicture {
            width: side,
            height: side,
            texels: vec![color; (side * side) as usize],
        }
    }

    fn colour(k: usize) -> Vec4 {
        Vec4::new(
            k as f32 / 8.0,
            1.0 - k as f32 / 8.0,
            0.25 * (k % 3) as f32,
            1.0,
        )
    }

    /// Each axis reads its own face, and the map's picture puts each face
    /// where the specification's latitude-longitude convention puts its
    /// direction: +z at the top, -z at the bottom, +x at longitude 0, +y
    /// at 90 degrees.
    #[test]
    fn each_axis_reads_its_face_and_the_map_puts_it_at_its_longitude() {
        let faces: [FacePicture; 6] = std::array::from_fn(|k| plain(8, colour(k)));
        for (k, axes) in FACES.iter().enumerate() {
            assert_eq!(
                cube_lookup(&faces, 90.0, axes.forward),
                colour(k),
                "{}",
                FACE_NAMES[k]
            );
        }
        let map = latlong_from_faces(&faces, 90.0);
        assert_eq!((map.width, map.height), (32, 16));
        let at = |s: f32, t: f32| {
            let (i, j) = (
                (s * map.width as f32) as u32,
                (t * map.height as f32) as u32,
            );
            map.texels[(j * map.width + i) as usize]
        };
        assert_eq!(at(0.0, 0.5), colour(0), "+x at longitude 0 on the equator");
        assert_eq!(at(0.25, 0.5), colour(2), "+y at 90 degrees");
        assert_eq!(at(0.5, 0.5), colour(1), "-x at 180 degrees");
        assert_eq!(at(0.75, 0.5), colour(3), "-y at 270 degrees");
        assert_eq!(at(0.3, 0.0), colour(4), "+z at the top");
        assert_eq!(at(0.6, 0.99), colour(5), "-z at the bottom");
    }

    /// Within a face, up and right are the specification's: for each face,
    /// a direction a little towards its `right` reads the right half of its
    /// picture, and one a little towards its `up` the top half.
    #[test]
    fn within_a_face_up_and_right_are_the_specifications() {
        let (left, right, top, bottom) = (
            Vec4::new(1.0, 0.0, 0.0, 1.0),
            Vec4::new(0.0, 1.0, 0.0, 1.0),
            Vec4::new(0.0, 0.0, 1.0, 1.0),
            Vec4::new(1.0, 1.0, 0.0, 1.0),
        );
        // Quadrants: left or right half by column, top or bottom by row,
        // summed so that each reading names both.
        let quadrants = FacePicture {
            width: 16,
            height: 16,
            texels: (0..256)
                .map(|k| {
                    let (x, y) = (k % 16, k / 16);
                    (if x < 8 { left } else { right }) + (if y < 8 { top } else { bottom })
                })
                .collect(),
        };
        let faces: [FacePicture; 6] = std::array::from_fn(|_| quadrants.clone());
        for (k, axes) in FACES.iter().enumerate() {
            let d = axes.forward + 0.5 * axes.right + 0.5 * axes.up;
            assert_eq!(
                cube_lookup(&faces, 90.0, d),
                right + top,
                "{}",
                FACE_NAMES[k]
            );
            let d = axes.forward - 0.5 * axes.right - 0.5 * axes.up;
            assert_eq!(
                cube_lookup(&faces, 90.0, d),
                left + bottom,
                "{}",
                FACE_NAMES[k]
            );
        }
        // The table is a right-handed frame for none of them: RenderMan's
        // camera space is left-handed (right = up x forward).
        for axes in FACES {
            assert_eq!(axes.up.cross(axes.forward), axes.right);
        }
    }

    /// A wider field of view shrinks each face's share of a direction: the
    /// edge of a 90-degree face is read a quarter of the way in from the
    /// edge of a face rendered at 2 atan(2) (its half-width tangent 2).
    #[test]
    fn the_field_of_view_scales_the_face() {
        let ramp = FacePicture {
            width: 64,
            height: 64,
            texels: (0..64 * 64)
                .map(|k| Vec4::splat((k % 64) as f32 + 0.5))
                .collect(),
        };
        let faces: [FacePicture; 6] = std::array::from_fn(|_| ramp.clone());
        let fov = 2.0 * 2f32.atan().to_degrees();
        // Along pz's forward + right (x = 1 unit ahead at one unit across).
        let d = FACES[4].forward + 0.999 * FACES[4].right;
        let x = cube_lookup(&faces, fov, d.normalize()).x;
        assert!((x - 0.75 * 64.0).abs() < 0.1, "read at column {x}");
    }
}
