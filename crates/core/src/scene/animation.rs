//! Scenes that move (the deformable objects of Zhang & Pajarola 2007 §4.3,
//! whose hash grouping is redone every frame): keyframed object transforms,
//! deformations of an object's points, and sequences of PLY frames.
//!
//! - **Keyframes** give a translation, rotation (Euler degrees, as the
//!   object's own `rotate`) and scale at times in seconds; between two keys
//!   they are interpolated linearly or with smoothstep easing ("smooth"),
//!   rotations by slerp. The keyed transform applies after the object's own.
//! - **Deformations** act in the object's coordinates, about the centre c of
//!   its rest bounds, with `up` the scene's up axis, `u` the longest of the
//!   two other axes (length L) and `w` the third; h = (p - c)·up,
//!   x = (p - c)·u:
//!   - wave: p + up · A sin(2π(x/λ + t/P)), λ = `wavelength` (default L/2);
//!   - twist: a turn about the up axis through c by A · h/(H/2) · sin(2πt/P)
//!     (H the size along up): A radians at the top and bottom at full swing;
//!   - bend: the model's length L bent into a circular arc of angle
//!     θ = A sin(2πt/P) in the (u, up) plane: with κ = θ/L, φ = κx,
//!     x' = (1/κ - h) sin φ, h' = 1/κ - (1/κ - h) cos φ. The plane h = 0
//!     becomes a cylinder of radius 1/κ.
//!
//!   Normals follow the Jacobian J of the map (n' ∝ J⁻ᵀn, through J's
//!   cofactors), and radii the square root of its area stretch in the
//!   splat's plane, √(σ₁σ₂) (see [`tangent_stretch`]). J is taken by central
//!   differences in f64.
//! - **Sequences**: PLY frames from a folder or a pattern (`frames/*.ply`),
//!   in name order, at `fps`; frames are read when first shown and a few
//!   are kept. A frame that cannot be read is reported once, naming it, and
//!   the nearest readable frame before it is shown; a frame whose header
//!   declares no points is an empty frame.
//!
//! Every animation loops: keyframes over their last time, deformations
//! over their period, sequences over their frames.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use glam::{DMat3, DVec3, Quat, Vec3};
use rayon::prelude::*;

use crate::cloud::{self, LoadOptions, PointCloud};

/// One keyed transform.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Keyframe {
    pub time: f32,
    pub translate: Vec3,
    pub rotate: Quat,
    pub scale: f32,
}

/// How keyed transforms are blended between two keys.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Interpolation {
    #[default]
    Linear,
    /// Smoothstep easing: each key is reached and left at rest.
    Smooth,
}

/// What a deformation does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DeformKind {
    Wave,
    Twist,
    Bend,
}

impl DeformKind {
    pub const ALL: [DeformKind; 3] = [DeformKind::Wave, DeformKind::Twist, DeformKind::Bend];

    pub fn name(self) -> &'static str {
        match self {
            Self::Wave => "wave",
            Self::Twist => "twist",
            Self::Bend => "bend",
        }
    }
}

crate::by_name!(DeformKind, "deform kind");

/// A deformation of an object's points over time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Deform {
    pub kind: DeformKind,
    /// Model units for a wave, radians for a twist or bend.
    pub amount: f32,
    /// Seconds.
    pub period: f32,
    /// A wave's wavelength in model units (default: half the model's length).
    pub wavelength: Option<f32>,
}

/// The axes and extent a deformation works in (from the rest pose).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeformFrame {
    pub centre: DVec3,
    pub up: DVec3,
    /// The longest axis across `up`, and the third.
    pub u: DVec3,
    pub w: DVec3,
    /// Size along `u` and along `up`.
    pub length: f64,
    pub height: f64,
}

impl DeformFrame {
    /// The frame of `cloud`'s bounds with `up` (a unit axis).
    pub fn of(cloud: &PointCloud, up: Vec3) -> Self {
        let (min, max) = match cloud.bounds() {
            Some(b) if b.min.is_finite() && b.max.is_finite() => (b.min.as_dvec3(), b.max.as_dvec3()),
            _ => (DVec3::ZERO, DVec3::ZERO),
        };
        let up = up.as_dvec3();
        let size = (max - min).abs();
        // The two axes across `up` (up is one of ±x, ±y, ±z).
        let across: Vec<DVec3> = [DVec3::X, DVec3::Y, DVec3::Z].into_iter().filter(|a| a.dot(up).abs() < 0.5).collect();
        let (u, w) =
            if size.dot(across[0]) >= size.dot(across[1]) { (across[0], across[1]) } else { (across[1], across[0]) };
        Self {
            centre: (min + max) / 2.0,
            up,
            u,
            w,
            length: size.dot(u).max(1e-12),
            height: size.dot(up.abs()).max(1e-12),
        }
    }
}

