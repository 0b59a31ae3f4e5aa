//! The descriptor table: one row per [`Parameter`], from which every front
//! end is made. The command line's flags and their `--help`, bench's variant
//! keys, the sidecar's settings and the viewer's widgets all read this table;
//! none of them names a parameter on its own (docs/ADDING_A_PARAMETER.md).
//!
//! A row holds the parameter's one name, its help, the values it takes, the
//! viewer's control, and two functions: `set` parses the text form into the
//! settings, `get` writes it back (`None`: left to the mode, as peel layers).
//! `get` of `set(x)` is `x` again, so a sidecar reproduces what it recorded.

use glam::Vec3;

use super::super::settings::{MAX_PEEL_LAYERS, MAX_SUPERSAMPLE};
use super::super::{Prefilter, Quality, RenderSettings};
use super::Parameter;
use crate::grouping::GroupingSpec;

/// The viewer's control for a parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Control {
    /// One radio button per text value.
    Choices(&'static [&'static str]),
    /// A checkbox: `on` or `off`.
    Toggle,
    /// A slider over real values (typed values outside it are kept when `set` takes them).
    Number { min: f32, max: f32, logarithmic: bool },
    /// A slider over whole values.
    Count { min: u32, max: u32 },
    /// A colour picker over `R,G,B` in 0..255.
    Colour,
    /// A widget of its own in the viewer (grouping, lights, shadows,
    /// environment, point budget), drawn under the row's label.
    Custom,
}

/// One parameter's row.
#[derive(Debug, Clone, Copy)]
pub struct ParameterInfo {
    pub parameter: Parameter,
    /// The one name: bench variants' and sidecars' key (`step=2`).
    pub key: &'static str,
    /// The command line's `--FLAG VALUE`.
    pub flag: &'static str,
    /// A flag without a value that sets `off` (`--no-cull`), kept for the
    /// switches the command line had before the table.
    pub off_switch: Option<&'static str>,
    /// The viewer's label.
    pub label: &'static str,
    /// What it does, for `--help` and the viewer's hover text.
    pub help: &'static str,
    /// The values it takes, for messages.
    pub values: &'static str,
    pub control: Control,
    /// Parses a text value into the settings. `Err` carries a detail to add
    /// to the row's `values` ("" for none).
    pub set: fn(&mut RenderSettings, &str) -> Result<(), String>,
    /// The text value the settings hold (`None`: the mode's own default).
    pub get: fn(&RenderSettings) -> Option<String>,
}

fn on_off(value: &str) -> Result<bool, String> {
    match value {
        "on" | "true" | "yes" => Ok(true),
        "off" | "false" | "no" => Ok(false),
        _ => Err(String::new()),
    }
}

fn on_off_text(on: bool) -> Option<String> {
    Some(if on { "on" } else { "off" }.to_string())
}

fn positive(value: &str) -> Result<f32, String> {
    value.parse::<f32>().ok().filter(|x| x.is_finite() && *x > 0.0).ok_or_else(String::new)
}

fn whole_in(value: &str, range: std::ops::RangeInclusive<u32>) -> Result<u32, String> {
    value.parse::<u32>().ok().filter(|n| range.contains(n)).ok_or_else(String::new)
}

fn number(x: f32) -> Option<String> {
    Some(x.to_string())
}

/// `R,G,B` (or `R/G/B`) in 0..255, stored in 0..1.
fn set_background(s: &mut RenderSettings, value: &str) -> Result<(), String> {
    let rgb: Vec<f32> =
        value.split([',', '/']).map(|c| c.trim().parse::<f32>().ok()).collect::<Option<_>>().ok_or_else(String::new)?;
    match rgb[..] {
        [r, g, b] if [r, g, b].iter().all(|c| (0.0..=255.0).contains(c)) => {
            s.shading.background = Vec3::new(r, g, b) / 255.0;
            Ok(())
        }
        _ => Err(String::new()),
    }
}

/// Each channel as the level (in 0..255) that reads back as exactly this
/// colour: an 8-bit colour's whole level, else the f32 nearest c·255 (within
/// a few units in the last place) whose quotient by 255, as `set` takes it,
/// is c again.
fn get_background(s: &RenderSettings) -> Option<String> {
    let level = |c: f32| {
        let near = c * 255.0;
        if near.round() / 255.0 == c {
            return near.round();
        }
        // The f32 values k units in the last place away (levels are ≥ 0, so the bits order them).
        let step = |k: i64| f32::from_bits((near.to_bits() as i64 + k).max(0) as u32);
        [0, 1, -1, 2, -2, 3, -3, 4, -4].map(step).into_iter().find(|v| *v / 255.0 == c).unwrap_or(near)
    };
    let [r, g, b] = s.shading.background.to_array().map(level);
    Some(format!("{r},{g},{b}"))
}

