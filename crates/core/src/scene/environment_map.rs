//! Environment maps for reflection and refraction (Zhang & Pajarola §5.2.3):
//! an equirectangular (latitude-longitude) image around the scene.
//!
//! Loading goes through the `image` crate: OpenEXR (the DWAB-compressed
//! Poly Haven maps decode with its `exr` feature), Radiance `.hdr`, PNG and
//! JPEG. Every texel is cleaned once: DWAB leaves small negative values and a
//! broken file may hold NaN or Inf, all of which become 0. The rest of
//! pointblend blends display-encoded colours (8-bit splat colours, an 8-bit
//! output), so a linear HDR map is encoded with the sRGB curve (extended as a
//! power above 1, so a sun of 1e5 stays finite: about 128); PNG and JPEG are
//! display-encoded already and kept as they are.
//!
//! The map is pre-filtered into a mip chain (2x2 box averages down to one
//! texel), so a minified lookup reads an average rather than aliasing.
//! [`EnvironmentMap::sample`] is the lookup the GPU's sampler makes (bilinear
//! within a level, linear between levels, the longitude wrapping across the
//! ±180° meridian, the latitude clamped at the poles), so the CPU reference
//! and the GPU modes see the same environment.

use std::path::Path;

use glam::Vec3;

/// One level of the mip chain: `width` x `height` RGB texels, row by row from the top (up).
#[derive(Debug, Clone, PartialEq)]
pub struct EnvLevel {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<[f32; 3]>,
}

/// An equirectangular environment map and its mip chain.
#[derive(Debug, Clone, PartialEq)]
pub struct EnvironmentMap {
    /// The file name (or a description), for messages and plans.
    pub name: String,
    /// Level 0 is the map itself; each next level halves both sizes (at least 1).
    pub levels: Vec<EnvLevel>,
    /// Texels that were negative, NaN or Inf and became 0.
    pub cleaned: usize,
    /// FNV-1a of level 0's texels, for caches keyed by what the map holds.
    pub hash: u64,
}

/// Why an environment map could not be used.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {problem}")]
pub struct EnvError {
    pub path: String,
    pub problem: String,
}

/// The largest value a GPU copy (half float) holds; texels are capped here
/// so the CPU samples what the GPU does.
pub const LARGEST: f32 = 65504.0;

