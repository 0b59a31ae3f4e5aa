//! Frames of a scene with meshes (`mesh` and `hybrid` objects) in a mode
//! that draws triangles: every triangle of the scene is uploaded once (three
//! unshared vertices each, in world space, materials applied), and each
//! frame chooses which leaves are drawn as triangles and which splats are
//! drawn ([`pointblend_core::hybrid::select`], Guennebaud's hybrid rules; part of
//! the frame's time). When the splats chosen change, they are gathered into
//! one cloud and handed to a [`PreparedScene`] of their own as a moving
//! scene's next frame (as under a point budget: the grouped modes get the
//! hash grouping of the splats drawn), and the mode's passes draw the
//! triangles' ranges beside them.
//!
//! Whether a frame draws triangles at all is decided by
//! [`crate::frame::resolve`] (a mode that cannot, a lit frame and a moving
//! scene draw the meshes as their vertex splats, and the spec says why).

use std::sync::Arc;
use std::time::Instant;

use super::subset::SubsetScene;
use super::{FrameError, PreparedScene};
use crate::context::GpuError;
use crate::frame::{Camera, FrameSpec};
use crate::gpu_data::TriangleVertex;
use crate::gpu_renderer::GpuRenderer;
use crate::gpu_scene::{GpuScene, TriangleDraw, WholeScene};
use crate::report::{FrameReport, HybridStats};
use pointblend_core::hybrid::select::{HybridOptions, HybridSelection, SceneSurfaces};

/// The scene's triangles and the frames of the splats drawn beside them.
pub(super) struct HybridFrames {
    surfaces: SceneSurfaces,
    buffer: Option<Arc<wgpu::Buffer>>,
    selected: Option<HybridSelection>,
    /// The drawn triangles' indices on the GPU, for the last selection's triangles.
    indices: Option<Arc<wgpu::Buffer>>,
    chosen: SubsetScene,
    /// What a frame with triangles takes from the whole scene, as a frame of every splat would.
    whole: WholeScene,
    /// Every splat is one-sided: triangles facing away can be culled by their winding.
    one_sided: bool,
}

impl PreparedScene {
    /// The GPU copy the frame `spec` (with triangles) draws from `camera`,
    /// its leaves chosen here, with what they cost in `report`. Such a frame
    /// draws every splat it chooses: no point budget applies (the spec's notes say so).
    pub(super) fn hybrid_scene(
        &mut self,
        gpu: &GpuRenderer,
        camera: &Camera,
        spec: &FrameSpec,
        report: &mut FrameReport,
    ) -> Result<&mut GpuScene, FrameError> {
        let (settings, size) = (&spec.drawn, spec.size);
        if self.hybrid.is_none() {
            let flat = self.scene.flatten();
            let surfaces = self.scene.surfaces(&flat);
            self.hybrid = Some(Box::new(HybridFrames {
                surfaces,
                buffer: None,
                selected: None,
                indices: None,
                chosen: SubsetScene::of(self, "hybrid"),
                whole: WholeScene::of(&self.cloud),
                one_sided: self.cloud.two_sided.iter().all(|&two| !two),
            }));
        }
        let whole = Arc::clone(&self.cloud);
        let state = self.hybrid.as_mut().expect("made above");
        if state.buffer.is_none() {
            let bytes = (state.surfaces.triangle_count() * 3 * std::mem::size_of::<TriangleVertex>()) as u64;
            let limit = gpu.ctx.device.limits().max_buffer_size;
            if bytes > limit {
                return Err(FrameError::Gpu(GpuError::TooLarge(format!(
                    "the scene's {} mesh triangles need {:.1} MiB in one vertex buffer, more than the {:.1} MiB this GPU \
                     allows; use `ply =` (its vertex splats) or a smaller mesh",
                    state.surfaces.triangle_count(),
                    bytes as f64 / (1u64 << 20) as f64,
                    limit as f64 / (1u64 << 20) as f64
                ))));
            }
            let device = &gpu.ctx.device;
            let buffer = gpu.ctx.allocating("uploading the mesh triangles", || {
                TriangleDraw::upload(device, &whole, state.surfaces.triangles())
            })?;
            state.buffer = Some(Arc::new(buffer));
        }
        let started = Instant::now();
        let options = HybridOptions {
            pixels: settings.hybrid_pixels,
            radius_scale: settings.radius_scale,
            cull: !settings.lit_by_lights(),
        };
        let selection = state.surfaces.select(camera, size, options);
        let select_ms = started.elapsed().as_secs_f64() * 1e3;
        let started = Instant::now();
        let changed = state.selected.as_ref().is_none_or(|s| s.splats != selection.splats);
        if state.indices.is_none() || state.selected.as_ref().is_none_or(|s| s.triangles != selection.triangles) {
            state.indices = Some(Arc::new(TriangleDraw::upload_indices(&gpu.ctx.device, &selection.triangles)));
        }
        let hash = self.hash;
        let frames = state.chosen.next(Some(gpu), changed, || {
            let splats: Vec<u8> = selection.splats.iter().flat_map(|v| v.to_le_bytes()).collect();
            (selection.gather(&whole), pointblend_core::hash::fnv1a(hash, &splats))
        })?;
        let draw = TriangleDraw {
            buffer: Arc::clone(state.buffer.as_ref().expect("uploaded above")),
            ranges: selection.triangles.clone(),
            indices: Arc::clone(state.indices.as_ref().expect("uploaded above")),
            cull_back: settings.backface_culling && state.one_sided,
        };
        report.hybrid = Some(HybridStats {
            pixels: settings.hybrid_pixels,
            triangles: selection.triangle_count(),
            splats: selection.splats.len(),
            triangle_leaves: selection.triangle_leaves,
            splat_leaves: selection.splat_leaves,
            transition_splats: selection.transition_splats,
            select_ms,
            update_ms: started.elapsed().as_secs_f64() * 1e3,
            changed,
        });
        let scene = frames.gpu_scene_mut(gpu, spec, report)?;
        scene.set_triangles(Some(draw), &state.whole);
        state.selected = Some(selection);
        Ok(scene)
    }
}
