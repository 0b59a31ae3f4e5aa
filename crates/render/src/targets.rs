//! The target pool: allocates exactly the targets a plan describes.
//!
//! [`TargetPool::prepare`] keeps each texture whose description is still in
//! the plan, frees every other one first (so memory is not held twice), and
//! creates the missing ones, with a view of the whole texture and, for
//! arrays, one render view per layer. What the pool holds is always what the
//! plan (and `--explain`) lists, byte for byte.

use super::plan::{Layout, TargetDesc, TargetId};

/// The formats of the targets, chosen for what they hold: depth compared
/// against ε must be f32 (linear view depth); a value one fragment writes
/// (a group's nearest splat, a blend bounded by 1) fits Rgba16Float.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
pub const ACCUM_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Colour targets of a cloud of one colour hold only w.
pub const WEIGHT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;
/// True view depth written as colour, read by a compositing pass.
pub const VIEW_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// The colour target's format for one fragment's values: (w·rgb, w), or w alone.
pub fn colour_format(weight_only: bool) -> wgpu::TextureFormat {
    if weight_only { WEIGHT_FORMAT } else { ACCUM_FORMAT }
}

/// How targets that add up every fragment of a pixel (Σw·rgb, Σw, Σw·n,
/// Σw·α) store their sums.
///
/// Half floats stop adding a weight of 1 at 2048 and overflow above 65504,
/// and scans hold many overlapping splats where registered scans overlap, so
/// the sums are f32 (24-bit mantissa: 100,000 coincident splats sum exactly
/// enough for 8-bit output) wherever the adapter can blend f32
/// (`FLOAT32_BLENDABLE`). Chosen over scaled weights, which cannot know how
/// many splats a pixel will meet, and over a renormalising pass, which costs
/// a pass per frame. Without the feature the sums fall back to f16 and the
/// plan says so.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SumPrecision {
    F32,
    F16,
}

impl SumPrecision {
    /// The best the device can blend.
    pub fn of(device: &wgpu::Device) -> Self {
        if device.features().contains(wgpu::Features::FLOAT32_BLENDABLE) { Self::F32 } else { Self::F16 }
    }

    /// A sum target's format: four channels, or one (Σw of a cloud of one colour).
    pub fn format(self, one_channel: bool) -> wgpu::TextureFormat {
        match (self, one_channel) {
            (Self::F32, false) => wgpu::TextureFormat::Rgba32Float,
            (Self::F32, true) => wgpu::TextureFormat::R32Float,
            (Self::F16, false) => ACCUM_FORMAT,
            (Self::F16, true) => WEIGHT_FORMAT,
        }
    }

    /// The plan's note when sums can saturate.
    pub fn note(self) -> Option<String> {
        (self == Self::F16).then(|| {
            "this GPU cannot blend f32: the targets that sum overlapping splats (two-pass, peeling) are f16, \
             which stops adding at 2048 splats of weight 1 per pixel"
                .to_string()
        })
    }
}

struct PooledTarget {
    desc: TargetDesc,
    /// What the views below view (passes use them; a read-back copies the texture).
    texture: wgpu::Texture,
    whole: wgpu::TextureView,
    layers: Vec<wgpu::TextureView>,
}

/// The textures of the current plan.
#[derive(Default)]
pub struct TargetPool {
    targets: Vec<PooledTarget>,
}

impl TargetPool {
    /// Makes the pool hold exactly `descs`.
    pub fn prepare(&mut self, device: &wgpu::Device, descs: &[TargetDesc]) {
        self.targets.retain(|t| descs.contains(&t.desc));
        for desc in descs {
            if !self.targets.iter().any(|t| &t.desc == desc) {
                self.targets.push(create(device, desc));
            }
        }
    }

    /// Frees every texture.
    pub fn clear(&mut self) {
        self.targets.clear();
    }

    fn get(&self, id: TargetId) -> Option<&PooledTarget> {
        self.targets.iter().find(|t| t.desc.id == id)
    }

    /// The texture of a target.
    pub fn texture(&self, id: TargetId) -> Option<&wgpu::Texture> {
        self.get(id).map(|t| &t.texture)
    }

    /// The view of the whole target (an array view for arrays).
    pub fn view(&self, id: TargetId) -> Option<&wgpu::TextureView> {
        self.get(id).map(|t| &t.whole)
    }

    /// A render view of one layer (layer 0 of a single image is the image).
    pub fn layer_view(&self, id: TargetId, layer: u32) -> Option<&wgpu::TextureView> {
        let target = self.get(id)?;
        match target.desc.layout {
            Layout::Single => (layer == 0).then_some(&target.whole),
            Layout::Array { .. } => target.layers.get(layer as usize),
        }
    }

    /// The target `view` is a view of, by the view's identity, and its layer
    /// (`None` for the whole texture).
    pub fn target_of(&self, view: &wgpu::TextureView) -> Option<(TargetId, Option<u32>)> {
        self.targets.iter().find_map(|t| {
            if &t.whole == view {
                return Some((t.desc.id, None));
            }
            t.layers.iter().position(|l| l == view).map(|layer| (t.desc.id, Some(layer as u32)))
        })
    }

    pub fn desc(&self, id: TargetId) -> Option<&TargetDesc> {
        self.get(id).map(|t| &t.desc)
    }

    /// The descriptions of what the pool holds.
    pub fn descs(&self) -> Vec<TargetDesc> {
        self.targets.iter().map(|t| t.desc.clone()).collect()
    }

    /// Bytes of all textures held.
    pub fn bytes(&self) -> u64 {
        self.targets.iter().map(|t| t.desc.bytes()).sum()
    }
}

fn create(device: &wgpu::Device, desc: &TargetDesc) -> PooledTarget {
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(desc.id.0),
        size: wgpu::Extent3d { width: desc.width, height: desc.height, depth_or_array_layers: desc.layers() },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: desc.format,
        usage: if desc.storage {
            wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING
        } else {
            // COPY_SRC: a plan's front depth is read back (`readback::read_depth32`).
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC
        },
        view_formats: &[],
    });
    let view = |dimension, base_array_layer, array_layer_count| {
        texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some(desc.id.0),
            dimension: Some(dimension),
            base_array_layer,
            array_layer_count,
            ..Default::default()
        })
    };
    let (whole, layers) = match desc.layout {
        Layout::Single => (view(wgpu::TextureViewDimension::D2, 0, None), Vec::new()),
        Layout::Array { layers } => (
            view(wgpu::TextureViewDimension::D2Array, 0, None),
            (0..layers).map(|k| view(wgpu::TextureViewDimension::D2, k, Some(1))).collect(),
        ),
    };
    PooledTarget { desc: desc.clone(), texture, whole, layers }
}
