//! The pipeline cache: shader modules by (file, variant), bind group layouts
//! by the textures they bind, and pipelines by [`PipelineKey`] (pass, variant,
//! output formats and fixed-function state), each built on first use and kept.
//!
//! Group 0 of every pipeline holds the frame's uniforms (binding 0) and the
//! pass's own uniforms (binding 1, a slot chosen by a dynamic offset); group 1
//! of a full-screen pipeline holds its input textures, and group 2 of one
//! built with `Variant::ENVIRONMENT` the environment map and its sampler.

use std::collections::HashMap;

use super::context::GpuError;
use super::gpu_data::{FrameUniforms, PassUniforms};
use super::passes::{PipelineKey, PipelineKind, PipelineSource, compute, fullscreen, splat};
use super::shaders::{self, Variant};

pub struct PipelineCache {
    frame_layout: wgpu::BindGroupLayout,
    modules: HashMap<(&'static str, Variant), wgpu::ShaderModule>,
    /// Bind group layouts of full-screen inputs, by their texture dimensions.
    input_layouts: HashMap<Vec<wgpu::TextureViewDimension>, wgpu::BindGroupLayout>,
    /// Pipeline layouts by the dimensions of the textures read at group 1,
    /// and whether group 2 binds the environment map.
    layouts: HashMap<(Vec<wgpu::TextureViewDimension>, bool), wgpu::PipelineLayout>,
    environment_layout: wgpu::BindGroupLayout,
    pipelines: HashMap<PipelineKey, wgpu::RenderPipeline>,
    /// Compute pipelines by (file, entry, variant, group-1 bindings), with their group-1 layout.
    computes: HashMap<ComputeKey, (wgpu::ComputePipeline, wgpu::BindGroupLayout)>,
}

/// What makes two compute pipelines the same.
type ComputeKey = (&'static str, &'static str, Variant, Vec<compute::Binding>);

impl PipelineCache {
    pub fn new(device: &wgpu::Device) -> Self {
        let uniform = |dynamic: bool, size: usize| wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: dynamic,
            min_binding_size: wgpu::BufferSize::new(size as u64),
        };
        let uniforms =
            [uniform(false, std::mem::size_of::<FrameUniforms>()), uniform(true, std::mem::size_of::<PassUniforms>())];
        let stages = wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE;
        let frame_layout = super::passes::group_layout(device, "Frame::layout", stages, uniforms.into_iter());
        Self {
            frame_layout,
            environment_layout: super::environment_texture::EnvTexture::layout(device),
            modules: HashMap::new(),
            input_layouts: HashMap::new(),
            layouts: HashMap::new(),
            pipelines: HashMap::new(),
            computes: HashMap::new(),
        }
    }

    /// The layout of bind group 0 (frame and pass uniforms).
    pub fn frame_layout(&self) -> &wgpu::BindGroupLayout {
        &self.frame_layout
    }

    /// The layout of group 2: the environment map and its sampler.
    pub fn environment_layout(&self) -> &wgpu::BindGroupLayout {
        &self.environment_layout
    }

    /// The layout of a full-screen pass's inputs.
    pub fn inputs_layout(
        &mut self,
        device: &wgpu::Device,
        dims: &[wgpu::TextureViewDimension],
    ) -> &wgpu::BindGroupLayout {
        self.input_layouts.entry(dims.to_vec()).or_insert_with(|| fullscreen::inputs_layout(device, dims))
    }

    /// The pipeline for `key`, built on first use.
    pub fn pipeline(&mut self, device: &wgpu::Device, key: &PipelineKey) -> Result<&wgpu::RenderPipeline, GpuError> {
        if !self.pipelines.contains_key(key) {
            let pipeline = self.build(device, key)?;
            self.pipelines.insert(key.clone(), pipeline);
        }
        self.pipelines.get(key).ok_or_else(|| GpuError::Device("pipeline cache".into()))
    }

    /// The pipeline for `key`, if it was built.
    pub fn built(&self, key: &PipelineKey) -> Option<&wgpu::RenderPipeline> {
        self.pipelines.get(key)
    }

    /// The compute pipeline of `entry` in `shader` built with `variant`,
    /// whose group 1 holds `bindings`, and that group's layout; built on first use.
    pub fn compute(
        &mut self,
        device: &wgpu::Device,
        (shader, entry, variant): (&'static str, &'static str, Variant),
        bindings: &[compute::Binding],
    ) -> Result<&(wgpu::ComputePipeline, wgpu::BindGroupLayout), GpuError> {
        let key: ComputeKey = (shader, entry, variant, bindings.to_vec());
        if !self.computes.contains_key(&key) {
            self.module(device, shader, variant)?;
            let group = compute::layout(device, bindings);
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("Compute::pipeline_layout"),
                bind_group_layouts: &[Some(&self.frame_layout), Some(&group)],
                immediate_size: 0,
            });
            let label = format!("{shader}::{entry} ({variant})");
            let module = &self.modules[&(shader, variant)];
            let pipeline = compute::pipeline(&PipelineSource { device, label: &label, layout: &layout, module, entry });
            self.computes.insert(key.clone(), (pipeline, group));
        }
        self.computes.get(&key).ok_or_else(|| GpuError::Device("compute pipeline cache".into()))
    }

    /// Builds the module of `shader` in `variant` unless it is there.
    fn module(&mut self, device: &wgpu::Device, shader: &'static str, variant: Variant) -> Result<(), GpuError> {
        if let std::collections::hash_map::Entry::Vacant(slot) = self.modules.entry((shader, variant)) {
            let source = shaders::compose(shader, variant)
                .map_err(|message| GpuError::Validation { stage: "composing a shader".into(), message })?;
            slot.insert(device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(shader),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            }));
        }
        Ok(())
    }

    /// Pipelines built so far.
    pub fn len(&self) -> usize {
        self.pipelines.len() + self.computes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.pipelines.is_empty() && self.computes.is_empty()
    }

    /// The shader modules built so far: (root file, variant).
    pub fn modules(&self) -> Vec<(&'static str, Variant)> {
        self.modules.keys().copied().collect()
    }

    fn build(&mut self, device: &wgpu::Device, key: &PipelineKey) -> Result<wgpu::RenderPipeline, GpuError> {
        self.module(device, key.shader, key.variant)?;
        let environment = key.variant.has(Variant::ENVIRONMENT);
        let layout_key = (key.kind.inputs().to_vec(), environment);
        if !self.layouts.contains_key(&layout_key) {
            let inputs = &layout_key.0;
            let inputs_layout =
                self.input_layouts.entry(inputs.clone()).or_insert_with(|| fullscreen::inputs_layout(device, inputs));
            let mut groups = vec![Some(&self.frame_layout)];
            if !inputs.is_empty() || environment {
                groups.push(Some(inputs_layout));
            }
            if environment {
                groups.push(Some(&self.environment_layout));
            }
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("Pipeline::layout"),
                bind_group_layouts: &groups,
                immediate_size: 0,
            });
            self.layouts.insert(layout_key.clone(), layout);
        }
        let (module, layout) = (&self.modules[&(key.shader, key.variant)], &self.layouts[&layout_key]);
        let label = format!("{}::{} ({})", key.shader, key.entry, key.variant);
        let source = PipelineSource { device, label: &label, layout, module, entry: key.entry };
        let built = match &key.kind {
            PipelineKind::Splats { .. } => splat::pipeline(&source, &key.kind, key.variant),
            PipelineKind::Fullscreen { .. } => fullscreen::pipeline(&source, &key.kind),
        };
        built.ok_or_else(|| GpuError::Device(format!("no pipeline for {label}")))
    }
}
