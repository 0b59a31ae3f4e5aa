//! `pointblend render FILE`: one frame to an image, written atomically.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use pointblend::copc::StreamBudget;
use pointblend::frame::{Camera, Parameter, RenderMode, RenderSettings, Sidecar, View, ViewPath};
use pointblend::lod::Choosing;
use pointblend::reference::{self, ReferenceOptions};
use pointblend::render::{Frame, GpuRenderer, PreparedScene, Readback};
use pointblend::scene::environment_map::EnvironmentMap;
use pointblend::scene::{Look, Scene};

use super::shared::{self, CameraArgs, ViewArgs};
use super::stream_args::StreamedFlight;

#[derive(clap::Args, Debug)]
pub struct Args {
    #[arg(help = super::formats_help::drawn_file())]
    pub file: PathBuf,
    /// More files drawn with the first, as layers: each its own object, origin and attributes
    /// (the flags style every layer; a scene file styles each).
    #[arg(id = "more_files", value_name = "MORE")]
    pub layers: Vec<PathBuf>,
    /// Rendering mode. tiled (exact) becomes the default only once it is at
    /// least as fast as two-pass wherever measured: on an H200 it is the
    /// fastest mode, on lavapipe its frame takes 1.16-2.19 times two-pass's
    /// (README, "Render modes").
    #[arg(long, default_value_t = RenderMode::DEFAULT, value_parser = shared::mode_parser())]
    pub mode: RenderMode,
    #[command(flatten)]
    pub camera_flags: CameraArgs,
    #[command(flatten)]
    pub view: ViewArgs,
    /// Output image (.png or .jpg).
    #[arg(long, default_value = "pointblend.png")]
    pub out: PathBuf,
    /// Print the passes and targets that will run.
    #[arg(long)]
    pub explain: bool,
    /// Also render the exact reference, print the error against it and write
    /// a false-colour difference image (amplified 8x) to this image.
    #[arg(long)]
    pub diff: Option<PathBuf>,
    /// Reproduce a viewer screenshot: take the mode, parameters, grouping, camera
    /// and size from its JSON sidecar (the other view options are ignored), and its
    /// colour and opacity by attribute unless --color-by and the like are given.
    #[arg(long, value_name = "SIDECAR.json")]
    pub camera: Option<PathBuf>,
    #[arg(long, value_name = "FILE", help = shared::environment_help())]
    pub env: Option<PathBuf>,
    /// Keep the flat background colour where nothing is drawn, instead of the environment map.
    #[arg(long)]
    pub flat_background: bool,
    /// Renders a moving scene at this time, in seconds (animations loop)
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    pub time: Option<f64>,
    /// Fly through the views of this file (bookmarked in the viewer):
    /// --out frames/f.png writes frames/f-0000.png ... and the animated frames/f.gif
    /// (a streamed file's frames each select their own nodes).
    #[arg(long, value_name = "VIEWS.json")]
    pub path: Option<PathBuf>,
    /// Frames of the --path flight, its first and last views included.
    #[arg(long, value_name = "N", default_value_t = 60, value_parser = clap::value_parser!(u32).range(2..=100_000))]
    pub path_frames: u32,
}

impl Args {
    /// Loads `--env` into the scene (in place of a scene file's map) and the
    /// environment options into the settings.
    fn apply_environment(&self, scene: &mut Scene, settings: &mut RenderSettings) -> Result<()> {
        let drawing = || -> String {
            RenderMode::ALL.iter().filter(|m| m.info().environment).map(|m| m.name()).collect::<Vec<_>>().join(", ")
        };
        if let Some(path) = &self.env {
            if !settings.mode.info().environment {
                bail!(
                    "{}: mode {} does not draw environment effects yet; modes that do: {}",
                    path.display(),
                    settings.mode,
                    drawing()
                );
            }
            let map = EnvironmentMap::load(path)?;
            if map.cleaned > 0 {
                log::warn!("{}: {} negative or non-finite values set to 0", path.display(), map.cleaned);
            }
            scene.environment = Some(std::sync::Arc::new(map));
        }
        let Some(map) = &scene.environment else { return Ok(()) };
        if !settings.mode.info().environment {
            log::warn!(
                "the scene's environment map {} is not drawn by {}; modes that draw it: {}",
                map.name,
                settings.mode,
                drawing()
            );
        }
        let env = &mut settings.environment;
        if env.dispersion >= env.eta {
            bail!("--dispersion must be below --eta ({}), not {}", env.eta, env.dispersion);
        }
        env.skybox = !self.flat_background;
        Ok(())
    }
}

