//! The compute pass builder: a pipeline from a root file's `@compute` entry
//! point, with group 0 the frame's uniforms (as every pass) and group 1 the
//! buffers and storage textures the pass names, described by [`Binding`]s so
//! that the pipeline cache can key its layouts by them.

/// One binding of a compute pass's group 1, in binding order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Binding {
    Uniform,
    /// A storage buffer, read-only or read-write.
    Storage {
        read_only: bool,
    },
    /// A single 2D image the pass writes.
    StorageTexture(wgpu::TextureFormat),
}

/// The layout of group 1 for `bindings`.
pub fn layout(device: &wgpu::Device, bindings: &[Binding]) -> wgpu::BindGroupLayout {
    let types = bindings.iter().map(|kind| match *kind {
        Binding::Uniform => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        Binding::Storage { read_only } => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        Binding::StorageTexture(format) => wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format,
            view_dimension: wgpu::TextureViewDimension::D2,
        },
    });
    super::group_layout(device, "Compute::layout", wgpu::ShaderStages::COMPUTE, types)
}

/// Builds the pipeline of `source`'s compute entry point.
pub fn pipeline(source: &super::PipelineSource<'_>) -> wgpu::ComputePipeline {
    source.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(source.label),
        layout: Some(source.layout),
        module: source.module,
        entry_point: Some(source.entry),
        compilation_options: Default::default(),
        cache: None,
    })
}
