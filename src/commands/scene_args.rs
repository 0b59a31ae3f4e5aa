//! Flags that change the scene rather than the rendering parameters: every
//! object's opacity and colour, colour and opacity by attribute, and point
//! lights added to the scene's. `render`, `bench` and `view` all take them from here.

use std::sync::Arc;

use pointblend::frame::clip::{self, ClipBox, ClipRegion, Hidden};
use pointblend::scene::{Materials, Scene};
use pointblend::style::{ColorBy, Colormap, Filter, Returns, Style, parse};

#[derive(clap::Args, Debug, Clone, Default)]
pub struct SceneArgs {
    /// Opacity of every object, 0..1 (transparent objects are drawn two-sided;
    /// only transparent modes and the reference show it).
    #[arg(long, value_parser = parse_opacity)]
    pub opacity: Option<f32>,
    /// Colour R,G,B (0..255) that replaces every object's own.
    #[arg(long = "color", value_parser = parse_rgb)]
    pub colour: Option<[u8; 3]>,
    /// A white point light at X,Y,Z in the model's file coordinates (repeatable, at most 8 with the scene's);
    /// any light replaces the headlight, and casts translucent shadows.
    #[arg(long = "light", value_parser = parse_light, allow_hyphen_values = true)]
    pub lights: Vec<pointblend::frame::Light>,
    /// What the colours show: rgb (the file's), classification (ASPRS colours), elevation,
    /// intensity, return, gps-time, or any attribute's name (`pointblend info` lists them).
    #[arg(long = "color-by", value_parser = |t: &str| t.parse::<ColorBy>())]
    pub color_by: Option<ColorBy>,
    /// The colormap of a scalar --color-by: viridis, magma, inferno, cividis, turbo, grey.
    #[arg(long, value_parser = |t: &str| t.parse::<Colormap>())]
    pub colormap: Option<Colormap>,
    /// MIN,MAX: the values at the colormap's ends [default: the 2nd and 98th percentiles].
    #[arg(long, value_parser = parse::range, allow_hyphen_values = true)]
    pub range: Option<(f64, f64)>,
    /// Show only these ASPRS classes, e.g. 2,6.
    #[arg(long, value_delimiter = ',', value_parser = parse_class)]
    pub classes: Vec<u8>,
    /// Opacity per class, e.g. 5:0.3,6:1 (translucent objects are drawn two-sided).
    #[arg(long = "class-opacity", value_delimiter = ',', value_parser = parse_class_opacity)]
    pub class_opacity: Vec<(u8, f32)>,
    /// An attribute whose value (over its 2nd-98th percentile range) is each splat's opacity.
    #[arg(long = "opacity-by")]
    pub opacity_by: Option<String>,
    /// Show only the points whose attribute NAME (as `pointblend info` lists it) lies in
    /// MIN..MAX or is one of V1,V2,...: NAME=MIN..MAX or NAME=V1,V2 (repeatable; all must hold).
    #[arg(long = "filter", value_parser = |t: &str| t.parse::<Filter>(), allow_hyphen_values = true)]
    pub filters: Vec<Filter>,
    /// Show only these returns: first, last, only (single returns) or a return number N.
    #[arg(long, value_parser = |t: &str| t.parse::<Returns>())]
    pub returns: Option<Returns>,
    /// Clip to a box MINX,MINY,MINZ,MAXX,MAXY,MAXZ in file coordinates (per pixel: a cut splat shows its kept part).
    #[arg(long = "clip-box", value_parser = |t: &str| ClipBox::parse(t).map_err(|e| e.to_string()), allow_hyphen_values = true)]
    pub clip_box: Option<ClipBox>,
    /// Which side of --clip-box is hidden: outside (keep the box's contents) or inside (cut the box away).
    #[arg(long = "clip-hide", value_parser = parse_hidden, requires = "clip_box")]
    pub clip_hide: Option<Hidden>,
    /// Keep the side of a plane NX,NY,NZ,D where n·x + d >= 0, x in file coordinates (repeatable, at most 6).
    #[arg(long = "clip-plane", value_parser = |t: &str| clip::parse_plane(t).map_err(|e| e.to_string()), allow_hyphen_values = true)]
    pub clip_planes: Vec<[f64; 4]>,
}

