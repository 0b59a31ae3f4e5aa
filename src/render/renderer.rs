//! The splat renderer: builds the pipelines once and runs a [`RenderPlan`] into any view.
//!
//! The window and the headless path both call [`SplatRenderer::render`]; only
//! the output view differs.

use std::collections::HashMap;

use glam::Mat4;
use wgpu::util::DeviceExt;

use super::context::{GpuContext, GpuError};
use super::gpu_data::FrameUniforms;
use super::passes::{accumulate, deferred_composite, deferred_geometry, nearest, normalize, visibility};
use super::plan::{PassKind, RenderPlan};
use super::shaders;
use super::splat_buffers::GpuCloud;
use super::targets::{FrameTargets, GroupTargets};
use super::timer::PassTimer;
use crate::view::Camera;
use crate::view::settings::RenderSettings;

pub struct SplatRenderer {
    frame_buffer: wgpu::Buffer,
    frame_bind_group: wgpu::BindGroup,
    normalize_layout: wgpu::BindGroupLayout,
    normalize_pipeline_layout: wgpu::PipelineLayout,
    normalize_module: wgpu::ShaderModule,
    visibility: wgpu::RenderPipeline,
    /// Indexed [weight only][lit]: single-channel colour targets for clouds of
    /// one colour, and no normal target without lighting.
    accumulate: Variants,
    nearest: Variants,
    normalize: HashMap<wgpu::TextureFormat, wgpu::RenderPipeline>,
    targets: Option<FrameTargets>,
    deferred_geometry: Variants,
    composite_layout: wgpu::BindGroupLayout,
    composite_pipeline_layout: wgpu::PipelineLayout,
    composite_module: wgpu::ShaderModule,
    composite: HashMap<wgpu::TextureFormat, wgpu::RenderPipeline>,
    group_targets: Option<GroupTargets>,
    timer: Option<PassTimer>,
}

impl SplatRenderer {
    pub fn new(ctx: &GpuContext) -> Result<Self, GpuError> {
        ctx.checked("building the splat pipelines", || Self::build(&ctx.device))
    }

