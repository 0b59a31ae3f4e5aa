//! The GPU renderer with its own output texture: every GPU frame is drawn
//! here and read back (`render`, bench, the viewer's render thread, tests).
//! A frame arrives decided ([`FrameSpec`]); a frame too large for the
//! sub-frame budget is drawn a sub-frame at a time ([`crate::subframe`]).

use super::context::{GpuContext, GpuError};
use super::gpu_scene::GpuScene;
use super::plan::RenderPlan;
use super::readback;
use super::renderer::Renderer;
use super::report::{FrameReport, SubFrames, TileLists};
use crate::frame::settings::RenderSettings;
use crate::frame::{Camera, FrameSpec, FrontDepth, View, resolve};
use crate::grouping::Grouping;
use crate::scene::Scene;
use crate::subframe::{self, SubFrame};

/// Format of the output images.
pub const OUTPUT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// Most bytes of render targets (with the output texture and its readback)
/// one render of an image may take: a frame that needs more is drawn a
/// sub-frame at a time ([`crate::subframe`]), so its memory does not grow with its size.
pub const DEFAULT_SUBFRAME_BUDGET: u64 = 1 << 30;

/// A GPU context, a renderer and an output texture.
pub struct GpuRenderer {
    pub ctx: GpuContext,
    pub renderer: Renderer,
    output: Option<wgpu::Texture>,
    /// [`DEFAULT_SUBFRAME_BUDGET`], or what [`Self::set_subframe_budget`] set.
    subframe_budget: u64,
    /// The parts the last `tiled` frame too large for its memory was drawn
    /// in, with its size and the scene's splat slots: the next such frame
    /// starts from them rather than finding them again.
    tile_parts: Option<TileParts>,
}

/// Parts of a `tiled` frame of `size` over a scene of `slots` splat slots.
struct TileParts {
    size: (u32, u32),
    slots: usize,
    parts: Vec<SubFrame>,
}

impl GpuRenderer {
    pub fn new() -> Result<Self, GpuError> {
        let ctx = GpuContext::headless()?;
        let renderer = Renderer::new(&ctx)?;
        Ok(Self { ctx, renderer, output: None, subframe_budget: DEFAULT_SUBFRAME_BUDGET, tile_parts: None })
    }

    /// Sets the most bytes one render of an image may take (see [`DEFAULT_SUBFRAME_BUDGET`]).
    pub fn set_subframe_budget(&mut self, bytes: u64) {
        self.subframe_budget = bytes;
    }

    /// Uploads `scene`, group by group when a grouping of it is given, with
    /// its environment map if it has one.
    pub fn upload(&self, scene: &Scene, grouping: Option<&Grouping>) -> GpuScene {
        self.upload_in(&scene.flattened(), scene.environment.as_deref(), grouping)
    }

    /// Uploads a scene's splats in world space, `cloud`, with the scene's environment map.
    pub fn upload_in(
        &self,
        cloud: &crate::cloud::PointCloud,
        environment: Option<&crate::scene::environment_map::EnvironmentMap>,
        grouping: Option<&Grouping>,
    ) -> GpuScene {
        let mut gpu = GpuScene::upload_cloud(&self.ctx.device, cloud, grouping);
        gpu.set_environment(&self.ctx.device, &self.ctx.queue, environment);
        gpu
    }

    /// [`Self::upload_in`] with the splats arranged as `arrangement` says (a node pool's, or packed).
    pub fn upload_arranged(
        &self,
        cloud: &crate::cloud::PointCloud,
        environment: Option<&crate::scene::environment_map::EnvironmentMap>,
        arrangement: crate::gpu_scene::Arrangement<'_>,
    ) -> GpuScene {
        let mut gpu = GpuScene::upload_arranged(&self.ctx.device, cloud, arrangement);
        gpu.set_environment(&self.ctx.device, &self.ctx.queue, environment);
        gpu
    }