impl Deform {
    /// Checks the parameters; the message names the problem.
    pub fn validate(&self) -> Result<(), String> {
        if !self.amount.is_finite() {
            return Err(format!("deform amount must be a finite number, not {}", self.amount));
        }
        // Beyond these the deformed splats leave what f32 can draw (a wave) or
        // the angles what sin and cos can resolve (radians of a twist or bend).
        let (largest, unit) = match self.kind {
            DeformKind::Wave => (1e9, "model units"),
            DeformKind::Twist | DeformKind::Bend => (1e3, "radians"),
        };
        if self.amount.abs() > largest {
            return Err(format!("deform amount must be within ±{largest:e} {unit}, not {}", self.amount));
        }
        if !(self.period.is_finite() && self.period > 0.0) {
            return Err(format!("deform period must be a positive number of seconds, not {}", self.period));
        }
        if let Some(l) = self.wavelength {
            if !(l.is_finite() && l > 0.0) {
                return Err(format!("deform wavelength must be positive, not {l}"));
            }
        }
        Ok(())
    }

    /// Where the map at time `t` takes the point `p` (f64, object coordinates).
    pub fn map(&self, frame: &DeformFrame, t: f64, p: DVec3) -> DVec3 {
        let (amount, period) = (self.amount as f64, self.period as f64);
        let phase = std::f64::consts::TAU * t / period;
        let rel = p - frame.centre;
        let (x, h, z) = (rel.dot(frame.u), rel.dot(frame.up), rel.dot(frame.w));
        match self.kind {
            DeformKind::Wave => {
                let wavelength = self.wavelength.map_or(frame.length / 2.0, |l| l as f64);
                p + frame.up * amount * (std::f64::consts::TAU * x / wavelength + phase).sin()
            }
            DeformKind::Twist => {
                let angle = amount * (h / (frame.height / 2.0)) * phase.sin();
                let (s, c) = angle.sin_cos();
                frame.centre + frame.up * h + frame.u * (c * x - s * z) + frame.w * (s * x + c * z)
            }
            DeformKind::Bend => {
                let kappa = amount * phase.sin() / frame.length;
                if kappa.abs() < 1e-12 {
                    return p;
                }
                let radius = 1.0 / kappa;
                let (s, c) = (kappa * x).sin_cos();
                let (x2, h2) = ((radius - h) * s, radius - (radius - h) * c);
                frame.centre + frame.u * x2 + frame.up * h2 + frame.w * z
            }
        }
    }

    /// `cloud` deformed at time `t`: positions, normals (J⁻ᵀ) and radii
    /// (√ of the tangent area stretch), in parallel.
    pub fn apply(&self, frame: &DeformFrame, t: f64, cloud: &PointCloud) -> PointCloud {
        let step = 1e-4 * frame.length.max(frame.height);
        let moved: Vec<(Vec3, Vec3, f32)> = (0..cloud.len())
            .into_par_iter()
            .map(|i| {
                let (p, n, r) = (cloud.positions[i].as_dvec3(), cloud.normals[i].as_dvec3(), cloud.radii[i]);
                let at = self.map(frame, t, p);
                if !at.is_finite() {
                    return (cloud.positions[i], cloud.normals[i], r);
                }
                let column = |axis: DVec3| {
                    (self.map(frame, t, p + axis * step) - self.map(frame, t, p - axis * step)) / (2.0 * step)
                };
                let jacobian = DMat3::from_cols(column(DVec3::X), column(DVec3::Y), column(DVec3::Z));
                (at.as_vec3(), deformed_normal(jacobian, n, cloud.normals[i]), r * tangent_stretch(jacobian, n) as f32)
            })
            .collect();
        let mut out = cloud.clone();
        // Moved splats are where they are drawn: no file position to keep.
        out.residuals.clear();
        for (i, (p, n, r)) in moved.into_iter().enumerate() {
            out.positions[i] = p;
            out.normals[i] = n;
            out.radii[i] = r;
        }
        out
    }
}

