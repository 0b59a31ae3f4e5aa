//! The renderer: runs a mode's plan into any view.
//!
//! A frame flows scene → plan → passes → image. The scene is uploaded once
//! ([`GpuScene`]); for each frame the mode of the registry plans its steps
//! ([`RenderPlan`]), each the commands of its render passes; the renderer
//! allocates exactly the plan's targets ([`TargetPool`]), writes the frame's
//! uniforms and one uniform slot per pass, takes each pass's pipeline from the
//! cache ([`PipelineCache`]) and encodes the passes, timed per plan pass when
//! timing is on. The window, the headless path, `bench` and the tests all call
//! [`Renderer::render`]; only the output view differs.

use glam::Mat4;
use wgpu::util::DeviceExt;

use super::context::{GpuContext, GpuError};
use super::gpu_data::{FrameUniforms, PASS_SLOT_BYTES, PassUniforms};
use super::gpu_scene::GpuScene;
use super::modes::FrameDesc;
use super::passes::{Blend, Command, Output, PipelineKey, PipelineKind, TileWork, fullscreen, splat};
use super::pipelines::PipelineCache;
use super::plan::{Layout, RenderPlan, TargetDesc, TargetId};
use super::targets::TargetPool;
use super::tile_engine::{self, TileEngine};
use super::timer::PassTimer;
use super::touches::{Bound, Slot};
use crate::frame::{Camera, RenderSettings};

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

    /// What the frame's mode needs to know: settings, size and the scene.
    fn frame_desc<'a>(
        scene: &'a GpuScene,
        camera: &Camera,
        settings: &'a RenderSettings,
        (width, height): (u32, u32),
    ) -> FrameDesc<'a> {
        let epsilon = settings.epsilon(scene.mean_radius);
        let (near, far) = camera.near_far();
        // Eq. 10 over the scene's depth range (near and far enclose its sphere).
        let depth_steps = super::depth_steps::depth_steps(near, far, epsilon * settings.depth_step);
        let lights = settings.lit_by_lights() && scene.light_chunks().is_some();
        FrameDesc {
            settings,
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
            environment: scene.environment.as_ref().filter(|_| settings.draws_environment()),
            sums: scene.sums,
            lights,
            triangles: scene.triangles.as_ref().map_or(0, |t| t.count()),
        }
    }

    /// The plan a frame of `settings` would run, without running it.
    pub fn plan(
        scene: &GpuScene,
        camera: &Camera,
        settings: &RenderSettings,
        size: (u32, u32),
    ) -> Result<RenderPlan, GpuError> {
        super::modes::plan(&Self::frame_desc(scene, camera, settings, size))
            .ok_or_else(|| GpuError::Device(format!("mode {} does not run on the GPU", settings.mode)))
    }

    /// Renders `scene` into `output` (of `format`, `width` x `height`) and returns the plan it ran.
    #[allow(clippy::too_many_arguments)]
    pub fn render(
        &mut self,
        ctx: &GpuContext,
        scene: &GpuScene,
        camera: &Camera,
        settings: &RenderSettings,
        output: &wgpu::TextureView,
        format: wgpu::TextureFormat,
        size: (u32, u32),
    ) -> Result<RenderPlan, GpuError> {
        ctx.check_size(size.0, size.1)?;
        let mut plan = Self::plan(scene, camera, settings, size)?;
        plan.check_fits(&ctx.device.limits(), ctx.target_budget())?;
        if plan.compute_passes() > 0 && !self.tiles.as_ref().is_some_and(|t| t.fits(scene, size)) {
            self.tiles = None; // free the old buffers first
            self.tiles = Some(TileEngine::new(ctx, scene, size)?);
        }
        if plan.back_to_front() {
            scene.order_back_to_front(&ctx.queue, camera.view_ray(), settings.order);
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
        ctx.queue.write_buffer(
            &self.frame_buffer,
            0,
            bytemuck::bytes_of(&frame_uniforms(
                camera,
                settings,
                size,
                scene.environment.as_ref().map_or(0, |e| e.width),
            )),
        );
        let mut slots = vec![0u8; commands.len() * PASS_SLOT_BYTES as usize];
        for (i, (_, command)) in commands.iter().enumerate() {
            let uniforms = command.uniforms();
            let at = i * PASS_SLOT_BYTES as usize;
            slots[at..at + std::mem::size_of::<PassUniforms>()].copy_from_slice(bytemuck::bytes_of(uniforms));
        }
        ctx.queue.write_buffer(&self.pass_buffer, 0, &slots);
        ctx.checked("rendering", || self.encode(ctx, scene, &plan, &commands, output, format))??;
        if let Some(tiles) = self.tiles.as_ref().filter(|_| plan.compute_passes() > 0) {
            // The entries' size is known now: the plan says what the frame used.
            let entries = (tiles.last.entries, tiles.entry_capacity());
            plan.buffers = tile_engine::planned_buffers(scene.len, size, Some(entries));
            plan.notes.push(format!(
                "tile lists: {} entries, the longest {} splats",
                tiles.last.entries, tiles.last.longest_list
            ));
        }
        Ok(plan)
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
        let missing = |what: &str| GpuError::Device(format!("the plan has no target '{what}'"));
        let desc = |id: super::plan::TargetId| plan.target(id).ok_or_else(|| missing(id.0));
        let new_encoder =
            || device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("Renderer::encoder") });
        let mut encoder = new_encoder();
        let budget = ctx.target_budget().saturating_sub(plan.target_bytes() + plan.buffer_bytes());
        let timer = self.timer.as_ref().filter(|_| self.timing);
        self.bound.clear();
        let mut step_ms = self.profile_steps.then(|| vec![0.0; plan.steps.len()]);
        for (i, &(step, command)) in commands.iter().enumerate() {
            if step_ms.is_some() {
                ctx.queue.submit([std::mem::replace(&mut encoder, new_encoder()).finish()]);
                ctx.wait_idle()?;
            }
            let started = std::time::Instant::now();
            let first = i == 0 || commands[i - 1].0 != step;
            let last = i + 1 == commands.len() || commands[i + 1].0 != step;
            let stamps = timer.and_then(|t| t.writes_span(step, first, last));
            let (frame, offset) = (&self.frame_bind_group, (i as u64 * PASS_SLOT_BYTES) as u32);
            match command {
                Command::Splats(pass) => {
                    let colour = pass.colour.iter().map(|c| Ok((desc(c.target)?.format, c.blend))).collect::<Result<
                        _,
                        GpuError,
                    >>(
                    )?;
                    let depth = match pass.depth {
                        Some((id, test)) => Some((desc(id)?.format, test.write, test.compare)),
                        None => None,
                    };
                    let inputs =
                        inputs(&mut self.cache, &self.pool, device, plan, &pass.inputs, (step, &mut self.bound))?;
                    let kind = PipelineKind::Splats {
                        colour,
                        depth,
                        inputs: inputs.as_ref().map(|i| i.0.clone()).unwrap_or_default(),
                        cull_back: false,
                    };
                    // A pass that writes only depth reads no colour: its splats are not lit.
                    let lights = super::shaders::Variant::LIGHTS;
                    let variant = pass.variant.with(lights, pass.variant.has(lights) && !pass.colour.is_empty());
                    let key = PipelineKey { shader: pass.shader, entry: pass.entry, variant, kind };
                    // The frame's mesh triangles, through the same fragment entry.
                    let triangle_key = scene.triangles.as_ref().filter(|_| pass.triangles).map(|draw| {
                        let kind = match key.kind.clone() {
                            PipelineKind::Splats { colour, depth, inputs, .. } => {
                                PipelineKind::Splats { colour, depth, inputs, cull_back: draw.cull_back }
                            }
                            other => other,
                        };
                        PipelineKey {
                            variant: variant.with(super::shaders::Variant::TRIANGLES, true),
                            kind,
                            ..key.clone()
                        }
                    });
                    if let Some(triangle_key) = &triangle_key {
                        self.cache.pipeline(device, triangle_key)?;
                    }
                    self.cache.pipeline(device, &key)?;
                    let built = |key: &PipelineKey| self.cache.built(key).ok_or_else(|| missing(key.entry));
                    let pipeline = built(&key)?;
                    let triangles = triangle_key.as_ref().map(built).transpose()?;
                    let layer_view = |id| self.pool.layer_view(id, pass.layer).ok_or_else(|| missing(id.0));
                    let attachments = splat::Attachments {
                        colour: pass.colour.iter().map(|c| layer_view(c.target)).collect::<Result<_, _>>()?,
                        depth: pass.depth.map(|(id, _)| layer_view(id)).transpose()?,
                    };
                    // Colour attachments are cleared, then blended into: written only.
                    for (i, view) in attachments.colour.iter().enumerate() {
                        let (slot, view) = (Slot::Colour(i as u32), (*view).clone());
                        self.bound.push(Bound { pass: step, slot, view, reads: false, writes: true });
                    }
                    if let (Some(view), Some((_, test))) = (attachments.depth, pass.depth) {
                        // The depth test reads what was loaded; the pipeline writes depth or not.
                        let reads = !test.clear && test.compare != wgpu::CompareFunction::Always;
                        let view = view.clone();
                        self.bound.push(Bound { pass: step, slot: Slot::Depth, view, reads, writes: test.write });
                    }
                    let group = inputs.as_ref().map(|i| &i.1);
                    splat::record(
                        &mut encoder,
                        pass,
                        pipeline,
                        frame,
                        offset,
                        group,
                        &attachments,
                        scene,
                        triangles,
                        stamps,
                    );
                }
                Command::Compute(pass) => {
                    let tiles = self.tiles.as_mut().ok_or_else(|| missing("tile pipeline"))?;
                    if pass.work == TileWork::Bin {
                        // The counts must come back before the entries can be placed.
                        ctx.queue.submit([std::mem::replace(&mut encoder, new_encoder()).finish()]);
                        tiles.bin_offsets(ctx, budget)?;
                    }
                    let outputs = pass
                        .outputs
                        .iter()
                        .map(|&id| self.pool.view(id).ok_or_else(|| missing(id.0)))
                        .collect::<Result<Vec<_>, _>>()?;
                    let format = match pass.outputs.first() {
                        Some(&id) => desc(id)?.format,
                        None => wgpu::TextureFormat::Rgba32Float,
                    };
                    let bindings = tile_engine::bindings(pass.work, pass.variant, format);
                    let variant = pass
                        .variant
                        .with(super::shaders::Variant::SUBGROUPS, self.subgroups && pass.work == TileWork::Raster);
                    let (pipeline, layout) =
                        self.cache.compute(device, (pass.shader, pass.entry, variant), &bindings)?;
                    let stamps = stamps.map(|s| wgpu::ComputePassTimestampWrites {
                        query_set: s.query_set,
                        beginning_of_pass_write_index: s.beginning_of_pass_write_index,
                        end_of_pass_write_index: s.end_of_pass_write_index,
                    });
                    let frame = (&self.frame_bind_group, offset);
                    let given =
                        tiles.record(device, &mut encoder, pass, (pipeline, layout), frame, scene, &outputs, stamps);
                    self.bound.extend(given.into_iter().map(|(binding, view)| Bound {
                        reads: false,
                        writes: true,
                        pass: step,
                        slot: Slot::Storage(binding),
                        view,
                    }));
                }
                Command::Fullscreen(pass) => {
                    let (target_view, target_format) = match pass.output {
                        Output::Frame => (output, output_format),
                        Output::Target(id) => (self.pool.view(id).ok_or_else(|| missing(id.0))?, desc(id)?.format),
                    };
                    if let Output::Target(_) = pass.output {
                        // Blending onto a loaded target reads it.
                        let reads = !pass.clear && pass.blend != Blend::Replace;
                        let view = target_view.clone();
                        self.bound.push(Bound { pass: step, slot: Slot::Colour(0), view, reads, writes: true });
                    }
                    let (dims, inputs) =
                        inputs(&mut self.cache, &self.pool, device, plan, &pass.inputs, (step, &mut self.bound))?
                            .ok_or_else(|| GpuError::Device(format!("{} reads no target", pass.label)))?;
                    let kind = PipelineKind::Fullscreen { inputs: dims, output: target_format, blend: pass.blend };
                    let key = PipelineKey { shader: pass.shader, entry: pass.entry, variant: pass.variant, kind };
                    let environment = if pass.variant.has(super::shaders::Variant::ENVIRONMENT) {
                        let map = scene.environment.as_ref().ok_or_else(|| missing("environment map"))?;
                        Some(map.bind_group(device, self.cache.environment_layout()))
                    } else {
                        None
                    };
                    let pipeline = self.cache.pipeline(device, &key)?;
                    let environment = environment.as_ref();
                    fullscreen::record(
                        &mut encoder,
                        pass,
                        pipeline,
                        frame,
                        offset,
                        &inputs,
                        environment,
                        target_view,
                        stamps,
                    );
                }
            }
            if let Some(times) = step_ms.as_mut() {
                ctx.queue.submit([std::mem::replace(&mut encoder, new_encoder()).finish()]);
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

/// The texture dimensions and the group-1 bind group of a pass that reads
/// `ids` (none when it reads nothing).
#[allow(clippy::type_complexity)]
fn inputs(
    cache: &mut PipelineCache,
    pool: &TargetPool,
    device: &wgpu::Device,
    plan: &RenderPlan,
    ids: &[super::plan::TargetId],
    (pass, bound): (usize, &mut Vec<Bound>),
) -> Result<Option<(Vec<wgpu::TextureViewDimension>, wgpu::BindGroup)>, GpuError> {
    if ids.is_empty() {
        return Ok(None);
    }
    let missing = |id: super::plan::TargetId| GpuError::Device(format!("the plan has no target '{}'", id.0));
    let mut dims = Vec::with_capacity(ids.len());
    let mut views = Vec::with_capacity(ids.len());
    for &id in ids {
        dims.push(match plan.target(id).ok_or_else(|| missing(id))?.layout {
            Layout::Single => wgpu::TextureViewDimension::D2,
            Layout::Array { .. } => wgpu::TextureViewDimension::D2Array,
        });
        views.push(pool.view(id).ok_or_else(|| missing(id))?);
    }
    let entries: Vec<wgpu::BindGroupEntry<'_>> = views
        .iter()
        .enumerate()
        .map(|(binding, view)| wgpu::BindGroupEntry {
            binding: binding as u32,
            resource: wgpu::BindingResource::TextureView(view),
        })
        .collect();
    for entry in &entries {
        if let wgpu::BindingResource::TextureView(view) = &entry.resource {
            let (slot, view) = (Slot::Input(entry.binding), (*view).clone());
            bound.push(Bound { pass, slot, view, reads: true, writes: false });
        }
    }
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("Pass::inputs"),
        layout: cache.inputs_layout(device, &dims),
        entries: &entries,
    });
    Ok(Some((dims, group)))
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
fn frame_uniforms(
    camera: &Camera,
    settings: &RenderSettings,
    (width, height): (u32, u32),
    environment_width: u32,
) -> FrameUniforms {
    use crate::frame::environment::LayerEffects;
    let env = &settings.environment;
    let (up, front) = camera.up.frame();
    let aspect = width as f32 / height as f32;
    let (near, far) = camera.near_far();
    let tan_y = (camera.fov_y_deg.to_radians() * 0.5).tan();
    let shading = &settings.shading;
    let to_cols = |m: Mat4| m.to_cols_array_2d();
    FrameUniforms {
        view: to_cols(camera.view_matrix()),
        proj: to_cols(camera.projection(aspect)),
        viewport: [width as f32, height as f32, 1.0 / width as f32, 1.0 / height as f32],
        depth: [near, far, 0.0, 1.0 / (far - near).max(f32::MIN_POSITIVE)],
        splat: [
            // Only modes whose passes weight their fragments filter (the registry lists them).
            settings.low_pass_radius_px(),
            settings.kernel.sharpness(),
            settings.kernel.min_normal_z,
            if settings.backface_culling { 1.0 } else { 0.0 },
        ],
        light: shading.light_dir_eye.extend(shading.shininess).to_array(),
        material: [shading.ambient, shading.diffuse, shading.specular, 0.0],
        background: shading.background.extend(1.0).to_array(),
        lens: [tan_y * aspect, tan_y, settings.radius_scale, 0.0],
        environment: [
            env.eta,
            env.dispersion,
            if env.layer_effects == LayerEffects::Multi { 1.0 } else { 0.0 },
            if env.skybox { 1.0 } else { 0.0 },
        ],
        environment_up: up.extend(std::f32::consts::TAU / environment_width.max(1) as f32).to_array(),
        environment_front: front.extend(0.0).to_array(),
        lights: eye_lights(camera, settings),
        light_count: [if settings.lit_by_lights() { settings.lights.len() as u32 } else { 0 }, 0, 0, 0],
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
