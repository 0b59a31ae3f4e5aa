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

use std::ops::Range;
use std::sync::Arc;
use std::time::Instant;

use super::subset::SubsetScene;
use super::{FrameError, PreparedScene};
use crate::context::GpuError;
use crate::frame::subset::{Choosing, Subset};
use crate::frame::{Camera, FrameSpec};
use crate::gpu_data::TriangleVertex;
use crate::gpu_renderer::GpuRenderer;
use crate::gpu_scene::{GpuScene, TriangleDraw, WholeScene};
use crate::report::{FrameReport, HybridStats};
use pointblend_core::hybrid::subset::HybridSubset;

/// The scene's triangles and the frames of the splats drawn beside them.
pub(super) struct HybridFrames {
    subset: HybridSubset,
    buffer: Option<Arc<wgpu::Buffer>>,
    /// The drawn triangles' indices on the GPU, and the ranges they hold.
    indices: Option<(Arc<wgpu::Buffer>, Vec<Range<u32>>)>,
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
        let settings = &spec.drawn;
        if self.hybrid.is_none() {
            let flat = self.scene.flatten();
            let surfaces = self.scene.surfaces(&flat);
            self.hybrid = Some(Box::new(HybridFrames {
                subset: HybridSubset::new(surfaces, Arc::clone(&self.cloud), self.hash),
                buffer: None,
                indices: None,
                chosen: SubsetScene::of(self, "hybrid"),
                whole: WholeScene::of(&self.cloud),
                one_sided: self.cloud.two_sided.iter().all(|&two| !two),
            }));
        }
        let whole = Arc::clone(&self.cloud);
        let state = self.hybrid.as_mut().expect("made above");
        if state.buffer.is_none() {
            let bytes = (state.subset.surfaces.triangle_count() * 3 * std::mem::size_of::<TriangleVertex>()) as u64;
            let limit = gpu.ctx.device.limits().max_buffer_size;
            if bytes > limit {
                return Err(FrameError::Gpu(GpuError::TooLarge(format!(
                    "the scene's {} mesh triangles need {:.1} MiB in one vertex buffer, more than the {:.1} MiB this GPU \
                     allows; use `ply =` (its vertex splats) or a smaller mesh",
                    state.subset.surfaces.triangle_count(),
                    bytes as f64 / (1u64 << 20) as f64,
                    limit as f64 / (1u64 << 20) as f64
                ))));
            }
            let device = &gpu.ctx.device;
            let buffer = gpu.ctx.allocating("uploading the mesh triangles", || {
                TriangleDraw::upload(device, &whole, state.subset.surfaces.triangles())
            })?;
            state.buffer = Some(Arc::new(buffer));
        }
        let started = Instant::now();
        state.subset.pixels = settings.hybrid_pixels;
        let Ok(choice) = state.subset.choose(camera, spec.size, Choosing::of(settings));
        let changed = choice.cloud.is_some();
        let selection = state.subset.selection().expect("chosen above");
        if state.indices.as_ref().is_none_or(|(_, ranges)| *ranges != selection.triangles) {
            let buffer = TriangleDraw::upload_indices(&gpu.ctx.device, &selection.triangles);
            state.indices = Some((Arc::new(buffer), selection.triangles.clone()));
        }
        let frames = state.chosen.next(Some(gpu), choice)?;
        let selection = state.subset.selection().expect("chosen above");
        let draw = TriangleDraw {
            buffer: Arc::clone(state.buffer.as_ref().expect("uploaded above")),
            ranges: selection.triangles.clone(),
            indices: Arc::clone(&state.indices.as_ref().expect("uploaded above").0),
            cull_back: settings.backface_culling && state.one_sided,
        };
        report.hybrid = Some(HybridStats {
            pixels: settings.hybrid_pixels,
            triangles: selection.triangle_count(),
            splats: selection.splats.len(),
            triangle_leaves: selection.triangle_leaves,
            splat_leaves: selection.splat_leaves,
            transition_splats: selection.transition_splats,
            select_ms: state.subset.select_ms,
            update_ms: (started.elapsed().as_secs_f64() * 1e3 - state.subset.select_ms).max(0.0),
            changed,
        });
        let scene = frames.gpu_scene_mut(gpu, spec, report)?;
        scene.set_triangles(Some(draw), &state.whole);
        Ok(scene)
    }
}
