//! `pointblend pick FILE --at X,Y`: the layers the pixel's ray passes, by
//! the exact reference (crates/core/src/reference/pick.rs), with the file's
//! attributes; text for people, `--json` for scripts. `measure` picks the
//! same way.

use std::path::PathBuf;

use anyhow::{Result, bail};
use pointblend::frame::{Camera, RenderMode};
use pointblend::inspect::PickReport;
use pointblend::reference::{ReferenceOptions, pick};
use pointblend::scene::Scene;

use super::shared::{self, CameraArgs, ViewArgs};

/// The flags of `pick` and `measure`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[arg(help = super::formats_help::drawn_file())]
    pub file: PathBuf,
    /// More files picked with the first, as layers (each its own object and origin).
    #[arg(id = "more_files", value_name = "MORE")]
    pub layers: Vec<PathBuf>,
    /// A pixel X,Y (from the top left, in the --size image) whose ray is
    /// cast; repeatable (measure: at least two, in order along the polyline).
    #[arg(long = "at", value_parser = parse_pixel)]
    pub at: Vec<(u32, u32)>,
    /// Print JSON. pick: {"pixel": [x, y], "layers": [...]} (an array of them
    /// for several --at); measure: {"points", "distance", "segments", "angle_deg", "angles_deg", "height"}.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub camera: CameraArgs,
    /// The size, parameter, scene and streaming flags of `render` (the layers
    /// are always the exact reference's, of the scene as defined).
    #[command(flatten)]
    pub view: ViewArgs,
}

/// `X,Y`: a pixel.
pub fn parse_pixel(text: &str) -> Result<(u32, u32), String> {
    let bad = || format!("'{text}' is not a pixel X,Y (two whole numbers)");
    let (x, y) = text.split_once(',').ok_or_else(bad)?;
    Ok((x.trim().parse().map_err(|_| bad())?, y.trim().parse().map_err(|_| bad())?))
}

/// What picking needs: the scene (streamed files: the view's selection),
/// the camera and the reference's options, as `render` makes them.
pub struct Picking {
    pub scene: Scene,
    pub camera: Camera,
    pub options: ReferenceOptions,
    pub size: (u32, u32),
}

impl Picking {
    pub fn open(args: &Args) -> Result<Self> {
        let (file, view, flags, pixels) = (args.file.as_path(), &args.view, &args.camera, &args.at);
        let size = view.size;
        if let Some(&(x, y)) = pixels.iter().find(|(x, y)| *x >= size.0 || *y >= size.1) {
            bail!("pixel {x},{y} is outside the {}x{} image (--size)", size.0, size.1);
        }
        let (scene, camera) = if super::layers::is_layered(file, &args.layers) {
            let files = (file, args.layers.as_slice());
            let opened = super::layers::load_layers(files, view, flags, RenderMode::RULER)?;
            let mut scene = opened.scene;
            view.scene.apply_materials(&mut scene).map_err(anyhow::Error::msg)?;
            let camera = match opened.camera {
                Some(camera) => camera,
                None => view.camera(flags, &scene)?,
            };
            (scene, camera)
        } else {
            match view.stream.open(file, pointblend::copc::drawn_by_nodes(file, view.stream_budget()?))? {
                Some(mut stream) => {
                    let bounds = super::stream_args::bounds_scene(&stream);
                    let camera = view.camera(flags, &super::stream_args::framing_scene(&mut stream, &view.scene))?;
                    let choosing = pointblend::lod::Choosing::of(&view.base_settings(&bounds, RenderMode::RULER)?);
                    let mut scene =
                        super::stream_args::frame_scene(stream, &camera, size, (view.stream_budget()?, choosing))?.0;
                    view.scene.apply_materials(&mut scene).map_err(anyhow::Error::msg)?;
                    (scene, camera)
                }
                None => {
                    // Styled before the default camera, which frames the points the filters keep.
                    let mut scene = shared::load_scene(file)?;
                    view.scene.apply_materials(&mut scene).map_err(anyhow::Error::msg)?;
                    let camera = view.camera(flags, &scene)?;
                    (scene, camera)
                }
            }
        };
        let settings = view.base_settings(&scene, RenderMode::RULER)?;
        let facts = scene.facts(&scene.flattened());
        let spec = pointblend::frame::resolve(&settings, &facts, &pointblend::frame::View::still(size));
        let options = pick::options(&spec.drawn, &scene);
        Ok(Picking { scene, camera, options, size })
    }

    /// The layers under `pixel`.
    pub fn pick(&self, (x, y): (u32, u32)) -> PickReport {
        PickReport::of(&self.scene, &self.camera, &self.options, self.size, [x, y])
    }
}

pub fn run(args: &Args) -> Result<()> {
    if args.at.is_empty() {
        bail!("pick needs at least one --at pixel X,Y");
    }
    let picking = Picking::open(args)?;
    let reports: Vec<PickReport> = args.at.iter().map(|&p| picking.pick(p)).collect();
    if args.json {
        let value = match reports.as_slice() {
            [one] => one.json(),
            many => serde_json::Value::Array(many.iter().map(PickReport::json).collect()),
        };
        println!("{}", serde_json::to_string_pretty(&value)?);
    } else {
        for report in &reports {
            print!("{}", report.text());
        }
    }
    Ok(())
}
