//! Frames of a scene with meshes (`mesh` and `hybrid` objects) in a mode
//! that draws triangles: every triangle of the scene is uploaded once (three
//! unshared vertices each, in world space, materials applied), and each
//! frame chooses which leaves are drawn as triangles and which splats are
//! drawn ([`pointblend_core::hybrid::select`], Guennebaud's hybrid rules; part of
//! the frame's time). When the splats chosen change, they are gathered into
//! one cloud and shown in the hybrid slot of the scene's cache as a moving
//! scene's next frame (`show.rs`) (as under a point budget: the grouped modes get the
//! hash grouping of the splats drawn), and the mode's passes draw the
//! triangles' ranges beside them.
//!
//! Whether a frame draws triangles at all is decided by
//! [`crate::frame::resolve`] (a mode that cannot, a lit frame and a moving
//! scene draw the meshes as their vertex splats, and the spec says why).

use std::sync::Arc;
use std::time::Instant;

use super::{FrameError, PreparedScene};
use crate::context::GpuError;
use crate::frame::subset::{Choosing, Subset};
use crate::frame::{Camera, FrameSpec};
use crate::gpu_data::TriangleVertex;
use crate::gpu_renderer::GpuRenderer;
use crate::gpu_scene::{GpuScene, TriangleDraw, WholeScene};
use crate::report::{FrameReport, HybridStats};
use crate::scene_cache::Slot;
use pointblend_core::hybrid::subset::HybridSubset;

/// The leaves a hybrid frame draws as triangles and the splats beside
/// them, and what such a frame takes from the whole scene.
pub(super) struct HybridSubsetState {
    subset: HybridSubset,
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
        let settings = &spec.drawn;
        let triangles = self.triangles(gpu)?;
        let state = self.hybrid.as_mut().expect("made with the triangles");
        let started = Instant::now();
        state.subset.pixels = settings.hybrid_pixels;
        let Ok(choice) = state.subset.choose(camera, spec.size, Choosing::of(settings));
        let changed = choice.cloud.is_some();
        let selection = state.subset.selection().expect("chosen above");
        let ranges = selection.triangles.clone();
        let cull_back = settings.backface_culling && state.one_sided;
        let whole = state.whole;
        let mut stats = HybridStats {
            pixels: settings.hybrid_pixels,
            triangles: selection.triangle_count(),
            splats: selection.splats.len(),
            triangle_leaves: selection.triangle_leaves,
            splat_leaves: selection.splat_leaves,
            transition_splats: selection.transition_splats,
            select_ms: state.subset.select_ms,
            update_ms: 0.0,
            changed,
        };
        let indices = match &self.prepared.triangle_indices {
            Some((kept, indices)) if *kept == ranges => Arc::clone(indices),
            _ => {
                let indices = Arc::new(TriangleDraw::upload_indices(&gpu.ctx.device, &ranges));
                self.prepared.triangle_indices = Some((ranges.clone(), Arc::clone(&indices)));
                indices
            }
        };
        self.show_choice(Some(gpu), Slot::Hybrid, choice)?;
        stats.update_ms = (started.elapsed().as_secs_f64() * 1e3 - stats.select_ms).max(0.0);
        report.hybrid = Some(stats);
        let draw = TriangleDraw { buffer: triangles, ranges, indices, cull_back };
        let scene = self.gpu_scene_mut(gpu, Slot::Hybrid, spec, report)?;
        scene.set_triangles(Some(draw), &whole);
        Ok(scene)
    }

    /// Every mesh triangle of the scene on the GPU, uploaded on first use
    /// (with the subset that chooses which are drawn).
    fn triangles(&mut self, gpu: &GpuRenderer) -> Result<Arc<wgpu::Buffer>, FrameError> {
        if self.hybrid.is_none() {
            let flat = self.scene.flatten();
            let surfaces = self.scene.surfaces(&flat);
            let cloud = self.cloud();
            self.hybrid = Some(Box::new(HybridSubsetState {
                subset: HybridSubset::new(surfaces, Arc::clone(cloud), self.hash),
                whole: WholeScene::of(cloud),
                one_sided: cloud.two_sided.iter().all(|&two| !two),
            }));
        }
        if let Some(buffer) = &self.prepared.triangles {
            return Ok(Arc::clone(buffer));
        }
        let surfaces = &self.hybrid.as_ref().expect("made above").subset.surfaces;
        let bytes = (surfaces.triangle_count() * 3 * std::mem::size_of::<TriangleVertex>()) as u64;
        let limit = gpu.ctx.device.limits().max_buffer_size;
        if bytes > limit {
            return Err(FrameError::Gpu(GpuError::TooLarge(format!(
                "the scene's {} mesh triangles need {:.1} MiB in one vertex buffer, more than the {:.1} MiB this GPU \
                 allows; use `ply =` (its vertex splats) or a smaller mesh",
                surfaces.triangle_count(),
                bytes as f64 / (1u64 << 20) as f64,
                limit as f64 / (1u64 << 20) as f64
            ))));
        }
        let device = &gpu.ctx.device;
        let whole = self.cloud();
        let buffer = gpu
            .ctx
            .allocating("uploading the mesh triangles", || TriangleDraw::upload(device, whole, surfaces.triangles()))?;
        let buffer = Arc::new(buffer);
        self.prepared.triangles = Some(Arc::clone(&buffer));
        Ok(buffer)
    }
}