    fn build(device: &wgpu::Device) -> Self {
        let module = |name: &'static str| {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(name),
                source: wgpu::ShaderSource::Wgsl(shaders::source(name).into()),
            })
        };
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("Frame::layout"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let frame_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("Frame::uniforms"),
            contents: bytemuck::bytes_of(&FrameUniforms::zeroed()),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let frame_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("Frame::bind_group"),
            layout: &frame_layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: frame_buffer.as_entire_binding() }],
        });
        let splat_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("Splat::pipeline_layout"),
            bind_group_layouts: &[Some(&frame_layout)],
            immediate_size: 0,
        });
        let normalize_layout = normalize::inputs_layout(device);
        let normalize_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("Normalize::pipeline_layout"),
            bind_group_layouts: &[Some(&frame_layout), Some(&normalize_layout)],
            immediate_size: 0,
        });
        let visibility_module = module("visibility");
        let accumulate_module = module("accumulate");
        let composite_layout = deferred_composite::inputs_layout(device);
        let composite_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("Composite::pipeline_layout"),
            bind_group_layouts: &[Some(&frame_layout), Some(&composite_layout)],
            immediate_size: 0,
        });
        Self {
            deferred_geometry: {
                let m = module("deferred_geometry");
                variants(|lit, weight_only| deferred_geometry::pipeline(device, &splat_layout, &m, lit, weight_only))
            },
            composite_module: module("deferred_composite"),
            composite_layout,
            composite_pipeline_layout,
            composite: HashMap::new(),
            group_targets: None,
            visibility: visibility::pipeline(device, &splat_layout, &visibility_module),
            accumulate: variants(|lit, w| accumulate::pipeline(device, &splat_layout, &accumulate_module, lit, w)),
            nearest: variants(|lit, w| nearest::pipeline(device, &splat_layout, &accumulate_module, lit, w)),
            normalize_module: module("normalize"),
            frame_buffer,
            frame_bind_group,
            normalize_layout,
            normalize_pipeline_layout,
            normalize: HashMap::new(),
            targets: None,
            timer: None,
        }
    }

    /// Turns per-pass GPU timestamps on; returns false when the adapter has none.
    pub fn enable_pass_timing(&mut self, ctx: &GpuContext) -> bool {
        if self.timer.is_none() {
            self.timer = PassTimer::new(ctx);
        }
        self.timer.is_some()
    }

    /// Milliseconds per pass of the last frame (waits for it), if timing is on.
    pub fn pass_times(&self, ctx: &GpuContext, plan: &RenderPlan) -> Result<Option<Vec<f64>>, GpuError> {
        self.timer.as_ref().map(|t| t.read(ctx, plan.passes.len())).transpose()
    }

    /// Renders `cloud` into `output` (of `format`, `width` x `height`) and returns the plan it ran.
    #[allow(clippy::too_many_arguments)]
    pub fn render(
        &mut self,
        ctx: &GpuContext,
        cloud: &GpuCloud,
        camera: &Camera,
        settings: &RenderSettings,
        output: &wgpu::TextureView,
        format: wgpu::TextureFormat,
        (width, height): (u32, u32),
    ) -> Result<RenderPlan, GpuError> {
        ctx.check_size(width, height)?;
        if !settings.mode.is_gpu() {
            return Err(GpuError::Device(format!("mode {} does not run on the GPU", settings.mode)));
        }
        let epsilon = settings.epsilon(cloud.mean_radius);
        let weight_only = cloud.uniform_color.is_some();
        let plan = RenderPlan::new(settings, width, height, cloud.len, epsilon, cloud.groups.len(), weight_only);
        let mut uniforms = frame_uniforms(camera, settings, width, height, epsilon);
        let (near, far) = camera.near_far();
        // Eq. 10: n >= (d_max - d_min)/ε low-precision depth steps.
        let steps = ((far - near) / epsilon.max(f32::MIN_POSITIVE)).ceil().clamp(1.0, 4_194_304.0);
        if let Some([r, g, b]) = cloud.uniform_color {
            uniforms.scene = [r as f32 / 255.0, g as f32 / 255.0, b as f32 / 255.0, 1.0];
        }
        uniforms.deferred = [steps, if settings.voronoi { 1.0 } else { 0.0 }, plan.groups as f32, 0.0];
        plan.check_fits(&ctx.device.limits(), ctx.target_budget())?;
        let deferred = plan.passes.contains(&PassKind::DeferredGeometry);
        ctx.allocating("allocating the render targets", || {
            let device = &ctx.device;
            // Only the targets this plan uses are kept; the others are freed.
            if deferred {
                self.targets = None;
                let layers = plan.groups as u32;
                let wanted = (width, height, layers, settings.lighting, weight_only);
                if self
                    .group_targets
                    .as_ref()
                    .is_none_or(|t| (t.width, t.height, t.layers, t.lit, t.weight_only) != wanted)
                {
                    drop(self.group_targets.take()); // free the old layers first
                    let (lit, layout) = (settings.lighting, &self.composite_layout);
                    self.group_targets =
                        Some(GroupTargets::new(device, (width, height, layers), layout, lit, weight_only));
                }
            } else {
                self.group_targets = None;
                let wanted = (width, height, settings.lighting, weight_only);
                if self.targets.as_ref().is_none_or(|t| (t.width, t.height, t.lit, t.weight_only) != wanted) {
                    let (lit, layout) = (settings.lighting, &self.normalize_layout);
                    self.targets = Some(FrameTargets::new(device, (width, height), layout, lit, weight_only));
                }
            }
        })?;
        ctx.checked("rendering", || {
            let device = &ctx.device;
            let normalize_pipeline = self.normalize.entry(format).or_insert_with(|| {
                normalize::pipeline(device, &self.normalize_pipeline_layout, &self.normalize_module, format)
            });
            let composite_pipeline = self.composite.entry(format).or_insert_with(|| {
                normalize::fullscreen_pipeline(
                    device,
                    "Composite::pipeline",
                    &self.composite_pipeline_layout,
                    &self.composite_module,
                    "fs_composite",
                    format,
                )
            });
            ctx.queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&uniforms));
            let mut encoder = device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("SplatRenderer::encoder") });
            let frame = &self.frame_bind_group;
            let lit = settings.lighting as usize;
            let weight_only = cloud.uniform_color.is_some() as usize;
            for (i, pass) in plan.passes.iter().enumerate() {
                let stamps = self.timer.as_ref().and_then(|t| t.writes(i));
                if let (Some(groups), true) = (self.group_targets.as_ref(), deferred) {
                    match pass {
                        PassKind::DeferredGeometry => {
                            let timer = self.timer.as_ref().map(|t| (t, i));
                            deferred_geometry::record(
                                &mut encoder,
                                &self.deferred_geometry[weight_only][lit],
                                frame,
                                groups,
                                cloud,
                                timer,
                            )
                        }
                        PassKind::DeferredComposite => {
                            deferred_composite::record(&mut encoder, composite_pipeline, frame, groups, output, stamps)
                        }
                        _ => {}
                    }
                    continue;
                }
                let Some(targets) = self.targets.as_ref() else { continue };
                match pass {
                    PassKind::Visibility => {
                        visibility::record(&mut encoder, &self.visibility, frame, targets, cloud, stamps)
                    }
                    PassKind::Accumulate => accumulate::record(
                        &mut encoder,
                        &self.accumulate[weight_only][lit],
                        frame,
                        targets,
                        cloud,
                        stamps,
                    ),
                    PassKind::NearestSplat => {
                        nearest::record(&mut encoder, &self.nearest[weight_only][lit], frame, targets, cloud, stamps)
                    }
                    PassKind::Normalize => {
                        normalize::record(&mut encoder, normalize_pipeline, frame, targets, output, stamps)
                    }
                    PassKind::DeferredGeometry | PassKind::DeferredComposite => {}
                }
            }
            if let Some(timer) = &self.timer {
                timer.resolve(&mut encoder, plan.passes.len());
            }
            ctx.queue.submit([encoder.finish()]);
        })?;
        Ok(plan)
    }
}