impl SceneArgs {
    /// The clip region: the flags' when any is given (they replace a scene
    /// file's `[clip]` and a sidecar's), else the scene's.
    pub fn clip_region(&self, scene: &Scene) -> Result<ClipRegion, String> {
        self.clip_region_or(&scene.clip)
    }

    /// The flags' clip region when any is given, else `otherwise`.
    pub fn clip_region_or(&self, otherwise: &ClipRegion) -> Result<ClipRegion, String> {
        if self.clip_box.is_none() && self.clip_planes.is_empty() {
            return Ok(otherwise.clone());
        }
        let clip_box = self.clip_box.map(|b| ClipBox { hide: self.clip_hide.unwrap_or_default(), ..b });
        let region = ClipRegion { clip_box, planes: self.clip_planes.clone() };
        region.check().map_err(|e| e.to_string())?;
        Ok(region)
    }

    /// Applies `--opacity`, `--color` and the style to the scene's objects.
    pub fn apply_materials(&self, scene: &mut Scene) -> Result<(), String> {
        self.materials(false).apply(scene)
    }

    /// The style the colour and opacity flags give (`None` when none is given).
    pub fn style(&self) -> Option<Style> {
        let style = Style {
            color_by: self.color_by.clone(),
            colormap: self.colormap.unwrap_or_default(),
            range: self.range,
            classes: (!self.classes.is_empty()).then(|| self.classes.clone()),
            class_opacity: self.class_opacity.clone(),
            opacity_by: self.opacity_by.clone(),
            filters: self.filters.clone(),
            returns: self.returns,
            regions: Vec::new(),
        };
        // `--color-by rgb` alone asks for the file's own colours, over a default colouring.
        (self.color_by.is_some() || !style.is_plain()).then_some(style)
    }

    /// The materials of every object opened; `background_given`: the scene's
    /// own background is not used.
    pub fn materials(&self, background_given: bool) -> Materials {
        Materials {
            opacity: self.opacity,
            colour: self.colour,
            style: self.style().map(Arc::new),
            scene_background: !background_given,
        }
    }
}

/// `R,G,B`, each 0..255.
pub fn parse_rgb(text: &str) -> Result<[u8; 3], String> {
    let values: Vec<&str> = text.split(',').map(str::trim).collect();
    match values[..] {
        [r, g, b] => {
            let c = |v: &str| v.parse::<u8>().map_err(|_| format!("'{v}' is not a value in 0..255"));
            Ok([c(r)?, c(g)?, c(b)?])
        }
        _ => Err(format!("'{text}' is not R,G,B (three values in 0..255)")),
    }
}

/// One ASPRS class number of `--classes`.
pub(super) fn parse_class(text: &str) -> Result<u8, String> {
    parse::classes(text).map(|c| c[0])
}

/// One `CLASS:OPACITY` pair of `--class-opacity`.
fn parse_class_opacity(text: &str) -> Result<(u8, f32), String> {
    parse::class_opacity(text).map(|c| c[0])
}

/// `A` in 0..1.
pub fn parse_opacity(text: &str) -> Result<f32, String> {
    text.parse::<f32>()
        .ok()
        .filter(|a| (0.0..=1.0).contains(a))
        .ok_or_else(|| format!("'{text}' is not an opacity in 0..1"))
}

/// `--light X,Y,Z`.
pub fn parse_light(text: &str) -> Result<pointblend::frame::Light, String> {
    pointblend::frame::Light::parse_point(text).map_err(|e| e.to_string())
}

/// `--clip-hide`: inside or outside.
pub(super) fn parse_hidden(text: &str) -> Result<Hidden, String> {
    match text {
        "inside" => Ok(Hidden::Inside),
        "outside" => Ok(Hidden::Outside),
        _ => Err(format!("'{text}' is not inside or outside")),
    }
}
