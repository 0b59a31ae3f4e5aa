//! The intermediate textures of a frame, sized to the output.
//!
//! Depth is linear view depth in Depth32Float (the ε test needs f32); the
//! accumulation targets are Rgba16Float, which every adapter can blend and
//! which keeps Σw·c exact to ~1e-3 relative for thousands of splats a pixel.

/// Formats of the intermediate targets.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
pub const ACCUM_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Colour targets of a cloud of one colour hold only Σw.
pub const WEIGHT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;

/// The colour target's format: (Σw·rgb, Σw), or Σw alone.
pub fn colour_format(weight_only: bool) -> wgpu::TextureFormat {
    if weight_only { WEIGHT_FORMAT } else { ACCUM_FORMAT }
}

/// Depth and accumulation textures for one output size.
pub struct FrameTargets {
    pub width: u32,
    pub height: u32,
    pub depth: wgpu::TextureView,
    pub accum_color: wgpu::TextureView,
    /// The normal sums; a 1x1 placeholder when lighting is off.
    pub accum_normal: wgpu::TextureView,
    /// Binds the two accumulation targets for the normalisation pass.
    pub normalize_inputs: wgpu::BindGroup,
    /// Whether the normal target is real (lighting on).
    pub lit: bool,
    /// Whether the colour target holds only Σw (a cloud of one colour).
    pub weight_only: bool,
}

impl FrameTargets {
    pub fn new(
        device: &wgpu::Device,
        (width, height): (u32, u32),
        normalize_layout: &wgpu::BindGroupLayout,
        lit: bool,
        weight_only: bool,
    ) -> Self {
        let make_sized = |label: &str, format, usage, (width, height)| {
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
        let make = |label: &str, format, usage| make_sized(label, format, usage, (width, height));
        let attach_and_read = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let depth = make("FrameTargets::depth", DEPTH_FORMAT, attach_and_read);
        let accum_color = make("FrameTargets::accumulated_color", colour_format(weight_only), attach_and_read);
        let normal_size = if lit { (width, height) } else { (1, 1) };
        let accum_normal = make_sized("FrameTargets::accumulated_normal", ACCUM_FORMAT, attach_and_read, normal_size);
        let normalize_inputs = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("Normalize::inputs"),
            layout: normalize_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&accum_color) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&accum_normal) },
            ],
        });
        Self { width, height, depth, accum_color, accum_normal, normalize_inputs, lit, weight_only }
    }
}

/// Format of the per-group depth image read by the compositing pass.
pub const GROUP_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// The K group images of deferred blending: 2D array textures with one layer
/// per group (so K is not limited by the number of colour attachments), each
/// layer with its own z-buffer layer.
pub struct GroupTargets {
    pub width: u32,
    pub height: u32,
    pub layers: u32,
    /// Whether the normal layers are real (lighting on); else a 1x1 placeholder.
    pub lit: bool,
    /// Whether the colour layers hold only w (a cloud of one colour).
    pub weight_only: bool,
    /// Per layer: colour, normal, depth views and the z-buffer view.
    pub layer_views: Vec<[wgpu::TextureView; 4]>,
    /// Binds the three arrays for the compositing pass.
    pub composite_inputs: wgpu::BindGroup,
}

impl GroupTargets {
    pub fn new(
        device: &wgpu::Device,
        (width, height, layers): (u32, u32, u32),
        composite_layout: &wgpu::BindGroupLayout,
        lit: bool,
        weight_only: bool,
    ) -> Self {
        let layers = layers.max(1);
        let make_sized = |label: &str, format, (width, height, layers)| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d { width, height, depth_or_array_layers: layers },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            })
        };
        let make = |label: &str, format| make_sized(label, format, (width, height, layers));
        let normal_size = if lit { (width, height, layers) } else { (1, 1, 1) };
        let textures = [
            make("GroupTargets::colour", colour_format(weight_only)),
            make_sized("GroupTargets::normal", ACCUM_FORMAT, normal_size),
            make("GroupTargets::depth", GROUP_DEPTH_FORMAT),
            make("GroupTargets::z_buffer", DEPTH_FORMAT),
        ];
        let layer_views = (0..layers)
            .map(|k| {
                [0, 1, 2, 3].map(|t| {
                    let layer = if t == 1 && !lit { 0 } else { k };
                    textures[t].create_view(&wgpu::TextureViewDescriptor {
                        label: Some("GroupTargets::layer"),
                        dimension: Some(wgpu::TextureViewDimension::D2),
                        base_array_layer: layer,
                        array_layer_count: Some(1),
                        ..Default::default()
                    })
                })
            })
            .collect();
        let array = |t: &wgpu::Texture| {
            t.create_view(&wgpu::TextureViewDescriptor {
                label: Some("GroupTargets::array"),
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            })
        };
        let (colour, normal, depth) = (array(&textures[0]), array(&textures[1]), array(&textures[2]));
        let composite_inputs = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("Composite::inputs"),
            layout: composite_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&colour) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&normal) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&depth) },
            ],
        });
        Self { width, height, layers, lit, weight_only, layer_views, composite_inputs }
    }
}
