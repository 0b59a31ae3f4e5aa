//! One file per pass: each builds its pipeline and records its render pass.

pub mod accumulate;
pub mod deferred_composite;
pub mod deferred_geometry;
pub mod nearest;
pub mod normalize;
pub mod visibility;

use super::gpu_data::SplatInstance;

/// How a splat pass uses the depth buffer.
pub(super) struct DepthTest {
    pub write: bool,
    pub compare: wgpu::CompareFunction,
}

/// Which fragment stage a splat pipeline runs: the entry point, its unlit
/// variant when lighting is off, and the single-channel weight-only output
/// (the WGSL override `WEIGHT_ONLY`) for clouds of one colour.
pub(super) struct FragmentVariant<'a> {
    pub entry: &'a str,
    pub lit: bool,
    pub weight_only: bool,
}

/// A pipeline that draws every splat as an instanced 4-vertex strip.
pub(super) fn splat_pipeline(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    fragment: &FragmentVariant<'_>,
    targets: &[Option<wgpu::ColorTargetState>],
    depth: DepthTest,
) -> wgpu::RenderPipeline {
    let entry = lighting_entry(fragment.lit, fragment.entry);
    let constants = [("WEIGHT_ONLY", if fragment.weight_only { 1.0 } else { 0.0 })];
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_splat"),
            compilation_options: Default::default(),
            buffers: &[Some(SplatInstance::layout())],
        },
        primitive: wgpu::PrimitiveState { topology: wgpu::PrimitiveTopology::TriangleStrip, ..Default::default() },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: super::targets::DEPTH_FORMAT,
            depth_write_enabled: Some(depth.write),
            depth_compare: Some(depth.compare),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(&entry),
            compilation_options: wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() },
            targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// Colour attachment of an intermediate target, cleared to zero.
pub(super) fn cleared(view: &wgpu::TextureView) -> Option<wgpu::RenderPassColorAttachment<'_>> {
    Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT), store: wgpu::StoreOp::Store },
    })
}

/// Depth attachment that is either cleared to the far plane or kept.
pub(super) fn depth(view: &wgpu::TextureView, clear: bool) -> Option<wgpu::RenderPassDepthStencilAttachment<'_>> {
    Some(wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load: if clear { wgpu::LoadOp::Clear(1.0) } else { wgpu::LoadOp::Load },
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    })
}

/// Records one render pass, described by `desc`, that draws splats with `pipeline`.
pub(super) fn record_splats(
    encoder: &mut wgpu::CommandEncoder,
    desc: &wgpu::RenderPassDescriptor<'_>,
    pipeline: &wgpu::RenderPipeline,
    frame: &wgpu::BindGroup,
    draw: impl FnOnce(&mut wgpu::RenderPass<'_>),
) {
    let mut pass = encoder.begin_render_pass(desc);
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, frame, &[]);
    draw(&mut pass);
}

/// Drops the normal slot (`normal_slot`) of a pass's colour targets or
/// attachments when lighting is off: without lighting no normal is written.
pub(super) fn lighting_slots<T: Clone>(lit: bool, slots: &[T], normal_slot: usize) -> Vec<T> {
    slots.iter().enumerate().filter(|(i, _)| lit || *i != normal_slot).map(|(_, t)| t.clone()).collect()
}

/// The fragment entry point for lighting on or off (`NAME` or `NAME_unlit`).
pub(super) fn lighting_entry(lit: bool, entry: &str) -> String {
    if lit { entry.to_string() } else { format!("{entry}_unlit") }
}