impl EnvironmentMap {
    /// Loads `path` (OpenEXR, Radiance HDR, PNG or JPEG, by content).
    pub fn load(path: &Path) -> Result<Self, EnvError> {
        let fail = |problem: String| EnvError { path: path.display().to_string(), problem };
        crate::input::regular_size(path).map_err(|e| fail(format!("cannot open: {e}")))?;
        let reader = image::ImageReader::open(path).map_err(|e| fail(format!("cannot open: {e}")))?;
        let reader = reader.with_guessed_format().map_err(|e| fail(format!("cannot read: {e}")))?;
        let format = reader.format();
        let decoded = reader.decode().map_err(|e| fail(format!("not a readable environment map: {e}")))?;
        let linear = matches!(format, Some(image::ImageFormat::OpenExr | image::ImageFormat::Hdr));
        let (width, height) = (decoded.width(), decoded.height());
        let rgb = decoded.into_rgb32f();
        let texels = rgb
            .pixels()
            .map(|p| {
                let c = [p.0[0], p.0[1], p.0[2]];
                if linear { c.map(encode_linear) } else { c }
            })
            .collect();
        let name = path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned());
        Self::from_texels(name, width, height, texels).map_err(fail)
    }

    /// A map of display-encoded `texels` (`width` x `height`, row by row from
    /// the top), cleaned and pre-filtered.
    pub fn from_texels(name: String, width: u32, height: u32, texels: Vec<[f32; 3]>) -> Result<Self, String> {
        if width < 2 || height < 1 {
            return Err(format!("a {width}x{height} map has too few pixels (at least 2x1 are needed)"));
        }
        if texels.len() as u64 != width as u64 * height as u64 {
            return Err(format!("{} texels for a {width}x{height} map", texels.len()));
        }
        let mut cleaned = 0;
        let texels: Vec<[f32; 3]> = texels
            .into_iter()
            .map(|c| {
                c.map(|v| {
                    if v.is_finite() && v >= 0.0 {
                        v.min(LARGEST)
                    } else {
                        cleaned += 1;
                        0.0
                    }
                })
            })
            .collect();
        let bytes: Vec<u8> = texels.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
        let hash = crate::hash::fnv1a(crate::hash::FNV_OFFSET, &bytes);
        let mut levels = vec![EnvLevel { width, height, texels }];
        while let Some(last) = levels.last().filter(|l| l.width > 1 || l.height > 1) {
            levels.push(last.halved());
        }
        Ok(Self { name, levels, cleaned, hash })
    }

    /// A map of one colour everywhere (display-encoded).
    pub fn constant(colour: [f32; 3]) -> Self {
        Self::from_texels("constant".into(), 2, 1, vec![colour; 2]).unwrap_or_else(|_| unreachable!("2x1 is valid"))
    }

    pub fn width(&self) -> u32 {
        self.levels[0].width
    }

    pub fn height(&self) -> u32 {
        self.levels[0].height
    }

    /// The colour seen along `direction` (world space; the map's up is `up`,
    /// its centre column looks along `front`), at mip level `lod` (0: the
    /// map itself; fractional levels blend two).
    pub fn sample(&self, direction: Vec3, (up, front): (Vec3, Vec3), lod: f32) -> [f32; 3] {
        let (u, v) = direction_uv(direction, up, front);
        let top = (self.levels.len() - 1) as f32;
        let lod = if lod.is_finite() { lod.clamp(0.0, top) } else { 0.0 };
        let (below, t) = (lod.floor() as usize, lod.fract());
        let a = self.levels[below].bilinear(u, v);
        if t == 0.0 {
            return a;
        }
        let b = self.levels[(below + 1).min(self.levels.len() - 1)].bilinear(u, v);
        [0, 1, 2].map(|k| a[k] + (b[k] - a[k]) * t)
    }
}

impl EnvLevel {
    /// The next mip level: 2x2 box averages (an odd last row or column is
    /// averaged with itself).
    fn halved(&self) -> EnvLevel {
        let (w, h) = ((self.width / 2).max(1), (self.height / 2).max(1));
        let at = |x: u32, y: u32| self.texels[(y.min(self.height - 1) * self.width + x.min(self.width - 1)) as usize];
        let texels = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| {
                let (x0, y0) = (x * 2, y * 2);
                let (x1, y1) = (if self.width > 1 { x0 + 1 } else { x0 }, if self.height > 1 { y0 + 1 } else { y0 });
                let quad = [at(x0, y0), at(x1, y0), at(x0, y1), at(x1, y1)];
                [0, 1, 2].map(|k| quad.iter().map(|c| c[k]).sum::<f32>() * 0.25)
            })
            .collect();
        EnvLevel { width: w, height: h, texels }
    }

    /// Bilinear lookup at (u, v) in 0..1, texel centres at (i + 0.5)/size:
    /// u wraps around (the ±180° meridian has no seam), v clamps at the poles.
    fn bilinear(&self, u: f32, v: f32) -> [f32; 3] {
        let (w, h) = (self.width as i64, self.height as i64);
        let x = u * w as f32 - 0.5;
        let y = (v * h as f32 - 0.5).clamp(0.0, (h - 1) as f32);
        let (x0, y0) = (x.floor(), y.floor());
        let (tx, ty) = (x - x0, y - y0);
        let column = |i: i64| i.rem_euclid(w);
        let row = |j: i64| j.clamp(0, h - 1);
        let texel = |i: i64, j: i64| self.texels[(row(j) * w + column(i)) as usize];
        let (i, j) = (x0 as i64, y0 as i64);
        let (a, b, c, d) = (texel(i, j), texel(i + 1, j), texel(i, j + 1), texel(i + 1, j + 1));
        [0, 1, 2].map(|k| {
            let top = a[k] + (b[k] - a[k]) * tx;
            let bottom = c[k] + (d[k] - c[k]) * tx;
            top + (bottom - top) * ty
        })
    }
}

