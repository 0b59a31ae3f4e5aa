//! The intermediate textures of a frame, sized to the output.
//!
//! Depth is linear view depth in Depth32Float (the ε test needs f32); the
//! accumulation targets are Rgba16Float, which every adapter can blend and
//! which keeps Σw·c exact to ~1e-3 relative for thousands of splats a pixel.

/// Formats of the intermediate targets.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
pub const ACCUM_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Depth and accumulation textures for one output size.
pub struct FrameTargets {
    pub width: u32,
    pub height: u32,
    pub depth: wgpu::TextureView,
    pub accum_color: wgpu::TextureView,
    pub accum_normal: wgpu::TextureView,
    /// Binds the two accumulation targets for the normalisation pass.
    pub normalize_inputs: wgpu::BindGroup,
}

impl FrameTargets {
    pub fn new(device: &wgpu::Device, width: u32, height: u32, normalize_layout: &wgpu::BindGroupLayout) -> Self {
        let make = |label: &str, format, usage| {
            device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage,
                    view_formats: &[],
                })
                .create_view(&wgpu::TextureViewDescriptor::default())
        };
        let attach_and_read = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let depth = make("FrameTargets::depth", DEPTH_FORMAT, attach_and_read);
        let accum_color = make("FrameTargets::accumulated_color", ACCUM_FORMAT, attach_and_read);
        let accum_normal = make("FrameTargets::accumulated_normal", ACCUM_FORMAT, attach_and_read);
        let normalize_inputs = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("Normalize::inputs"),
            layout: normalize_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&accum_color) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&accum_normal) },
            ],
        });
        Self { width, height, depth, accum_color, accum_normal, normalize_inputs }
    }
}