/// The normal `n` carried by `jacobian` (J⁻ᵀn through the cofactor matrix,
/// so a singular J still gives a direction); `fallback` when none is left.
pub fn deformed_normal(jacobian: DMat3, n: DVec3, fallback: Vec3) -> Vec3 {
    let (a, b, c) = (jacobian.x_axis, jacobian.y_axis, jacobian.z_axis);
    // The cofactor matrix of J is det(J) · J⁻ᵀ; its columns are these cross products.
    let cofactor = DMat3::from_cols(b.cross(c), c.cross(a), a.cross(b));
    let mut m = cofactor * n;
    if jacobian.determinant() < 0.0 {
        m = -m;
    }
    let m = m.normalize_or_zero();
    if m == DVec3::ZERO || !m.is_finite() { fallback } else { m.as_vec3() }
}

/// How much `jacobian` scales a splat across `n`: the square root of the
/// area stretch of its plane, √(σ₁σ₂) with σ the singular values of J on
/// the tangent plane (at least 10⁻³, so a collapsed splat keeps a size).
/// The disc keeps the area of the ellipse it becomes. The largest stretch σ₁
/// would cover the ellipse too, but inflates every stretched splat: on the
/// waving bunny it raised alg2's ε from 6.0 to 7.2-7.6, where √(σ₁σ₂) leaves
/// no hole for stretch ratios σ₁/σ₂ below about 4.8 on our scans (radii of
/// 1.1 neighbour spacings).
pub fn tangent_stretch(jacobian: DMat3, n: DVec3) -> f64 {
    let n = n.normalize_or_zero();
    if n == DVec3::ZERO || !n.is_finite() {
        return 1.0;
    }
    let (t1, t2) = n.any_orthonormal_pair();
    let (a, b) = (jacobian * t1, jacobian * t2);
    // The area of the parallelogram the unit square across n becomes: σ₁σ₂.
    let area = a.cross(b).length();
    let stretch = area.sqrt();
    if stretch.is_finite() { stretch.max(1e-3) } else { 1.0 }
}

/// PLY frames shown one after another.
#[derive(Debug)]
pub struct Sequence {
    pub frames: Vec<PathBuf>,
    pub fps: f32,
    options: LoadOptions,
    /// The last frames read (index, cloud), newest last.
    kept: Mutex<Vec<(usize, Arc<PointCloud>)>>,
    /// Frames that could not be read, each reported once.
    failed: Mutex<Vec<usize>>,
}

/// Frames of a sequence kept in memory.
const KEPT_FRAMES: usize = 4;

impl Sequence {
    /// The frames `pattern` names: a folder (its `.ply` files) or a file
    /// pattern whose name may hold `*` and `?`, in name order.
    pub fn find(pattern: &Path, fps: f32, options: &LoadOptions) -> Result<Self, String> {
        if !(fps.is_finite() && fps > 0.0) {
            return Err(format!("fps must be positive, not {fps}"));
        }
        let (folder, name) = if pattern.is_dir() {
            (pattern.to_path_buf(), "*.ply".to_string())
        } else {
            let folder = pattern.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
            let name = pattern.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
            (folder.to_path_buf(), name)
        };
        let listing = std::fs::read_dir(&folder).map_err(|e| format!("{}: {e}", folder.display()))?;
        let mut frames: Vec<PathBuf> = listing
            .filter_map(|entry| entry.ok().map(|e| e.path()))
            .filter(|p| p.is_file() && p.file_name().is_some_and(|n| wildcard(&name, &n.to_string_lossy())))
            .collect();
        frames.sort();
        if frames.is_empty() {
            return Err(format!("{}: no file matches the sequence", pattern.display()));
        }
        Ok(Self { frames, fps, options: options.clone(), kept: Mutex::new(Vec::new()), failed: Mutex::new(Vec::new()) })
    }

    /// Seconds the sequence lasts.
    pub fn duration(&self) -> f64 {
        self.frames.len() as f64 / self.fps as f64
    }