/// The scene's frames at `--time` (0 for a moving scene without it), and a
/// note when a still scene is given a time.
fn moving_frames(scene: Scene, time: Option<f64>) -> Result<PreparedScene> {
    shared::check_time(time)?;
    if !scene.is_animated() {
        if time.is_some() {
            log::warn!("{}: nothing in the scene moves, so --time changes nothing", scene.name());
        }
        return Ok(PreparedScene::of(std::sync::Arc::new(scene)));
    }
    let at = scene.at_time(time.unwrap_or(0.0)).map_err(anyhow::Error::msg)?;
    log::info!("the scene at {:.3} s of its {:.3} s period", at.time, scene.animation_period());
    let lattice = pointblend::render::rest_lattice(&scene).map_err(anyhow::Error::msg)?;
    Ok(PreparedScene::of(std::sync::Arc::new(at.scene)).moving_on(lattice))
}

pub fn run(args: &Args) -> Result<()> {
    // Options are checked before anything is loaded or the GPU is opened.
    shared::check_time(args.time)?;
    let sidecar = args.camera.as_deref().map(Sidecar::read).transpose()?;
    let views = args.path.as_deref().map(ViewPath::read).transpose()?;
    check_outputs(args, views.is_some())?;
    let started = Instant::now();
    let (mut scene, streamed, layers_camera, layers_by_nodes) =
        open_scene(args, sidecar.as_ref(), views.as_ref().map(|v| v.camera_at(0.0)))?;
    let stream_camera = streamed.as_ref().map(|(camera, _)| *camera);
    let load_seconds = started.elapsed().as_secs_f64();
    let (settings, (width, height)) = frame_settings(args, sidecar.as_ref(), &mut scene)?;
    // A `.vpc`'s camera was framed on its boxes, to choose the files it reaches.
    let camera = match (stream_camera, layers_camera.filter(|_| sidecar.is_none())) {
        (Some(camera), _) | (None, Some(camera)) => camera,
        (None, None) => frame_camera(args, sidecar.as_ref(), &scene)?,
    };
    let mut gpu = match settings.mode.is_gpu() {
        true => Some(GpuRenderer::new().context("opening the GPU")?),
        false => None,
    };
    if let Some(gpu) = &gpu {
        log::info!("GPU: {}", gpu.ctx.describe());
    }
    let render_started = Instant::now();
    // A screenshot of a moving scene names its time; --time overrides it.
    let time = args.time.or(sidecar.as_ref().and_then(|s| s.time));
    let mut frames = moving_frames(scene, time)?;
    if stream_camera.is_some() || layers_by_nodes {
        frames = frames.streamed(); // the selection applied the budget
    }
    if let Some(views) = &views {
        let flight = super::render_path::Flight { file: &args.file, out: &args.out, frames: args.path_frames };
        let restream = streamed.map(|(_, flight)| flight);
        return super::render_path::run(
            &flight,
            views,
            &mut frames,
            (gpu.as_mut(), restream),
            &settings,
            (width, height),
        );
    }
    let spec = frames.resolve(&settings, View::still((width, height)));
    let Frame { image, plan, report } =
        frames.render_frame(gpu.as_mut(), &camera, &spec, Readback::ImageWithProgress)?;
    let scene = frames.scene();
    let render_seconds = render_started.elapsed().as_secs_f64();
    if args.explain {
        println!("{plan}");
        print!("{report}");
    }
    if spec.opaque_fallback {
        println!(
            "{}: this model is opaque, so {} ran two-pass; set --opacity below 1 to see through it",
            shared::shown_path(&args.file),
            settings.mode
        );
    }
    shared::write_image(&image, &args.out)?;
    if let Some(diff_path) = &args.diff {
        write_difference(scene, (&camera, &settings), &image, diff_path)?;
    }
    println!(
        "{}: {} splats, {} {}x{} in {:.0} ms (load {:.2} s) -> {}",
        shared::shown_path(&args.file),
        scene.len(),
        plan.mode,
        width,
        height,
        render_seconds * 1e3,
        load_seconds,
        args.out.display()
    );
    Ok(())
}

