//! The renderer: runs a mode's plan into any view.
//!
//! A frame flows scene → plan → passes → image. The scene is uploaded once
//! ([`GpuScene`]); for each frame the mode of the registry plans its steps
//! ([`RenderPlan`]), each the commands of its render passes; the renderer
//! allocates exactly the plan's targets ([`TargetPool`]), writes the frame's
//! uniforms and one uniform slot per pass, and lets each pass record itself
//! (`record`: each kind in its own file, its pipeline from the cache,
//! [`PipelineCache`]), timed per plan pass when timing is on. Every frame
//! (`render`, `bench`, the viewer, the tests) reaches it through
//! [`crate::GpuRenderer`], which calls [`Renderer::render_planned`] once per
//! sub-frame; what the run counted comes back to go in the frame's report.

use glam::Mat4;
use wgpu::util::DeviceExt;

use super::context::{GpuContext, GpuError};
use super::gpu_data::{FrameUniforms, PASS_SLOT_BYTES, PassUniforms};
use super::gpu_scene::GpuScene;
use super::modes::FrameDesc;
use super::passes::Command;
use super::pipelines::PipelineCache;
use super::plan::{RenderPlan, TargetDesc, TargetId};
use super::record::{self, At, Recording, compute::TileRun};
use super::subframe::SubFrame;
use super::targets::TargetPool;
use super::tile_engine::TileEngine;
use super::tile_layout;
use super::timer::PassTimer;
use super::touches::Bound;
use crate::frame::spec::EpsilonRadius;
use crate::frame::{Camera, FrameSpec, RenderSettings};
use crate::report::TileLists;

pub struct Renderer {
    cache: PipelineCache,
    pool: TargetPool,
    frame_buffer: wgpu::Buffer,
    /// One [`PASS_SLOT_BYTES`] slot of [`PassUniforms`] per render pass of a frame.
    pass_buffer: wgpu::Buffer,
    pass_slots: u64,
    /// Group 0: the frame's uniforms and, at a dynamic offset, one pass slot's.
    frame_bind_group: wgpu::BindGroup,
    timer: Option<PassTimer>,
    timing: bool,
    /// Every texture view the last frame's passes were given, and where.
    bound: Vec<Bound>,
    /// The tile pipeline's buffers, made by the first frame that runs it.
    tiles: Option<TileEngine>,
    /// Whether `tiled`'s raster reads its lists a subgroup at a time; see
    /// shaders/tiled_raster.wgsl. By default on a software adapter with
    /// subgroup operations: on lavapipe the raster takes half the time, on
    /// an H200 5-10 % more (docs/BENCHMARKS.md), so hardware GPUs read by pixel.
    subgroups: bool,
    /// Whether a pixel of `tiled`'s raster stops once less light than can
    /// change an 8-bit channel gets through (on by default).
    early_stop: bool,
    /// Whether each step is waited for on its own and timed on the CPU
    /// (see [`Renderer::profile_steps`]), and the last frame's times.
    profile_steps: bool,
    step_ms: Option<Vec<f64>>,
}