    /// The frame shown at time `t` (looping).
    pub fn index_at(&self, t: f64) -> usize {
        let n = self.frames.len();
        ((t * self.fps as f64).floor() as i64).rem_euclid(n as i64) as usize
    }

    /// Frame `index`, read on first use; an unreadable frame is reported once
    /// (naming it) and the nearest readable one before it (or after) is shown.
    /// Many unreadable frames are said in one line with their count.
    pub fn frame(&self, index: usize) -> Result<(usize, Arc<PointCloud>), String> {
        let n = self.frames.len();
        // The frames found unreadable on this search, not reported before.
        let mut new_failures: Vec<String> = Vec::new();
        let mut first_error = None;
        for step in 0..n {
            let at = (index + n - step) % n;
            match self.read(at) {
                Ok(cloud) => {
                    match new_failures.as_slice() {
                        [] => {}
                        [one] => crate::progress::warn_once(format!("{one}; the frame before it is shown instead")),
                        [first, ..] => crate::progress::warn_once(format!(
                            "{} frames of the sequence cannot be read (the first: {first}); the frame before each is shown instead",
                            new_failures.len()
                        )),
                    }
                    return Ok((at, cloud));
                }
                Err(message) => {
                    let mut failed = self.failed.lock().unwrap_or_else(|p| p.into_inner());
                    if !failed.contains(&at) {
                        failed.push(at);
                        new_failures.push(message.clone());
                    }
                    first_error.get_or_insert(message);
                }
            }
        }
        let first = first_error.unwrap_or_default();
        Err(format!("none of the sequence's {n} files can be read as a frame (the first: {first})"))
    }

    fn read(&self, index: usize) -> Result<Arc<PointCloud>, String> {
        {
            let kept = self.kept.lock().unwrap_or_else(|p| p.into_inner());
            if let Some((_, cloud)) = kept.iter().find(|(i, _)| *i == index) {
                return Ok(Arc::clone(cloud));
            }
        }
        let path = &self.frames[index];
        let cloud = match cloud::load_with(path, &self.options) {
            Ok((cloud, _)) => cloud,
            // A frame of no points (a capture with nothing in view) shows nothing.
            Err(_) if declares_no_vertices(path) => PointCloud::default(),
            Err(e) => return Err(cloud::one_line(&e.to_string())),
        };
        let cloud = Arc::new(cloud);
        let mut kept = self.kept.lock().unwrap_or_else(|p| p.into_inner());
        if kept.len() >= KEPT_FRAMES {
            kept.remove(0);
        }
        kept.push((index, Arc::clone(&cloud)));
        Ok(cloud)
    }
}

/// An object's animation: any of keyframes, a deformation and a sequence.
#[derive(Debug, Default)]
pub struct Animation {
    /// In increasing time (checked when read).
    pub keyframes: Vec<Keyframe>,
    pub interpolate: Interpolation,
    pub deform: Option<(Deform, DeformFrame)>,
    pub sequence: Option<Sequence>,
}