/// Checks every output before the work starts, so that none is written when
/// another cannot be; and that a camera path (`flying`) is given what it reads.
fn check_outputs(args: &Args, flying: bool) -> Result<()> {
    if flying && (args.camera.is_some() || args.diff.is_some()) {
        bail!("--path flies its own views: it takes neither --camera nor --diff");
    }
    shared::refuse_same_file(&args.out, "the input", &args.file)?;
    shared::prepare_image_output(&args.out)?;
    if let Some(diff) = &args.diff {
        shared::refuse_same_file(diff, "the input", &args.file)?;
        shared::refuse_same_file(diff, "the --out image", &args.out)?;
        shared::prepare_image_output(diff)?;
    }
    Ok(())
}

/// The scene to draw; a streamed file's first camera and flight; a `.vpc`'s camera.
/// Whether layers were drawn node by node (under the point budget already).
type OpenedScene = (Scene, Option<(Camera, StreamedFlight)>, Option<Camera>, bool);

/// The scene to draw, with the command line's materials and a screenshot's
/// style; a COPC file or URL is streamed: the nodes its view selects under
/// the point budget, and that view's camera.
/// The scene to draw; for a streamed file, the nodes the first camera
/// selects (a flight's `first`, else the sidecar's or the flags'), that
/// camera, and the stream to select each later camera's nodes from.
fn open_scene(args: &Args, sidecar: Option<&Sidecar>, first: Option<Camera>) -> Result<OpenedScene> {
    let mut streamed = None;
    if super::layers::is_layered(&args.file, &args.layers) {
        let files = (args.file.as_path(), args.layers.as_slice());
        let opened = super::layers::load_layers(files, &args.view, &args.camera_flags, args.mode)?;
        let mut scene = opened.scene;
        args.view.scene.apply_materials(&mut scene).map_err(anyhow::Error::msg)?;
        apply_screenshot_style(args, sidecar, &mut scene)?;
        return Ok((scene, None, opened.camera, opened.by_nodes));
    }
    // A screenshot's file is drawn as the window drew it: node by node or whole.
    let by_nodes = match sidecar {
        Some(s) => s.model.nodes || pointblend::copc::is_streamed(&args.file),
        None => pointblend::copc::drawn_by_nodes(&args.file, args.view.stream_budget()?),
    };
    let mut scene = match args.view.stream.open(&args.file, by_nodes)? {
        Some(mut stream) => {
            let bounds = super::stream_args::bounds_scene(&stream);
            let camera = match (first, sidecar) {
                (Some(camera), _) => camera,
                (None, Some(s)) => s.camera(),
                (None, None) => {
                    let framed = super::stream_args::framing_scene(&mut stream, &args.view.scene);
                    args.view.camera(&args.camera_flags, &framed)?
                }
            };
            let size = sidecar.map_or(args.view.size, |s| (s.size[0], s.size[1]));
            // Chosen as the frame's settings say: their radius scale, and every node when lit.
            let budget = match sidecar {
                Some(s) => {
                    let settings = s.settings().map_err(anyhow::Error::msg)?;
                    let lit = settings.lighting && !s.lights().map_err(anyhow::Error::msg)?.is_empty();
                    let choosing = Choosing { cull: !lit, ..Choosing::of(&settings) };
                    (StreamBudget::of_settings(settings.point_budget, false), choosing)
                }
                None => (args.view.stream_budget()?, Choosing::of(&args.view.base_settings(&bounds, args.mode)?)),
            };
            let (scene, subset) = super::stream_args::frame_scene(stream, &camera, size, budget)?;
            let materials = args.view.scene.materials(false);
            streamed = Some((camera, StreamedFlight { subset, choosing: budget.1, size, materials }));
            scene
        }
        None => shared::load_scene(&args.file)?,
    };
    args.view.scene.apply_materials(&mut scene).map_err(anyhow::Error::msg)?;
    apply_screenshot_style(args, sidecar, &mut scene)?;
    Ok((scene, streamed, None, false))
}