/// `tsm`, `tsm-POLxAZ` (table cells), `exact` or `off`.
fn set_shadows(s: &mut RenderSettings, value: &str) -> Result<(), String> {
    let (method, cells) = match value.split_once('-') {
        Some(("tsm", cells)) => ("tsm", Some(super::super::lights::parse_cells(cells)?)),
        Some(_) => return Err(String::new()),
        None => (value, None),
    };
    s.shadows.method = method.parse()?;
    if let Some(cells) = cells {
        s.shadows.cells = cells;
    }
    Ok(())
}

fn get_shadows(s: &RenderSettings) -> Option<String> {
    use super::super::lights::{DEFAULT_TSM_CELLS, ShadowMethod};
    let [p, a] = s.shadows.cells;
    Some(match s.shadows.method {
        ShadowMethod::Tsm if s.shadows.cells != DEFAULT_TSM_CELLS => format!("tsm-{p}x{a}"),
        method => method.name().to_string(),
    })
}

/// `single` or `multi` (on), or `off`.
fn set_environment_layers(s: &mut RenderSettings, value: &str) -> Result<(), String> {
    let env = &mut s.environment;
    (env.enabled, env.layer_effects) = match value {
        "off" => (false, env.layer_effects),
        other => (true, other.parse().map_err(|_| String::new())?),
    };
    Ok(())
}

