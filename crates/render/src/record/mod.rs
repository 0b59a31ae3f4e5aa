//! Recording a frame's passes: each kind of pass records itself, in its own
//! file ([`splat`], [`fullscreen`], [`compute`]), from what every kind needs
//! ([`Recording`]): the device, the pipeline cache, the frame's targets and
//! plan, the scene, the frame's bind group, and the record of every view a
//! pass is given and how ([`Bound`], which render_core holds `--explain`
//! against). The renderer's `encode` is a loop over the plan's commands.
//!
//! This sits above `passes` (the passes as data and their pipeline
//! builders) and `pipelines` (the cache), so neither imports the other back.

pub mod compute;
pub mod fullscreen;
pub mod splat;

use crate::context::GpuError;
use crate::gpu_scene::GpuScene;
use crate::pipelines::PipelineCache;
use crate::plan::{Layout, RenderPlan, TargetDesc, TargetId};
use crate::targets::TargetPool;
use crate::touches::{Bound, Slot};

/// What every pass of one frame records with.
pub struct Recording<'a> {
    pub device: &'a wgpu::Device,
    pub cache: &'a mut PipelineCache,
    pub pool: &'a TargetPool,
    pub plan: &'a RenderPlan,
    pub scene: &'a GpuScene,
    /// Group 0: the frame's uniforms and, at a pass's offset, its slot.
    pub frame: &'a wgpu::BindGroup,
    /// Every view the frame's passes are given, and where.
    pub bound: &'a mut Vec<Bound>,
}

/// Where one pass records: the plan's step it belongs to, and the offset of
/// its uniform slot in the frame's bind group.
#[derive(Debug, Clone, Copy)]
pub struct At {
    pub step: usize,
    pub offset: u32,
}

/// The error for something the plan should hold and does not.
pub fn missing(what: &str) -> GpuError {
    GpuError::Device(format!("the plan has no target '{what}'"))
}

/// A new command encoder for the frame (a pass that reads back mid-frame submits the one before).
pub fn new_encoder(device: &wgpu::Device) -> wgpu::CommandEncoder {
    device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("Renderer::encoder") })
}

impl<'a> Recording<'a> {
    /// The plan's description of target `id`.
    pub fn target(&self, id: TargetId) -> Result<&'a TargetDesc, GpuError> {
        self.plan.target(id).ok_or_else(|| missing(id.0))
    }

    /// The view of target `id` (all its layers).
    pub fn view(&self, id: TargetId) -> Result<&'a wgpu::TextureView, GpuError> {
        self.pool.view(id).ok_or_else(|| missing(id.0))
    }

    /// The view of layer `layer` of target `id`.
    pub fn layer_view(&self, id: TargetId, layer: u32) -> Result<&'a wgpu::TextureView, GpuError> {
        self.pool.layer_view(id, layer).ok_or_else(|| missing(id.0))
    }

    /// Notes that the pass of `step` was given `view` at `slot`, read and/or written.
    pub fn given(&mut self, step: usize, slot: Slot, view: &wgpu::TextureView, reads: bool, writes: bool) {
        self.bound.push(Bound { pass: step, slot, view: view.clone(), reads, writes });
    }

    /// The texture dimensions and the group-1 bind group of a pass that
    /// reads `ids` (none when it reads nothing).
    #[allow(clippy::type_complexity)]
    pub fn inputs(
        &mut self,
        step: usize,
        ids: &[TargetId],
    ) -> Result<Option<(Vec<wgpu::TextureViewDimension>, wgpu::BindGroup)>, GpuError> {
        if ids.is_empty() {
            return Ok(None);
        }
        let mut dims = Vec::with_capacity(ids.len());
        let mut views = Vec::with_capacity(ids.len());
        for &id in ids {
            dims.push(match self.target(id)?.layout {
                Layout::Single => wgpu::TextureViewDimension::D2,
                Layout::Array { .. } => wgpu::TextureViewDimension::D2Array,
            });
            views.push(self.view(id)?);
        }
        for (binding, view) in views.iter().enumerate() {
            self.given(step, Slot::Input(binding as u32), view, true, false);
        }
        let entries: Vec<wgpu::BindGroupEntry<'_>> = views
            .iter()
            .enumerate()
            .map(|(binding, view)| wgpu::BindGroupEntry {
                binding: binding as u32,
                resource: wgpu::BindingResource::TextureView(view),
            })
            .collect();
        let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("Pass::inputs"),
            layout: self.cache.inputs_layout(self.device, &dims),
            entries: &entries,
        });
        Ok(Some((dims, group)))
    }
}