/// A screenshot's colours by attribute and filters, unless the command
/// line gives its own, each object's opacity and colour (each layer's),
/// unless it gives `--opacity` or `--color`, and each object's cut.
fn apply_screenshot_style(args: &Args, sidecar: Option<&Sidecar>, scene: &mut Scene) -> Result<()> {
    let (Some(sidecar), Some(path)) = (sidecar, &args.camera) else { return Ok(()) };
    if let (None, Some(record)) = (args.view.scene.style(), sidecar.style.as_ref()) {
        let style = record.style().map_err(|e| anyhow::anyhow!("{}: style: {e}", path.display()))?;
        scene.apply_style(&style).map_err(anyhow::Error::msg)?;
    }
    let flags = &args.view.scene;
    if !sidecar.looks.is_empty() {
        let mut looks = sidecar.looks.clone();
        if (flags.opacity.is_some() || flags.colour.is_some()) && looks.len() == scene.objects.len() {
            // The flags' opacity and colour, and each layer's cut as recorded.
            looks =
                scene.looks().into_iter().zip(&sidecar.looks).map(|(now, l)| Look { clip: l.clip, ..now }).collect();
        }
        scene.set_looks(&looks).map_err(|e| anyhow::anyhow!("{}: looks: {e}", path.display()))?;
    }
    Ok(())
}

/// The frame's settings and size: the flags', or a screenshot's with its
/// clip and lights; the environment applied.
fn frame_settings(args: &Args, sidecar: Option<&Sidecar>, scene: &mut Scene) -> Result<(RenderSettings, (u32, u32))> {
    let (mut settings, size) = match sidecar {
        Some(s) => (s.settings().map_err(anyhow::Error::msg)?, (s.size[0], s.size[1])),
        None => (args.view.settings(scene, args.mode)?, args.view.size),
    };
    if let Some(s) = sidecar {
        // The screenshot's clip, unless the command line gives one.
        let region = args.view.scene.clip_region_or(&s.clip.clone().unwrap_or_default()).map_err(anyhow::Error::msg)?;
        settings.clip = scene.clip_in_frame(&region);
        // Its lights, from file coordinates into the scene's frame.
        let lights: Vec<_> = s.lights().map_err(anyhow::Error::msg)?.iter().map(|l| scene.light_in_frame(l)).collect();
        settings.lights = pointblend::frame::Lights::new(&lights).map_err(|e| anyhow::anyhow!("lights: {e}"))?;
    }
    args.apply_environment(scene, &mut settings)?;
    let supersample = args.view.parameters.given(Parameter::Supersample);
    if let (Some(_), Some(n)) = (sidecar, supersample) {
        // The sidecar sets the view; --supersample still sets the reference's rays (and --diff's ruler).
        Parameter::Supersample.apply(&mut settings, n).map_err(anyhow::Error::msg)?;
    }
    let reads_supersample = settings.mode.parameters().contains(&Parameter::Supersample);
    if supersample.is_some() && !reads_supersample && args.diff.is_none() {
        log::warn!(
            "--supersample is ignored: mode {} does not use it (the reference does, and the ruler of --diff)",
            settings.mode
        );
    }
    Ok((settings, size))
}

/// The camera: a screenshot's (with a line when the file is not the one it
/// was saved from), else the flags' over the scene file's and the default view.
fn frame_camera(args: &Args, sidecar: Option<&Sidecar>, scene: &Scene) -> Result<Camera> {
    let Some(s) = sidecar else { return args.view.camera(&args.camera_flags, scene) };
    let hash = format!("{:016x}", scene.geometry_hash());
    if hash != s.model.hash {
        log::warn!(
            "{}: this file is not the one the view was saved from ({}, hash {})",
            shared::shown_path(&args.file),
            s.model.name,
            s.model.hash
        );
    }
    Ok(s.camera())
}

/// `--diff`: the exact reference of the frame, the error against it in one
/// line, and the false-colour difference image (amplified 8×) at `path`.
fn write_difference(
    scene: &Scene,
    (camera, settings): (&Camera, &RenderSettings),
    image: &image::RgbaImage,
    path: &std::path::Path,
) -> Result<()> {
    let (width, height) = image.dimensions();
    let options = ReferenceOptions { progress: true, ..ReferenceOptions::matching(settings, scene) };
    let exact = reference::render(scene, camera, &options, width, height);
    let error = reference::compare(image, &exact).context("image sizes differ")?;
    let diff = reference::difference_image(image, &exact, 8.0).context("image sizes differ")?;
    shared::write_image(&diff, path)?;
    println!(
        "error against the reference: ε {:.3}, PSNR {:.2} dB, {:.2}% pixels off by more than {}/255 -> {}",
        error.eps,
        error.psnr,
        100.0 * error.bad_pixel_share,
        reference::metrics::BAD_PIXEL_THRESHOLD,
        path.display()
    );
    Ok(())
}