    /// Uploads a cloud already in world space (a scene's flattened splats).
    pub fn upload_cloud(&self, cloud: &crate::cloud::PointCloud, grouping: Option<&Grouping>) -> GpuScene {
        GpuScene::upload_cloud(&self.ctx.device, cloud, grouping)
    }

    /// Renders one frame of `settings` at `size` on a bare upload and
    /// submits it, without reading it back ([`Self::render_image`]'s frame).
    pub fn render(
        &mut self,
        scene: &mut GpuScene,
        camera: &Camera,
        settings: &RenderSettings,
        size: (u32, u32),
    ) -> Result<RenderPlan, GpuError> {
        let spec = resolve(settings, &scene.facts(), &View::still(size));
        Ok(self.render_spec(scene, camera, &spec, false)?.1)
    }

    /// Renders one frame of `settings` on a bare upload (resolved over what
    /// `scene` holds, [`GpuScene::facts`]) and reads it back.
    pub fn render_image(
        &mut self,
        scene: &mut GpuScene,
        camera: &Camera,
        settings: &RenderSettings,
        width: u32,
        height: u32,
    ) -> Result<(image::RgbaImage, RenderPlan), GpuError> {
        let spec = resolve(settings, &scene.facts(), &View::still((width, height)));
        self.render_spec(scene, camera, &spec, true).map(|(image, plan, _)| (image, plan))
    }

    /// The one way a GPU frame is drawn: the frame `spec` of `scene` from
    /// `camera`, read back when `read` (else the image is empty, 0×0: bench's
    /// timed frames). A frame whose targets pass the sub-frame budget is drawn
    /// a sub-frame at a time whether or not it is read back, so a timed frame
    /// runs the plan the saved image runs. Returns the image, the plan (the
    /// largest sub-frame's when drawn in sub-frames) and what the frame measured.
    pub fn render_spec(
        &mut self,
        scene: &mut GpuScene,
        camera: &Camera,
        spec: &FrameSpec,
        read: bool,
    ) -> Result<(image::RgbaImage, RenderPlan, FrameReport), GpuError> {
        let (width, height) = spec.size;
        // The whole frame's plan, made once: it says whether the frame fits, and runs when it does.
        let whole = Renderer::plan_spec(scene, camera, spec, (width, height))?;
        let subframes = self.subframes(&whole, (width, height));
        let margin = subframe::margin(&whole);
        if subframes.len() > 1 {
            return self.render_subframes(scene, camera, spec, (&subframes, margin, false), read);
        }
        let known = self.tile_parts.as_ref().filter(|t| t.size == (width, height) && t.slots == scene.slot_count());
        if let Some(parts) = known.filter(|_| whole.compute_passes() > 0).map(|t| t.parts.clone()) {
            return self.render_subframes(scene, camera, spec, (&parts, margin, true), read);
        }
        let tile_lists = match self.render_subframe(scene, (camera, spec), SubFrame::whole((width, height)), &whole) {
            // A `tiled` frame whose splats or lists would pass its memory is drawn in parts.
            Err(GpuError::TilesDoNotFit { message, over }) => {
                let parts = subframe::split(SubFrame::whole((width, height)), over)
                    .ok_or(GpuError::TilesDoNotFit { message, over })?;
                return self.render_subframes(scene, camera, spec, (&parts, margin, true), read);
            }
            drawn => drawn?,
        };
        let window_overflows = self.window_overflows(tile_lists.is_some());
        let mut whole = whole;
        if let Some(lists) = &tile_lists {
            // The plan states the tile buffers the frame held, now that they are known.
            whole.buffers = lists.buffers.clone();
        }
        let report = FrameReport { tile_lists, window_overflows, ..Default::default() };
        if !read {
            return Ok((image::RgbaImage::new(0, 0), whole, report));
        }
        let image = readback::read_rgba8(&self.ctx, self.output_texture()?)?;
        Ok((image, whole, report))
    }