/// The table: row i is the parameter whose discriminant is i (a test checks it).
pub const TABLE: [ParameterInfo; 21] = [
    ParameterInfo {
        parameter: Parameter::Quality,
        key: "quality",
        flag: "quality",
        off_switch: None,
        label: "quality",
        help: "Gaussian-filtered blending, or the unfiltered nearest splat (two-pass's quality levels)",
        values: "filtered or unfiltered",
        control: Control::Choices(&["filtered", "unfiltered"]),
        set: |s, v| {
            s.quality = match v {
                "filtered" => Quality::Filtered,
                "unfiltered" => Quality::Unfiltered,
                _ => return Err(String::new()),
            };
            Ok(())
        },
        get: |s| Some(if s.quality == Quality::Filtered { "filtered" } else { "unfiltered" }.into()),
    },
    ParameterInfo {
        parameter: Parameter::Epsilon,
        key: "epsilon",
        flag: "epsilon",
        off_switch: None,
        label: "ε (× mean radius)",
        help: "ε of the depth test that decides which splats blend, in multiples of the mean splat radius",
        values: "a positive multiple of the mean splat radius",
        control: Control::Number { min: 0.05, max: 5.0, logarithmic: false },
        set: |s, v| {
            s.epsilon_scale = positive(v)?;
            Ok(())
        },
        get: |s| number(s.epsilon_scale),
    },
    ParameterInfo {
        parameter: Parameter::DepthStep,
        key: "step",
        flag: "depth-step",
        off_switch: None,
        label: "Eq. 10 depth step (× ε)",
        help: "Eq. 10's low-precision depth step, in multiples of ε",
        values: "a positive multiple of ε",
        control: Control::Number { min: 0.25, max: 4.0, logarithmic: false },
        set: |s, v| {
            s.depth_step = positive(v)?;
            Ok(())
        },
        get: |s| number(s.depth_step),
    },
    ParameterInfo {
        parameter: Parameter::RadiusScale,
        key: "radius-scale",
        flag: "radius-scale",
        off_switch: None,
        label: "splat radius scale",
        help: "a factor on every splat radius",
        values: "a positive factor, at most 100",
        control: Control::Number { min: 0.25, max: 3.0, logarithmic: false },
        set: |s, v| {
            let max = super::super::settings::MAX_RADIUS_SCALE;
            s.radius_scale = positive(v).ok().filter(|f| *f <= max).ok_or_else(String::new)?;
            Ok(())
        },
        get: |s| number(s.radius_scale),
    },
    ParameterInfo {
        parameter: Parameter::MinPixelRadius,
        key: "min-pixel-radius",
        flag: "min-pixel-radius",
        off_switch: None,
        label: "min splat radius (px)",
        help: "far splats are drawn at least this many pixels in radius, in their own plane (0: as they are); applied before the EWA prefilter, which then stretches only what is still smaller than its low-pass radius",
        values: "a number of pixels, 0 to 64",
        control: Control::Number { min: 0.0, max: 4.0, logarithmic: false },
        set: |s, v| {
            let px = v.parse::<f32>().ok().filter(|p| (0.0..=64.0).contains(p)).ok_or_else(String::new)?;
            s.min_pixel_radius = px;
            Ok(())
        },
        get: |s| number(s.min_pixel_radius),
    },
    ParameterInfo {
        parameter: Parameter::BackfaceCulling,
        key: "cull",
        flag: "cull",
        off_switch: Some("no-cull"),
        label: "back-face culling",
        help: "drop splats that face away from the camera (--no-cull keeps them)",
        values: "on or off",
        control: Control::Toggle,
        set: |s, v| {
            s.backface_culling = on_off(v)?;
            Ok(())
        },
        get: |s| on_off_text(s.backface_culling),
    },
    ParameterInfo {
        parameter: Parameter::Lighting,
        key: "lighting",
        flag: "lighting",
        off_switch: Some("unlit"),
        label: "lighting",
        help: "Phong lighting; off (--unlit) shows the blended colours, headlight lights by the camera instead of the scene's lights",
        values: "on, off or headlight (the camera's light instead of the scene's lights)",
        control: Control::Custom,
        set: |s, v| {
            // `headlight`: lit, but by the camera's light rather than the scene's lights.
            if v == "headlight" {
                s.lighting = true;
                s.lights = Default::default();
                return Ok(());
            }
            s.lighting = on_off(v)?;
            Ok(())
        },
        get: |s| on_off_text(s.lighting),
    },
    ParameterInfo {
        parameter: Parameter::EyeDome,
        key: "edl",
        flag: "edl",
        off_switch: None,
        label: "eye-dome lighting",
        help: "eye-dome lighting (Boucheny): shades the nearest surface by its depth's steps to 8 neighbours, for clouds without normals; on, off, STRENGTH or STRENGTH,RADIUS (defaults 1, 1.4 px)",
        values: "on, off, STRENGTH or STRENGTH,RADIUS (strength in (0, 100], radius 1 to 16 px)",
        control: Control::Custom,
        set: |s, v| {
            s.eye_dome = crate::frame::EyeDome::parse(v)?;
            Ok(())
        },
        get: |s| Some(s.eye_dome.map_or("off".to_string(), |e| e.text())),
    },
    ParameterInfo {
        parameter: Parameter::Grouping,
        key: "group",
        flag: "group",
        off_switch: None,
        label: "grouping",
        help: "the grouping of the deferred modes (Zhang & Pajarola §4)",
        values: crate::grouping::spec::GRAMMAR,
        control: Control::Custom,
        set: |s, v| {
            s.grouping = v.parse::<GroupingSpec>()?;
            Ok(())
        },
        get: |s| Some(s.grouping.to_string()),
    },
    ParameterInfo {
        parameter: Parameter::Voronoi,
        key: "voronoi",
        flag: "voronoi",
        off_switch: Some("no-voronoi"),
        label: "Voronoi rasterisation (Eq. 14)",
        help: "Voronoi rasterisation inside a group's image (Zhang & Pajarola Eq. 14)",
        values: "on or off",
        control: Control::Toggle,
        set: |s, v| {
            s.voronoi = on_off(v)?;
            Ok(())
        },
        get: |s| on_off_text(s.voronoi),
    },
    ParameterInfo {
        parameter: Parameter::Background,
        key: "background",
        flag: "background",
        off_switch: None,
        label: "background",
        help: "the background colour (else the scene's)",
        values: "R,G,B (or R/G/B) in 0..255",
        control: Control::Colour,
        set: set_background,
        get: get_background,
    },
    ParameterInfo {
        parameter: Parameter::PeelLayers,
        key: "layers",
        flag: "layers",
        off_switch: None,
        label: "layers k",
        help: "transparent layers k a peeling mode draws (depth-peel 8, approx-peel 3 unless given)",
        values: "a number of layers, 2..=64",
        control: Control::Count { min: 2, max: MAX_PEEL_LAYERS },
        set: |s, v| {
            s.peel_layers = whole_in(v, 2..=MAX_PEEL_LAYERS)?;
            Ok(())
        },
        get: |s| (s.peel_layers != 0).then(|| s.peel_layers.to_string()),
    },
    ParameterInfo {
        parameter: Parameter::EnvironmentLayers,
        key: "env-layers",
        flag: "env-layers",
        off_switch: None,
        label: "environment effects",
        help: "reflection and refraction of the environment map at the nearest layer, through all layers, or off (§5.2.3)",
        values: "single, multi or off",
        control: Control::Custom,
        set: set_environment_layers,
        get: |s| Some(if s.environment.enabled { s.environment.layer_effects.to_string() } else { "off".into() }),
    },
    ParameterInfo {
        parameter: Parameter::Eta,
        key: "eta",
        flag: "eta",
        off_switch: None,
        label: "η refraction",
        help: "index of refraction η of the environment effects",
        values: "a positive index of refraction",
        control: Control::Number { min: 0.5, max: 2.5, logarithmic: false },
        set: |s, v| {
            s.environment.eta = positive(v)?;
            Ok(())
        },
        get: |s| number(s.environment.eta),
    },
    ParameterInfo {
        parameter: Parameter::Dispersion,
        key: "dispersion",
        flag: "dispersion",
        off_switch: None,
        label: "dispersion δ",
        help: "chromatic dispersion δ of the environment effects",
        values: "a dispersion of 0 or more",
        control: Control::Number { min: 0.0, max: 0.1, logarithmic: false },
        // Checked alone (not against η, which may come later in the
        // variant): η - δ is kept above MIN_ETA where it is used.
        set: |s, v| {
            s.environment.dispersion =
                v.parse::<f32>().ok().filter(|d| d.is_finite() && *d >= 0.0).ok_or_else(String::new)?;
            Ok(())
        },
        get: |s| number(s.environment.dispersion),
    },
    ParameterInfo {
        parameter: Parameter::Order,
        key: "order",
        flag: "order",
        off_switch: None,
        label: "back to front",
        help: "back-to-front order of the modes that blend in order: bucket (Gunjee's bucket sort), bsp (Zhang & Pajarola's BSP traversal, §5.2.1) or sort (an exact comparison sort)",
        values: "bucket, bsp or sort",
        control: Control::Choices(&["bucket", "bsp", "sort"]),
        set: |s, v| {
            s.order = v.parse().map_err(|_| String::new())?;
            Ok(())
        },
        get: |s| Some(s.order.to_string()),
    },
    ParameterInfo {
        parameter: Parameter::Shadows,
        key: "shadows",
        flag: "shadows",
        off_switch: None,
        label: "shadows",
        help: "how lit splats find their light: tsm (Gunjee's translucent shadow map, tsm-POLxAZ or tsm-N for its table per light), exact (a shadow ray per splat) or off",
        values: "tsm, tsm-POLxAZ (table cells), exact or off",
        control: Control::Custom,
        set: set_shadows,
        get: get_shadows,
    },
    ParameterInfo {
        parameter: Parameter::Prefilter,
        key: "prefilter",
        flag: "prefilter",
        off_switch: None,
        label: "prefilter",
        help: "screen-space low-pass filter of the splat passes: ewa (Guennebaud's EWA approximation: splats smaller than a pixel are stretched to the filter, so far models do not alias) or none",
        values: "ewa or none",
        control: Control::Choices(&["none", "ewa"]),
        set: |s, v| {
            s.prefilter = v.parse::<Prefilter>().map_err(|_| String::new())?;
            Ok(())
        },
        get: |s| Some(s.prefilter.to_string()),
    },
    ParameterInfo {
        parameter: Parameter::Supersample,
        key: "supersample",
        flag: "supersample",
        off_switch: None,
        label: "supersample N×N",
        help: "rays per pixel side of the reference: N×N rays per pixel, box-filtered (the exact answer to aliasing; in bench and --diff, the ruler)",
        values: "rays per pixel side, 1..=16",
        control: Control::Count { min: 1, max: MAX_SUPERSAMPLE },
        set: |s, v| {
            s.supersample = whole_in(v, 1..=MAX_SUPERSAMPLE)?;
            Ok(())
        },
        get: |s| Some(s.supersample.to_string()),
    },
    ParameterInfo {
        parameter: Parameter::PointBudget,
        key: "point-budget",
        flag: "point-budget",
        off_switch: None,
        label: "point budget",
        help: "most splats a GPU frame draws: nodes of a multi-resolution octree (built once per model and cached) chosen by screen-space error; the octree's root (up to 1,728 splats) is always drawn, and the reference draws every splat; a point file (LAS, LAZ, PLY without faces, E57) under N below its points is held in memory as the octree of nodes a COPC file of it would hold and drawn node by node as one is (its root always drawn, the reference drawing the nodes selected)",
        values: "a number of splats, 1 or more, or all",
        control: Control::Custom,
        set: |s, v| {
            s.point_budget = match v {
                "all" => None,
                _ => Some(v.parse::<u32>().ok().filter(|n| *n >= 1).ok_or_else(String::new)?),
            };
            Ok(())
        },
        get: |s| Some(s.point_budget.map_or("all".into(), |n| n.to_string())),
    },
    ParameterInfo {
        parameter: Parameter::HybridPixels,
        key: "hybrid-px",
        flag: "hybrid-px",
        off_switch: None,
        label: "hybrid px",
        help: "hybrid objects (`hybrid = \"x.ply\"` in a scene file): a leaf of the mesh is drawn as triangles where its largest splat would be wider than this radius in pixels, as splats elsewhere",
        values: "a splat radius in pixels, 0 or more (0: every leaf as triangles), or inf (splats only)",
        control: Control::Number { min: 0.0, max: 32.0, logarithmic: false },
        set: |s, v| {
            s.hybrid_pixels = v.parse::<f32>().ok().filter(|p| *p >= 0.0).ok_or_else(String::new)?;
            Ok(())
        },
        get: |s| number(s.hybrid_pixels),
    },
];