impl Renderer {
    pub fn new(ctx: &GpuContext) -> Result<Self, GpuError> {
        ctx.checked("building the renderer", || {
            let device = &ctx.device;
            let cache = PipelineCache::new(device);
            let frame_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("Frame::uniforms"),
                contents: bytemuck::bytes_of(&FrameUniforms::zeroed()),
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            });
            let slots = 8;
            let pass_buffer = pass_buffer(device, slots);
            let frame_bind_group = frame_bind_group(device, &cache, &frame_buffer, &pass_buffer);
            Self {
                cache,
                pool: TargetPool::default(),
                frame_buffer,
                pass_buffer,
                pass_slots: slots,
                frame_bind_group,
                timer: None,
                timing: false,
                bound: Vec::new(),
                tiles: None,
                subgroups: device.features().contains(wgpu::Features::SUBGROUP)
                    && ctx.adapter.get_info().device_type == wgpu::DeviceType::Cpu,
                early_stop: true,
                profile_steps: false,
                step_ms: None,
            }
        })
    }

    /// Times every step of the following frames on the CPU, each submitted
    /// and waited for on its own ([`Renderer::step_times`]): where a software
    /// adapter's timestamps say nothing of compute passes. The waits slow
    /// the frame, so a profiled frame is not a timed one.
    pub fn profile_steps(&mut self, on: bool) {
        self.profile_steps = on;
    }

    /// Milliseconds per plan step of the last frame, when it was profiled.
    pub fn step_times(&self) -> Option<&[f64]> {
        self.step_ms.as_deref()
    }

    /// Makes `tiled`'s raster read its lists a subgroup at a time, or each
    /// pixel on its own (`false`; always so on a device without subgroup
    /// operations). Returns whether it now does.
    pub fn use_subgroups(&mut self, ctx: &GpuContext, on: bool) -> bool {
        self.subgroups = on && ctx.device.features().contains(wgpu::Features::SUBGROUP);
        self.subgroups
    }

    /// Makes `tiled`'s raster stop a pixel once less light than can change
    /// an 8-bit channel gets through, behind an opaque layer at once (the
    /// default), or composite every layer its ray meets (`false`).
    pub fn stop_early(&mut self, on: bool) {
        self.early_stop = on;
    }

    /// Turns per-pass GPU timestamps on; returns false when the adapter has none.
    pub fn enable_pass_timing(&mut self, ctx: &GpuContext) -> bool {
        self.timing = ctx.device.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        self.timing
    }

    /// Milliseconds per plan pass of the last frame (waits for it), if timing is on.
    /// None as well for a plan of compute passes on a software adapter:
    /// lavapipe's timestamps around a compute pass do not enclose its
    /// dispatches (they read 0.01-3 ms around a raster that takes a second).
    pub fn pass_times(&self, ctx: &GpuContext, plan: &RenderPlan) -> Result<Option<Vec<f64>>, GpuError> {
        if plan.compute_passes() > 0 && ctx.adapter.get_info().device_type == wgpu::DeviceType::Cpu {
            return Ok(None);
        }
        self.timer.as_ref().filter(|_| self.timing).map(|t| t.read(ctx, plan.steps.len())).transpose()
    }

    /// The targets the pool holds now (those of the last frame's plan).
    pub fn allocated_targets(&self) -> Vec<TargetDesc> {
        self.pool.descs()
    }

    /// The texture of a target the pool holds now (of the last frame's plan).
    pub fn target_texture(&self, id: TargetId) -> Option<&wgpu::Texture> {
        self.pool.texture(id)
    }

    /// Bytes of the targets the pool holds now.
    pub fn allocated_bytes(&self) -> u64 {
        self.pool.bytes()
    }

    /// Pipelines built so far.
    pub fn pipelines_built(&self) -> usize {
        self.cache.len()
    }

    /// The shader modules built so far: (root file, variant).
    pub fn modules_built(&self) -> Vec<(&'static str, super::shaders::Variant)> {
        self.cache.modules()
    }

    /// The tile pipeline's buffers, if a frame has run it.
    pub fn tile_engine(&self) -> Option<&TileEngine> {
        self.tiles.as_ref()
    }

    /// The texture views the last frame's passes were given, recorded as
    /// their bind groups and attachments were made.
    pub fn last_frame_bindings(&self) -> &[Bound] {
        &self.bound
    }

    /// The target a view of the pool belongs to, by identity, and its layer.
    pub fn target_of(&self, view: &wgpu::TextureView) -> Option<(TargetId, Option<u32>)> {
        self.pool.target_of(view)
    }

    /// What the frame's mode needs to know: the spec, the size and the scene.
    fn frame_desc<'a>(
        scene: &'a GpuScene,
        camera: &Camera,
        spec: &'a FrameSpec,
        (width, height): (u32, u32),
    ) -> FrameDesc<'a> {
        let settings = &spec.drawn;
        let mean_radius = match spec.epsilon_radius {
            EpsilonRadius::Drawn => scene.mean_radius,
            EpsilonRadius::Scene(radius) => radius,
        };
        let epsilon = settings.epsilon(mean_radius);
        let (near, far) = camera.near_far();
        // Eq. 10 over the scene's depth range (near and far enclose its sphere).
        let depth_steps = super::depth_steps::depth_steps(near, far, epsilon * settings.depth_step);
        let lights = spec.lights;
        FrameDesc {
            settings,
            spec,
            width,
            height,
            splats: scene.len,
            groups: &scene.groups,
            transparent_groups: &scene.transparent_groups,
            opaque: scene.opaque.clone(),
            // Lit colours differ per splat even where the albedo does not.
            uniform_colour: scene.uniform_colour.filter(|_| !lights),
            epsilon,
            depth_steps,
            transparent: scene.transparent,
            environment: scene.environment.as_ref().filter(|_| spec.environment),
            sums: scene.sums,
            lights,
            triangles: scene.triangles.as_ref().map_or(0, |t| t.count()),
        }
    }

    /// The plan of the frame `spec` at `size` (the frame's, or a window's), without running it.
    pub fn plan_spec(
        scene: &GpuScene,
        camera: &Camera,
        spec: &FrameSpec,
        size: (u32, u32),
    ) -> Result<RenderPlan, GpuError> {
        super::modes::plan(&Self::frame_desc(scene, camera, spec, size))
            .ok_or_else(|| GpuError::Device(format!("mode {} does not run on the GPU", spec.mode())))
    }

    /// Renders `window` of the frame `spec` into `output` (of `format`, the
    /// window's size) by the window's plan, made already ([`Self::plan_spec`]
    /// at its size), and returns what the run measured. The scene is changed
    /// only where the plan blends in order: its instances are sorted back to
    /// front for the camera first (in place, so an unchanged view sorts nothing).
    pub fn render_planned(
        &mut self,
        ctx: &GpuContext,
        scene: &mut GpuScene,
        (camera, spec): (&Camera, &FrameSpec),
        (output, format): (&wgpu::TextureView, wgpu::TextureFormat),
        window: SubFrame,
        plan: &RenderPlan,
    ) -> Result<Option<TileLists>, GpuError> {
        let size = window.size;
        ctx.check_size(size.0, size.1)?;
        plan.check_fits(&ctx.device.limits(), ctx.target_budget())?;
        if plan.back_to_front() {
            scene.order_back_to_front(&ctx.queue, camera.view_ray(), spec.drawn.order);
        }
        let scene = &*scene;
        let tiled = plan.compute_passes() > 0;
        // What the tile pipeline's per-splat buffers and lists may take: the
        // frame's memory beside its targets and per-tile tables.
        let budget = ctx.target_budget().saturating_sub(plan.target_bytes() + tile_layout::table_bytes(size));
        if tiled {
            match self.tiles.as_mut() {
                Some(tiles) if tiles.fits(ctx, scene, budget) => tiles.set_grid(ctx, scene, size)?,
                _ => {
                    self.tiles = None; // free the old buffers first
                    self.tiles = Some(TileEngine::new(ctx, scene, size, budget)?);
                }
            }
        }
        let commands: Vec<(usize, &Command)> = plan.commands().collect();
        let allocated =
            ctx.allocating("allocating the render targets", || self.pool.prepare(&ctx.device, &plan.targets));
        if let Err(e) = allocated {
            self.pool.clear(); // do not keep textures whose allocation failed
            return Err(e);
        }
        self.ensure_pass_slots(ctx, commands.len() as u64);
        if self.timing && self.timer.as_ref().is_none_or(|t| t.capacity() < plan.steps.len()) {
            self.timer = PassTimer::new(ctx, plan.steps.len());
        }
        let environment_width = scene.environment.as_ref().map_or(0, |e| e.width);
        let uniforms = frame_uniforms(camera, spec, &window, environment_width);
        ctx.queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&uniforms));
        let mut slots = vec![0u8; commands.len() * PASS_SLOT_BYTES as usize];
        for (i, (_, command)) in commands.iter().enumerate() {
            let uniforms = command.uniforms();
            let at = i * PASS_SLOT_BYTES as usize;
            slots[at..at + std::mem::size_of::<PassUniforms>()].copy_from_slice(bytemuck::bytes_of(uniforms));
        }
        ctx.queue.write_buffer(&self.pass_buffer, 0, &slots);
        let mut retried = false;
        loop {
            if let Some(tiles) = self.tiles.as_mut().filter(|_| tiled) {
                tiles.begin_frame(ctx, budget)?;
            }
            ctx.checked("rendering", || self.encode(ctx, scene, plan, &commands, output, format))??;
            let Some(tiles) = self.tiles.as_mut().filter(|_| tiled) else { return Ok(None) };
            // What the lists met comes back with the frame's result; a frame
            // whose lists passed their room drew them empty and is drawn again.
            let met = tiles.finish_frame(ctx)?;
            if !met.overflow || retried {
                break;
            }
            if let Some(packed) = met.packed.filter(|&p| p > tiles.slots()) {
                // More splats reach this part than the slots hold: smaller parts.
                return Err(GpuError::TilesDoNotFit {
                    message: format!(
                        "tiled: {packed} splats reach a {}x{} part of the frame, more than the {} its memory holds",
                        size.0,
                        size.1,
                        tiles.slots()
                    ),
                    over: packed as f64 / tiles.slots() as f64,
                });
            }
            tiles.make_room(ctx, met.entries, budget)?;
            retried = true;
        }
        let tiles = self.tiles.as_ref().expect("a tiled frame has its engine");
        if tiles.last.overflow {
            return Err(GpuError::Device(format!(
                "tiled: the tile lists passed their room ({} entries) twice in one frame",
                tiles.entry_capacity()
            )));
        }
        Ok(Some(TileLists {
            entries: tiles.last.entries,
            kept: tiles.last.kept,
            capacity: tiles.entry_capacity(),
            longest: tiles.last.longest_list,
            retried,
            slots: tiles.slots(),
            packed: tiles.last.packed,
            buffers: tile_layout::planned_buffers(
                tiles.slots() as usize + scene.triangles.as_ref().map_or(0, |t| t.count() as usize),
                size,
                Some((tiles.last.entries, tiles.entry_capacity())),
            ),
        }))
    }

    /// Grows the pass uniform buffer to at least `slots` slots.
    fn ensure_pass_slots(&mut self, ctx: &GpuContext, slots: u64) {
        if slots > self.pass_slots {
            self.pass_slots = slots.next_power_of_two();
            self.pass_buffer = pass_buffer(&ctx.device, self.pass_slots);
            self.frame_bind_group = frame_bind_group(&ctx.device, &self.cache, &self.frame_buffer, &self.pass_buffer);
        }
    }

    /// Encodes and submits the recorded passes.
    fn encode(
        &mut self,
        ctx: &GpuContext,
        scene: &GpuScene,
        plan: &RenderPlan,
        commands: &[(usize, &Command)],
        output: &wgpu::TextureView,
        output_format: wgpu::TextureFormat,
    ) -> Result<(), GpuError> {
        let device = &ctx.device;
        let mut encoder = record::new_encoder(device);
        let timer = self.timer.as_ref().filter(|_| self.timing);
        self.bound.clear();
        let mut step_ms = self.profile_steps.then(|| vec![0.0; plan.steps.len()]);
        let mut rec = Recording {
            device,
            cache: &mut self.cache,
            pool: &self.pool,
            plan,
            scene,
            frame: &self.frame_bind_group,
            bound: &mut self.bound,
        };
        for (i, &(step, command)) in commands.iter().enumerate() {
            if step_ms.is_some() {
                ctx.queue.submit([std::mem::replace(&mut encoder, record::new_encoder(device)).finish()]);
                ctx.wait_idle()?;
            }
            let started = std::time::Instant::now();
            let first = i == 0 || commands[i - 1].0 != step;
            let last = i + 1 == commands.len() || commands[i + 1].0 != step;
            let stamps = timer.and_then(|t| t.writes_span(step, first, last));
            let at = At { step, offset: (i as u64 * PASS_SLOT_BYTES) as u32 };
            match command {
                Command::Splats(pass) => record::splat::encode(&mut rec, &mut encoder, pass, at, stamps)?,
                Command::Fullscreen(pass) => {
                    record::fullscreen::encode(&mut rec, &mut encoder, pass, at, (output, output_format), stamps)?
                }
                Command::Compute(pass) => {
                    let tiles = self.tiles.as_ref().ok_or_else(|| record::missing("tile pipeline"))?;
                    let run = TileRun { tiles, subgroups: self.subgroups, early_stop: self.early_stop };
                    record::compute::encode(&mut rec, &mut encoder, &run, pass, at, stamps)?
                }
            }
            if let Some(times) = step_ms.as_mut() {
                ctx.queue.submit([std::mem::replace(&mut encoder, record::new_encoder(device)).finish()]);
                ctx.wait_idle()?;
                times[step] += started.elapsed().as_secs_f64() * 1e3;
            }
        }
        self.step_ms = step_ms;
        if let Some(timer) = timer {
            timer.resolve(&mut encoder, plan.steps.len());
        }
        ctx.queue.submit([encoder.finish()]);
        Ok(())
    }
}