    /// Renders `part` of a frame by `plan` (the sub-frame's) into an output
    /// texture of its size and submits it.
    fn render_subframe(
        &mut self,
        scene: &mut GpuScene,
        frame: (&Camera, &FrameSpec),
        part: SubFrame,
        plan: &RenderPlan,
    ) -> Result<Option<TileLists>, GpuError> {
        let (width, height) = part.size;
        self.ctx.check_size(width, height)?;
        if self.output.as_ref().is_none_or(|t| (t.width(), t.height()) != (width, height)) {
            self.output = Some(self.ctx.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("GpuRenderer::output"),
                size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: OUTPUT_FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            }));
        }
        let view = self.output_texture()?.create_view(&Default::default());
        self.renderer.render_planned(&self.ctx, scene, frame, (&view, OUTPUT_FORMAT), part, plan)
    }

    /// The sub-frames a `size` frame whose plan is `plan` is drawn in: the whole frame when its
    /// targets, output texture and readback fit the sub-frame budget and the
    /// GPU's limits, else sub-frames that do ([`subframe::tiles`]). When not even
    /// a sub-frame of [`subframe::MIN_SIDE`] fits, the whole frame, which the
    /// renderer then refuses with the memory it needs and what to change.
    fn subframes(&self, plan: &RenderPlan, size: (u32, u32)) -> Vec<SubFrame> {
        let limits = self.ctx.device.limits();
        let pixels = (size.0 as u64 * size.1 as u64).max(1);
        // The output texture and its readback take 4 bytes a pixel each.
        let per_pixel = plan.target_bytes() as f64 / pixels as f64 + 8.0;
        let budget = self.subframe_budget.min(self.ctx.target_budget());
        let max_pixels = ((budget as f64 / per_pixel) as u64).min(limits.max_buffer_size / 4);
        if max_pixels < (subframe::MIN_SIDE * subframe::MIN_SIDE) as u64 {
            return vec![SubFrame::whole(size)];
        }
        subframe::tiles(size, max_pixels, limits.max_texture_dimension_2d)
    }

    /// A frame drawn sub-frame by sub-frame, each grown by `margin` ([`subframe::margin`]) for
    /// the passes that read neighbours and cropped to the part it keeps
    /// (read back only when `read`). A sub-frame whose `tiled` splats or
    /// lists would pass the memory given to it is cut into smaller ones
    /// ([`subframe::split`]) and those are drawn instead; only a part too
    /// small to cut is an error. `tile_parts`: the sub-frames are such parts
    /// already; the parts drawn are then kept for the next frame of this
    /// size, unless the splats reaching them would fill under half the slots
    /// (the next frame tries the whole frame again).
    fn render_subframes(
        &mut self,
        scene: &mut GpuScene,
        camera: &Camera,
        spec: &FrameSpec,
        (subframes, margin, tile_parts): (&[SubFrame], u32, bool),
        read: bool,
    ) -> Result<(image::RgbaImage, RenderPlan, FrameReport), GpuError> {
        let (width, height) = subframes[0].frame;
        log::info!("{width}x{height} is drawn in {} sub-frames, so that its memory stays bounded", subframes.len());
        let mut image = image::RgbaImage::new(if read { width } else { 0 }, if read { height } else { 0 });
        let mut largest: Option<(RenderPlan, Option<TileLists>)> = None;
        let mut window_overflows = None;
        let mut pending: Vec<SubFrame> = subframes.iter().rev().copied().collect();
        let (mut count, mut for_tiles) = (0, tile_parts);
        let (mut parts_drawn, mut packed) = (Vec::new(), Some(0));
        while let Some(kept) = pending.pop() {
            let drawn = kept.grown(margin);
            let plan = Renderer::plan_spec(scene, camera, spec, drawn.size)?;
            let lists = match self.render_subframe(scene, (camera, spec), drawn, &plan) {
                Err(GpuError::TilesDoNotFit { message, over }) => {
                    let parts = subframe::split(kept, over).ok_or_else(|| GpuError::TilesDoNotFit {
                        message: format!(
                            "{message}, even in a part of {}x{} pixels: use a smaller --size or another mode, or give \
                             the frame more memory (POINTBLEND_GPU_MEMORY_MB)",
                            drawn.size.0, drawn.size.1
                        ),
                        over,
                    })?;
                    pending.extend(parts.into_iter().rev());
                    for_tiles = true;
                    continue;
                }
                drawn => drawn?,
            };
            count += 1;
            parts_drawn.push(kept);
            // The splats that reached the parts, summed (none when they were not packed).
            packed = packed.zip(lists.as_ref().and_then(|l| l.packed)).map(|(sum, p)| sum + p);
            if let Some(n) = self.window_overflows(lists.is_some()) {
                *window_overflows.get_or_insert(0) += n;
            }
            if read {
                let part = readback::read_rgba8(&self.ctx, self.output_texture()?)?;
                let (x, y) = (kept.origin.0 - drawn.origin.0, kept.origin.1 - drawn.origin.1);
                let kept_part = image::imageops::crop_imm(&part, x, y, kept.size.0, kept.size.1).to_image();
                image::imageops::replace(&mut image, &kept_part, kept.origin.0 as i64, kept.origin.1 as i64);
            }
            // The report's plan and lists: the largest part's, by its targets then its lists.
            let size_of = |p: &RenderPlan, l: &Option<TileLists>| (p.target_bytes(), l.as_ref().map_or(0, |l| l.kept));
            if largest.as_ref().is_none_or(|(p, l)| size_of(p, l) < size_of(&plan, &lists)) {
                largest = Some((plan, lists));
            }
        }
        let (mut plan, tile_lists) = largest.ok_or_else(|| GpuError::Device("a frame of no sub-frames".into()))?;
        if let Some(lists) = &tile_lists {
            plan.buffers = lists.buffers.clone();
        }
        log::info!("{width}x{height} was drawn in {count} parts");
        let slots = tile_lists.as_ref().map_or(0, |l| l.slots);
        self.tile_parts = packed.filter(|&p| for_tiles && 2 * p > slots).map(|_| TileParts {
            size: (width, height),
            slots: scene.slot_count(),
            parts: parts_drawn,
        });
        let subframes = SubFrames {
            count,
            for_tiles,
            largest: (plan.width, plan.height),
            margin,
            budget_mib: self.subframe_budget.min(self.ctx.target_budget()) >> 20,
        };
        let report = FrameReport { subframes: Some(subframes), tile_lists, window_overflows, ..Default::default() };
        Ok((image, plan, report))
    }

    /// The pixels of the frame just drawn whose tile window overflowed,
    /// when it was `tiled` (read with its result, [`crate::tile_engine::TileEngine::finish_frame`]).
    fn window_overflows(&self, tiled: bool) -> Option<u32> {
        self.renderer.tile_engine().filter(|_| tiled).map(|t| t.last.window_overflows)
    }

    /// [`Renderer::use_subgroups`] on this renderer's device.
    pub fn use_subgroups(&mut self, on: bool) -> bool {
        self.renderer.use_subgroups(&self.ctx, on)
    }

    /// [`Renderer::stop_early`] on this renderer.
    pub fn stop_early(&mut self, on: bool) {
        self.renderer.stop_early(on);
    }

    /// The nearest surface per pixel of the last frame, drawn by `plan` from
    /// `camera`, where its plan keeps one (two-pass) and it was drawn whole
    /// (a frame drawn in sub-frames keeps only its last part's targets).
    pub fn front_depth(&self, plan: &RenderPlan, camera: &Camera) -> Result<Option<FrontDepth>, GpuError> {
        let Some(front) = plan.front_depth else { return Ok(None) };
        let size = (plan.width, plan.height);
        let Some(texture) = self.renderer.target_texture(front.target).filter(|t| (t.width(), t.height()) == size)
        else {
            return Ok(None);
        };
        let buffer = readback::read_depth32(&self.ctx, texture)?;
        Ok(Some(FrontDepth::from_buffer(camera, size, &buffer, front.push)))
    }

    fn output_texture(&self) -> Result<&wgpu::Texture, GpuError> {
        self.output.as_ref().ok_or_else(|| GpuError::Device("no output texture".into()))
    }
}
