//! WGSL sources, embedded at build time, and their variants.
//!
//! Shader variants come from one mechanism: a small preprocessor with
//! `#include "file.wgsl"` (each file included once), `#ifdef NAME`,
//! `#ifndef NAME`, `#else` and `#endif`. A [`Variant`] is a set of names
//! (`LIT`, `WEIGHT_ONLY`, `OPAQUE_APART`, `ENVIRONMENT`, `LIGHTS`,
//! `TRIANGLES`, `SUBGROUPS`, `COVERAGE`, `CLIP`).
//! Chosen over WGSL `override` constants, which cannot remove a binding, a
//! fragment output or a struct field (an unlit pass must neither declare nor
//! write a normal target), and over `naga_oil`, which composes into naga IR
//! pinned to its own naga release and brings far more than these dozen
//! directives need. `cargo test` composes every root file in every variant
//! and validates it with naga (`tests/shaders.rs`). Every file in
//! `shaders/` is embedded (build.rs); a pass names its root file.

// `FILES`: every WGSL file in shaders/, embedded by build.rs.
include!(concat!(env!("OUT_DIR"), "/shader_files.rs"));

/// Whether `name` is a file passes build modules from (it has a fragment
/// or compute entry point) rather than one that is only included.
pub fn is_root(name: &str) -> bool {
    FILES.iter().any(|(n, source)| *n == name && (source.contains("@fragment") || source.contains("@compute")))
}

/// The root files: those a pass can build a module from.
pub fn roots() -> impl Iterator<Item = &'static str> {
    FILES.iter().map(|(n, _)| *n).filter(|n| is_root(n))
}

/// A set of preprocessor names a shader module is built with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Variant(u32);

impl Variant {
    /// Lighting: normal targets are written and read, and the result is shaded.
    pub const LIT: Variant = Variant(1);
    /// A cloud of one colour: colour targets hold only the weight.
    pub const WEIGHT_ONLY: Variant = Variant(2);
    /// A transparent scene's opaque splats were drawn apart: transparent
    /// fragments behind their depth are culled, and the layers are
    /// composited over their image instead of the background.
    pub const OPAQUE_APART: Variant = Variant(4);
    /// The scene has an environment map: it is bound at group 2 (texture,
    /// filtering sampler) and the compositing pass reflects and refracts it.
    pub const ENVIRONMENT: Variant = Variant(8);
    /// Scene lights instead of the headlight: splats are lit once each, at
    /// their centre, with their shadow coefficients (a second instance
    /// buffer), and the passes blend lit colours (no normal targets, no
    /// shading when normalising). Never with `LIT`.
    pub const LIGHTS: Variant = Variant(16);
    /// Mesh triangles through a splat pass's fragment entry: `vs_triangle`
    /// (shaders/splat.wgsl) and interpolated point, normal and colour.
    pub const TRIANGLES: Variant = Variant(32);
    /// `tiled`'s raster reads its lists a subgroup at a time (the device has subgroup operations).
    pub const SUBGROUPS: Variant = Variant(64);
    /// The EWA prefilter's edge antialiasing in two-pass: the accumulation
    /// tests ε itself, sums the fragments behind the front apart, and adds
    /// each fragment's coverage; the normalisation composites by it.
    pub const COVERAGE: Variant = Variant(128);
    /// The frame is clipped: splat fragments and tile hits whose point the
    /// clip planes or box cut away are dropped (`clip_keeps`, frame.wgsl).
    /// Only then, so an unclipped frame's shaders are those it always had.
    pub const CLIP: Variant = Variant(256);
    /// Eye-dome lighting reads the nearest surface's depth from K group
    /// images (deferred) rather than a depth buffer (two-pass).
    pub const GROUP_DEPTH: Variant = Variant(512);
    /// `tiled`'s splats were packed into fewer slots than the scene has
    /// (a frame drawn in parts): the sort orders equal keys by the places
    /// the pixel boxes keep, not by slot (shaders/tiled_sort.wgsl).
    pub const PACKED: Variant = Variant(1024);
    /// `tiled`'s raster composites every layer a ray meets: no pixel stops
    /// once its light is spent (shaders/tiled_raster.wgsl, `LAST_LIGHT`).
    /// Only for comparing images with and without the stop.
    pub const EVERY_LAYER: Variant = Variant(2048);