/// (u, v) of a direction on an equirectangular map whose up is `up` and whose
/// centre column (u = 0.5) looks along `front`: u from the longitude, v from
/// the angle to `up` (0 at the top). A zero or non-finite direction looks along `front`.
pub fn direction_uv(direction: Vec3, up: Vec3, front: Vec3) -> (f32, f32) {
    let d = direction.normalize_or_zero();
    let d = if d == Vec3::ZERO || !d.is_finite() { front } else { d };
    let right = up.cross(front);
    let longitude = d.dot(right).atan2(d.dot(front));
    let u = 0.5 + longitude / std::f32::consts::TAU;
    let v = d.dot(up).clamp(-1.0, 1.0).acos() / std::f32::consts::PI;
    (u, v)
}

/// A linear value encoded with the sRGB curve, as a power above 1 (so HDR
/// values stay ordered and finite); negative and non-finite values are left
/// for cleaning.
fn encode_linear(v: f32) -> f32 {
    if !(v.is_finite() && v >= 0.0) {
        v
    } else if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_chain_halves_down_to_one_texel_and_keeps_the_mean() {
        let texels: Vec<[f32; 3]> = (0..8 * 4).map(|i| [i as f32, 1.0, 0.0]).collect();
        let mean = texels.iter().map(|c| c[0]).sum::<f32>() / texels.len() as f32;
        let map = EnvironmentMap::from_texels("t".into(), 8, 4, texels).unwrap();
        let sizes: Vec<(u32, u32)> = map.levels.iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, [(8, 4), (4, 2), (2, 1), (1, 1)]);
        let top = map.levels.last().unwrap().texels[0];
        assert!((top[0] - mean).abs() < 1e-4 && top[1] == 1.0, "{top:?} against {mean}");
    }

    #[test]
    fn bad_texels_become_zero_and_are_counted() {
        let map = EnvironmentMap::from_texels("t".into(), 2, 1, vec![[-0.5, f32::NAN, 1e9], [f32::INFINITY, 0.5, 2.0]])
            .unwrap();
        assert_eq!(map.cleaned, 3);
        assert_eq!(map.levels[0].texels, vec![[0.0, 0.0, LARGEST], [0.0, 0.5, 2.0]]);
        assert!(EnvironmentMap::from_texels("t".into(), 1, 1, vec![[1.0; 3]]).is_err());
        assert!(EnvironmentMap::from_texels("t".into(), 0, 0, vec![]).is_err());
    }

    #[test]
    fn the_meridian_wraps_and_the_poles_clamp() {
        // Two columns, black and white: either side of u = 0 (the back, ±180°)
        // the lookup blends the two across the seam, with no jump.
        let map = EnvironmentMap::from_texels("t".into(), 2, 1, vec![[0.0; 3], [1.0; 3]]).unwrap();
        let frame = (Vec3::Y, Vec3::Z);
        let back_left = map.sample(Vec3::new(-0.001, 0.0, -1.0), frame, 0.0)[0];
        let back_right = map.sample(Vec3::new(0.001, 0.0, -1.0), frame, 0.0)[0];
        assert!((back_left - 0.5).abs() < 0.01 && (back_right - 0.5).abs() < 0.01, "{back_left} {back_right}");
        for pole in [Vec3::Y, Vec3::NEG_Y] {
            let c = map.sample(pole, frame, 0.0);
            assert!(c.iter().all(|v| v.is_finite()), "{c:?}");
        }
        // The front looks at the map's centre column, u = 0.5.
        let (u, v) = direction_uv(Vec3::Z, Vec3::Y, Vec3::Z);
        assert!((u - 0.5).abs() < 1e-6 && (v - 0.5).abs() < 1e-6);
    }

    #[test]
    fn hdr_values_encode_finite_and_ordered() {
        let values = [0.0, 0.001, 0.5, 1.0, 10.0, 1e5, 3.0e38];
        let encoded: Vec<f32> = values.iter().map(|&v| encode_linear(v)).collect();
        assert!(encoded.iter().all(|v| v.is_finite()), "{encoded:?}");
        assert!(encoded.windows(2).all(|w| w[0] < w[1]), "{encoded:?}");
        assert!((encode_linear(1.0) - 1.0).abs() < 1e-6);
    }
}
