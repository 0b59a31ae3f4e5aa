//! Plain-old-data structs uploaded to the GPU, kept in sync with `shaders/`.
//!
//! Each struct names the WGSL struct it mirrors and asserts its size, so a
//! change on one side that is not made on the other fails to compile.

use bytemuck::{Pod, Zeroable};

/// One splat, as a per-instance vertex attribute. Mirrors `SplatIn` in
/// `shaders/splat.wgsl` (locations 0-4).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct SplatInstance {
    pub position: [f32; 3],
    /// The disc's radius; negative for a splat of a two-sided object, which
    /// is never back-face culled.
    pub radius: f32,
    pub normal: [f32; 3],
    /// RGB8 and an unused byte, read as unorm8x4 (colours are 8-bit in the files).
    pub colour: [u8; 4],
    /// Opacity in f32, as the reference keeps it: 8 bits would turn α < 0.002
    /// into 0 and 0.5 into 0.502, and alg2's layer count l = Σα/α needs more.
    pub opacity: f32,
}
const _: () = assert!(std::mem::size_of::<SplatInstance>() == 36);

impl SplatInstance {
    /// What an empty slot of a node pool holds: a negative opacity, which
    /// the splat shader culls (`splat.wgsl`; `tiled` skips the slots its
    /// live mask leaves out, `live_mask.rs`).
    pub const VACANT: SplatInstance =
        SplatInstance { position: [0.0; 3], radius: 0.0, normal: [0.0, 0.0, 1.0], colour: [0; 4], opacity: -1.0 };

    pub const ATTRIBUTES: [wgpu::VertexAttribute; 5] = wgpu::vertex_attr_array![
        0 => Float32x3,
        1 => Float32,
        2 => Float32x3,
        3 => Unorm8x4,
        4 => Float32,
    ];

    pub fn layout() -> wgpu::VertexBufferLayout<'static> {
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<SplatInstance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &Self::ATTRIBUTES,
        }
    }
}

/// One vertex of a mesh triangle (three per triangle, not shared: each
/// carries its triangle's plane normal). Mirrors `TriangleIn` in `shaders/splat.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct TriangleVertex {
    pub position: [f32; 3],
    /// Negative for a vertex of a two-sided object (never back-face culled), else 1.
    pub sided: f32,
    /// The vertex normal (interpolated for shading).
    pub normal: [f32; 3],
    pub colour: [u8; 4],
    pub opacity: f32,
    /// The triangle's plane normal, by its winding.
    pub face: [f32; 3],
}
const _: () = assert!(std::mem::size_of::<TriangleVertex>() == 48);

impl TriangleVertex {
    pub const ATTRIBUTES: [wgpu::VertexAttribute; 6] = wgpu::vertex_attr_array![
        0 => Float32x3,
        1 => Float32,
        2 => Float32x3,
        3 => Unorm8x4,
        4 => Float32,
        5 => Float32x3,
    ];

    pub fn layout() -> wgpu::VertexBufferLayout<'static> {
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<TriangleVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &Self::ATTRIBUTES,
        }
    }
}

/// Per-frame constants. Mirrors `Frame` in `shaders/frame.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct FrameUniforms {
    pub view: [[f32; 4]; 4],
    pub proj: [[f32; 4]; 4],
    /// width, height, 1/width, 1/height
    pub viewport: [f32; 4],
    /// near, far, unused, 1/(far - near)
    pub depth: [f32; 4],
    /// EWA low-pass radius in pixels (0: none), Gaussian sharpness k (Eq. 3), min |cos| of a footprint, back-face culling (0/1)
    pub splat: [f32; 4],
    /// direction to the light in eye space, shininess
    pub light: [f32; 4],
    /// ambient, diffuse, specular, unused
    pub material: [f32; 4],
    /// background colour, alpha
    pub background: [f32; 4],
    /// the window's half extent at view depth 1 (tan(fov_x/2), tan(fov_y/2) for a whole frame), splat radius scale, least radius per unit of view depth (`--min-pixel-radius`)
    pub lens: [f32; 4],
    /// Environment effects: η, dispersion δ, multi-layer (0/1), skybox (0/1)
    pub environment: [f32; 4],
    /// The map's up axis (world), the angle of one texel of its level 0 (2π / width)
    pub environment_up: [f32; 4],
    /// The world direction the map's centre column looks along, unused
    pub environment_front: [f32; 4],
    /// Scene lights in eye space, two rows each: position (w = 1) or the
    /// direction towards the light (w = 0); colour × intensity, and 1 for
    /// inverse-square falloff.
    pub lights: [[f32; 4]; 2 * MAX_LIGHTS],
    /// The number of lights, unused ×3.
    pub light_count: [u32; 4],
    /// Clip planes in eye space (`EyeClip::planes`).
    pub clip: [[f32; 4]; 2 * MAX_CLIP_PLANES],
    /// `EyeClip::counts`, unused.
    pub clip_counts: [u32; 4],
    /// The centre of the frame's window at view depth 1 (eye space; 0 for a
    /// whole frame), unused ×2 (`crate::subframe`).
    pub window: [f32; 4],
}
const _: () =
    assert!(std::mem::size_of::<FrameUniforms>() == 288 + 32 * MAX_LIGHTS + 16 + 32 * MAX_CLIP_PLANES + 16 + 16);

use pointblend_core::frame::clip::MAX_CLIP_PLANES;

use pointblend_core::frame::lights::MAX_LIGHTS;

/// A splat's shadow coefficients, one unorm8 per light: a second
/// per-instance vertex buffer beside [`SplatInstance`], present only in a
/// frame lit by scene lights (locations 5-6 of `SplatIn`, `Variant::LIGHTS`).
pub type SplatLight = [u8; MAX_LIGHTS];

/// The vertex layout of [`SplatLight`].
pub fn splat_light_layout() -> wgpu::VertexBufferLayout<'static> {
    const ATTRIBUTES: [wgpu::VertexAttribute; 2] = wgpu::vertex_attr_array![5 => Unorm8x4, 6 => Unorm8x4];
    wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<SplatLight>() as u64,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &ATTRIBUTES,
    }
}

/// The constants of one pass, in its own slot of a buffer bound with a
/// dynamic offset. Mirrors `Pass` in `shaders/frame.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct PassUniforms {
    /// The cloud's one colour (rgb, 0..1) for single-channel weight targets.
    pub uniform_colour: [f32; 4],
    /// ε (view-depth units), low-precision depth steps n (Eq. 10/14), unused, unused
    pub depth: [f32; 4],
    /// this pass's layer, layer count K, Voronoi depth (0/1), unused
    pub layers: [u32; 4],
    /// A full-screen effect's parameters: eye-dome lighting's strength,
    /// radius (pixels) and the depth buffer's push behind the front (ε or 0), unused.
    pub effect: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<PassUniforms>() == 64);

/// Bytes between two pass slots: the largest dynamic-offset alignment wgpu allows a device to ask.
pub const PASS_SLOT_BYTES: u64 = 256;