use bytemuck::Zeroable;

/// Pipelines for [weight only][lit].
type Variants = [[wgpu::RenderPipeline; 2]; 2];

fn variants(make: impl Fn(bool, bool) -> wgpu::RenderPipeline) -> Variants {
    [false, true].map(|weight_only| [false, true].map(|lit| make(lit, weight_only)))
}

/// The uniforms of one frame.
fn frame_uniforms(camera: &Camera, settings: &RenderSettings, width: u32, height: u32, epsilon: f32) -> FrameUniforms {
    let aspect = width as f32 / height as f32;
    let (near, far) = camera.near_far();
    let tan_y = (camera.fov_y_deg.to_radians() * 0.5).tan();
    let shading = &settings.shading;
    let to_cols = |m: Mat4| m.to_cols_array_2d();
    FrameUniforms {
        view: to_cols(camera.view_matrix()),
        proj: to_cols(camera.projection(aspect)),
        viewport: [width as f32, height as f32, 1.0 / width as f32, 1.0 / height as f32],
        depth: [near, far, epsilon, 1.0 / (far - near)],
        splat: [
            camera.focal_pixels(height),
            settings.kernel.sharpness(),
            settings.kernel.min_normal_z,
            if settings.backface_culling { 1.0 } else { 0.0 },
        ],
        light: shading.light_dir_eye.extend(shading.shininess).to_array(),
        material: [shading.ambient, shading.diffuse, shading.specular, if settings.lighting { 1.0 } else { 0.0 }],
        background: shading.background.extend(1.0).to_array(),
        lens: [tan_y * aspect, tan_y, settings.radius_scale, 0.0],
        deferred: [0.0; 4],
        scene: [0.0; 4],
    }
}