use bytemuck::Zeroable;

fn pass_buffer(device: &wgpu::Device, slots: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("Pass::uniforms"),
        size: slots * PASS_SLOT_BYTES,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

fn frame_bind_group(
    device: &wgpu::Device,
    cache: &PipelineCache,
    frame: &wgpu::Buffer,
    passes: &wgpu::Buffer,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("Frame::bind_group"),
        layout: cache.frame_layout(),
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: frame.as_entire_binding() },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: passes,
                    offset: 0,
                    size: wgpu::BufferSize::new(std::mem::size_of::<PassUniforms>() as u64),
                }),
            },
        ],
    })
}

/// The uniforms of one frame.
fn frame_uniforms(camera: &Camera, spec: &FrameSpec, window: &SubFrame, environment_width: u32) -> FrameUniforms {
    let settings = &spec.drawn;
    use crate::frame::environment_effects::LayerEffects;
    let env = &settings.environment;
    let (up, front) = camera.up.frame();
    let (width, height) = window.size;
    let (near, far) = camera.near_far();
    let (lens, centre) = window.lens(camera);
    let shading = &settings.shading;
    let to_cols = |m: Mat4| m.to_cols_array_2d();
    let clip = settings.clip.in_eye(&camera.view_matrix());
    FrameUniforms {
        view: to_cols(camera.view_matrix()),
        proj: to_cols(window.projection(camera)),
        viewport: [width as f32, height as f32, 1.0 / width as f32, 1.0 / height as f32],
        depth: [near, far, if camera.is_ortho() { 1.0 } else { 0.0 }, 1.0 / (far - near).max(f32::MIN_POSITIVE)],
        splat: [
            // Only modes whose passes weight their fragments filter (the registry lists them).
            spec.low_pass_px,
            settings.kernel.sharpness(),
            settings.kernel.min_normal_z,
            if settings.backface_culling { 1.0 } else { 0.0 },
        ],
        light: shading.light_dir_eye.extend(shading.shininess).to_array(),
        material: [shading.ambient, shading.diffuse, shading.specular, 0.0],
        background: shading.background.extend(1.0).to_array(),
        // The floor is in the frame's pixels, whatever part of it the window is.
        lens: [
            lens.x,
            lens.y,
            settings.radius_scale,
            settings.pixel_radius_floor(camera.half_extent_y(), window.frame.1),
        ],
        environment: [
            env.eta,
            env.dispersion,
            if env.layer_effects == LayerEffects::Multi { 1.0 } else { 0.0 },
            if env.skybox { 1.0 } else { 0.0 },
        ],
        environment_up: up.extend(std::f32::consts::TAU / environment_width.max(1) as f32).to_array(),
        environment_front: front.extend(0.0).to_array(),
        lights: eye_lights(camera, settings),
        light_count: [if spec.lights { settings.lights.len() as u32 } else { 0 }, 0, 0, 0],
        clip: clip.planes.map(|p| p.to_array()),
        clip_counts: [clip.counts[0], clip.counts[1], clip.counts[2], 0],
        window: [centre.x, centre.y, 0.0, 0.0],
    }
}

/// The scene lights in eye space, as `FrameUniforms::lights` holds them.
fn eye_lights(
    camera: &Camera,
    settings: &RenderSettings,
) -> [[f32; 4]; 2 * pointblend_core::frame::lights::MAX_LIGHTS] {
    use crate::frame::LightKind;
    let view = camera.view_matrix();
    let mut rows = [[0.0; 4]; 2 * pointblend_core::frame::lights::MAX_LIGHTS];
    for (k, light) in settings.lights.as_slice().iter().enumerate() {
        rows[2 * k] = match light.kind {
            LightKind::Point(p) => view.transform_point3(p).extend(1.0).to_array(),
            LightKind::Directional(d) => view.transform_vector3(-d).normalize_or_zero().extend(0.0).to_array(),
        };
        rows[2 * k + 1] = (light.colour * light.intensity).extend(light.inverse_square as u32 as f32).to_array();
    }
    rows
}