impl Animation {
    /// Checks the keyframes: finite, and in increasing time; the message names the first wrong one (from 1).
    pub fn check_keyframes(keyframes: &[Keyframe]) -> Result<(), (usize, String)> {
        for (k, key) in keyframes.iter().enumerate() {
            if !(key.time.is_finite() && key.time >= 0.0) {
                return Err((k, format!("keyframe {} has time {}, not a time ≥ 0", k + 1, key.time)));
            }
            if !(key.translate.is_finite() && key.rotate.is_finite() && key.scale.is_finite() && key.scale > 0.0) {
                return Err((k, format!("keyframe {} has a transform that is not finite (or a scale ≤ 0)", k + 1)));
            }
            if !(crate::scene::SCALES.contains(&key.scale)) {
                let range = crate::scene::SCALES;
                let message = format!(
                    "keyframe {} has scale {}, not within {:e}..{:e}",
                    k + 1,
                    key.scale,
                    range.start(),
                    range.end()
                );
                return Err((k, message));
            }
            if k > 0 && key.time <= keyframes[k - 1].time {
                return Err((
                    k,
                    format!(
                        "keyframes out of order: keyframe {} at {} s comes after keyframe {} at {} s",
                        k + 1,
                        key.time,
                        k,
                        keyframes[k - 1].time
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Seconds after which the animation repeats (0 when nothing moves).
    pub fn period(&self) -> f64 {
        let keys = self.keyframes.last().map_or(0.0, |k| k.time as f64);
        let deform = self.deform.as_ref().map_or(0.0, |(d, _)| d.period as f64);
        let sequence = self.sequence.as_ref().map_or(0.0, Sequence::duration);
        keys.max(deform).max(sequence)
    }

    /// The keyed transform at time `t` (identity without keyframes).
    pub fn keyed(&self, t: f64) -> glam::Affine3A {
        let keys = &self.keyframes;
        let Some(last) = keys.last() else { return glam::Affine3A::IDENTITY };
        let t = if last.time > 0.0 { t.rem_euclid(last.time as f64) as f32 } else { 0.0 };
        let at = keys.partition_point(|k| k.time <= t);
        let (a, b, s) = match at {
            0 => (keys[0], keys[0], 0.0),
            i if i == keys.len() => (*last, *last, 0.0),
            i => {
                let (a, b) = (keys[i - 1], keys[i]);
                let s = ((t - a.time) / (b.time - a.time)).clamp(0.0, 1.0);
                (a, b, if self.interpolate == Interpolation::Smooth { s * s * (3.0 - 2.0 * s) } else { s })
            }
        };
        glam::Affine3A::from_scale_rotation_translation(
            Vec3::splat(a.scale + (b.scale - a.scale) * s),
            a.rotate.slerp(b.rotate, s),
            a.translate.lerp(b.translate, s),
        )
    }

    /// The object's cloud at time `t` (its sequence frame, deformed) and the
    /// sequence frame shown, if any; `rest` is the object's own cloud.
    pub fn cloud_at(&self, rest: &Arc<PointCloud>, t: f64) -> Result<(Arc<PointCloud>, Option<usize>), String> {
        let (frame, shown) = match &self.sequence {
            Some(sequence) => {
                let (index, cloud) = sequence.frame(sequence.index_at(t))?;
                (cloud, Some(index))
            }
            None => (Arc::clone(rest), None),
        };
        let cloud = match &self.deform {
            // Its own period's time: a deformation repeats with it, and a time
            // of 1e20 s would leave the phase no precision.
            Some((deform, axes)) if deform.amount != 0.0 => {
                Arc::new(deform.apply(axes, t.rem_euclid(deform.period as f64), &frame))
            }
            _ => frame,
        };
        Ok((cloud, shown))
    }
}

/// Whether the PLY header at `path` declares `element vertex 0`.
fn declares_no_vertices(path: &Path) -> bool {
    use std::io::Read;
    let mut head = [0u8; 4096];
    let Ok(read) = std::fs::File::open(path).and_then(|mut f| f.read(&mut head)) else { return false };
    let text = String::from_utf8_lossy(&head[..read]);
    let header = text.split("end_header").next().unwrap_or("");
    header.lines().any(|l| l.split_whitespace().collect::<Vec<_>>() == ["element", "vertex", "0"])
}

/// Whether `name` matches `pattern` (`*`: any run of characters, `?`: one).
/// Hand-written: a sequence needs only a file-name pattern in one folder.
fn wildcard(pattern: &str, name: &str) -> bool {
    let (p, n): (Vec<char>, Vec<char>) = (pattern.chars().collect(), name.chars().collect());
    let (mut i, mut j, mut star, mut mark) = (0, 0, None, 0);
    while j < n.len() {
        if i < p.len() && (p[i] == '?' || p[i] == n[j]) {
            i += 1;
            j += 1;
        } else if i < p.len() && p[i] == '*' {
            star = Some(i);
            mark = j;
            i += 1;
        } else if let Some(s) = star {
            i = s + 1;
            mark += 1;
            j = mark;
        } else {
            return false;
        }
    }
    p[i..].iter().all(|&c| c == '*')
}

#[cfg(test)]
mod tests {
    use super::wildcard;

    #[test]
    fn wildcards_match_file_names() {
        assert!(wildcard("*.ply", "frame_001.ply"));
        assert!(wildcard("frame_??.ply", "frame_01.ply"));
        assert!(!wildcard("frame_??.ply", "frame_001.ply"));
        assert!(!wildcard("*.ply", "frame.plyx"));
        assert!(wildcard("*", "anything"));
    }
}
