//! The environment map on the GPU (Zhang & Pajarola §5.2.3): its mip chain
//! (`scene::environment_map`, pre-filtered on the CPU so that the GPU and the
//! reference read the same averages) as one Rgba16Float texture, and a
//! sampler that wraps the longitude (no seam at the ±180° meridian), clamps
//! the latitude at the poles, and filters linearly within and between
//! levels. The compositing pass picks the level from how fast its lookup
//! direction turns between pixels (`shaders/environment.wgsl`). It is bound
//! at group 2 of the passes built with `Variant::ENVIRONMENT`; a scene without
//! a map uploads and binds nothing.

use wgpu::util::DeviceExt;

use crate::scene::environment_map::EnvironmentMap;

/// A scene's environment map, uploaded.
#[derive(Debug)]
pub struct EnvTexture {
    pub view: wgpu::TextureView,
    pub sampler: wgpu::Sampler,
    /// Level 0's width: the angle of one texel is 2π / width.
    pub width: u32,
    pub height: u32,
    pub levels: u32,
    pub name: String,
    /// Group 2 of the passes that read the map, made on first use and kept
    /// with the map (one per scene, not one per pass and frame).
    bind_group: std::sync::OnceLock<wgpu::BindGroup>,
}

impl EnvTexture {
    /// Uploads `map` and its mip chain (texels capped to half float's range on load).
    /// A map larger than the device's textures is drawn from its largest
    /// mip level that fits, said once in a warning.
    pub fn upload(device: &wgpu::Device, queue: &wgpu::Queue, map: &EnvironmentMap) -> Self {
        let max = device.limits().max_texture_dimension_2d;
        let first = map.levels.iter().position(|l| l.width <= max && l.height <= max).unwrap_or(map.levels.len() - 1);
        let levels_used = &map.levels[first..];
        let (width, height) = (levels_used[0].width, levels_used[0].height);
        if first > 0 {
            pointblend_core::progress::warn_once(format!(
                "{}: {}x{} texels is more than this GPU's {max}-texel textures: drawn from its {width}x{height} level",
                map.name,
                map.width(),
                map.height()
            ));
        }
        // One layer, so the data is each level in turn (half floats: a lossless
        // store of the capped texels to 3 significant digits).
        let mut bytes = Vec::new();
        for level in levels_used {
            for texel in &level.texels {
                for v in [texel[0], texel[1], texel[2], 1.0] {
                    bytes.extend_from_slice(&half::f16::from_f32(v).to_bits().to_le_bytes());
                }
            }
        }
        let levels = levels_used.len() as u32;
        let texture = device.create_texture_with_data(
            queue,
            &wgpu::TextureDescriptor {
                label: Some("Environment::map"),
                size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
                mip_level_count: levels,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba16Float,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            &bytes,
        );
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("Environment::sampler"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        Self {
            view: texture.create_view(&Default::default()),
            sampler,
            width,
            height,
            levels,
            name: map.name.clone(),
            bind_group: std::sync::OnceLock::new(),
        }
    }

    /// Bytes of the texture with its mip chain.
    pub fn bytes(&self) -> u64 {
        let mut total = 0u64;
        let (mut w, mut h) = (self.width as u64, self.height as u64);
        for _ in 0..self.levels {
            total += w * h * 8;
            (w, h) = ((w / 2).max(1), (h / 2).max(1));
        }
        total
    }

    /// The layout of group 2: the map (filterable) and its sampler.
    pub fn layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
        let map = wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        };
        let sampler = wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering);
        super::passes::group_layout(
            device,
            "Environment::layout",
            wgpu::ShaderStages::FRAGMENT,
            [map, sampler].into_iter(),
        )
    }

    /// Group 2 of a pass that reads the map, made once (`layout` is
    /// [`Self::layout`]'s, which wgpu keeps as one layout per device).
    pub fn bind_group(&self, device: &wgpu::Device, layout: &wgpu::BindGroupLayout) -> &wgpu::BindGroup {
        self.bind_group.get_or_init(|| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("Environment::bind_group"),
                layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&self.view) },
                    wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::Sampler(&self.sampler) },
                ],
            })
        })
    }
}