    /// Every name, by bit.
    const NAMES: [&'static str; 12] = [
        "LIT",
        "WEIGHT_ONLY",
        "OPAQUE_APART",
        "ENVIRONMENT",
        "LIGHTS",
        "TRIANGLES",
        "SUBGROUPS",
        "COVERAGE",
        "CLIP",
        "GROUP_DEPTH",
        "PACKED",
        "EVERY_LAYER",
    ];

    pub const NONE: Variant = Variant(0);

    /// This variant with `flag` set when `on`.
    pub fn with(self, flag: Variant, on: bool) -> Variant {
        if on { Variant(self.0 | flag.0) } else { Variant(self.0 & !flag.0) }
    }

    pub fn has(self, flag: Variant) -> bool {
        self.0 & flag.0 == flag.0
    }

    /// The preprocessor names that are defined.
    pub fn defines(self) -> Vec<&'static str> {
        Self::NAMES.iter().enumerate().filter(|(bit, _)| self.0 & (1 << bit) != 0).map(|(_, n)| *n).collect()
    }

    /// Every variant there is.
    pub fn all() -> impl Iterator<Item = Variant> {
        (0..1u32 << Self::NAMES.len()).map(Variant)
    }
}

impl std::fmt::Display for Variant {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let defines = self.defines();
        if defines.is_empty() { f.write_str("plain") } else { f.write_str(&defines.join("+")) }
    }
}

/// The source of `root` with its includes resolved for `variant`.
pub fn compose(root: &str, variant: Variant) -> Result<String, String> {
    let mut out = String::new();
    let mut included = Vec::new();
    include(root, &variant.defines(), &mut included, &mut out)?;
    Ok(out)
}

fn include(name: &str, defines: &[&str], included: &mut Vec<String>, out: &mut String) -> Result<(), String> {
    if included.iter().any(|n| n == name) {
        return Ok(());
    }
    included.push(name.to_string());
    let source = FILES.iter().find(|(n, _)| *n == name).map(|(_, s)| *s).ok_or(format!("no shader file {name}"))?;
    // One entry per open #if: (this branch is taken, the enclosing ones are).
    let mut stack: Vec<(bool, bool)> = Vec::new();
    let active = |stack: &[(bool, bool)]| stack.last().is_none_or(|&(taken, outer)| taken && outer);
    for (number, line) in source.lines().enumerate() {
        let at = |what: &str| format!("{name}:{}: {what}", number + 1);
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["#include", file] if active(&stack) => include(file.trim_matches('"'), defines, included, out)?,
            ["#include", _] => {}
            ["#ifdef", flag] | ["#ifndef", flag] => {
                let defined = defines.contains(flag);
                let taken = if words[0] == "#ifdef" { defined } else { !defined };
                stack.push((taken, active(&stack)));
            }
            ["#else"] => {
                let top = stack.last_mut().ok_or_else(|| at("#else without #ifdef"))?;
                top.0 = !top.0;
            }
            ["#endif"] => {
                stack.pop().ok_or_else(|| at("#endif without #ifdef"))?;
            }
            [directive, ..] if directive.starts_with('#') => return Err(at(&format!("unknown directive {directive}"))),
            _ if active(&stack) => {
                out.push_str(line);
                out.push('\n');
            }
            _ => {}
        }
    }
    if stack.is_empty() { Ok(()) } else { Err(format!("{name}: #ifdef without #endif")) }
}

/// Every WGSL file name, for the check that each is used.
pub fn file_names() -> impl Iterator<Item = &'static str> {
    FILES.iter().map(|(n, _)| *n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn variants_select_their_branches_and_includes_come_once() {
        let lit = compose("accumulate.wgsl", Variant::LIT).unwrap();
        let unlit = compose("accumulate.wgsl", Variant::NONE).unwrap();
        assert!(lit.contains("@location(1) normal") && !unlit.contains("@location(1) normal"));
        assert_eq!(lit.matches("struct Frame {").count(), 1, "frame.wgsl is included once");
        assert!(compose("missing.wgsl", Variant::NONE).is_err());
        assert_eq!(Variant::LIT.with(Variant::WEIGHT_ONLY, true).defines(), ["LIT", "WEIGHT_ONLY"]);
        assert_eq!(Variant::all().count(), 1 << Variant::NAMES.len());
    }
}
