//! Frames of a scene with meshes (`mesh` and `hybrid` objects) in a mode
//! that draws triangles: every triangle of the scene is uploaded once (three
//! unshared vertices each, in world space, materials applied), and each
//! frame chooses which leaves are drawn as triangles and which splats are
//! drawn ([`pointblend_core::hybrid::select`], Guennebaud's hybrid rules; part of
//! the frame's time). When the splats chosen change, they are gathered into
//! one cloud and handed to a [`SceneFrames`] of their own as a moving
//! scene's next frame (as under a point budget: the grouped modes get the
//! hash grouping of the splats drawn), and the mode's passes draw the
//! triangles' ranges beside them.
//!
//! A mode that cannot draw triangles draws the scene's every splat (the
//! mesh's vertices among them) and says so, once in the log and in the
//! plan's notes; so does a frame lit by scene lights (translucent shadows
//! are cast and received by splats) and a moving scene; those frames
//! draw every splat as splat frames do, under a point budget if one is set.
//! A frame that draws triangles draws every splat it chooses: a point
//! budget does not apply to it, and its plan's notes say so.

use std::sync::Arc;
use std::time::Instant;

use super::chosen::ChosenFrames;
use super::{FrameError, SceneFrames};
use crate::context::GpuError;
use crate::frame::{Camera, RenderMode, RenderSettings};
use crate::gpu_data::TriangleVertex;
use crate::gpu_scene::{GpuScene, TriangleDraw, WholeScene};
use crate::headless::HeadlessRenderer;
use pointblend_core::hybrid::select::{HybridOptions, HybridSelection, SceneSurfaces};

/// What the last frame with triangles drew and cost.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct HybridStats {
    pub triangles: u32,
    pub splats: usize,
    pub triangle_leaves: usize,
    pub splat_leaves: usize,
    pub transition_splats: usize,
    /// Choosing the leaves, in milliseconds.
    pub select_ms: f64,
    /// Gathering the splats and rewriting their GPU copy (when they changed), in milliseconds.
    pub update_ms: f64,
    pub changed: bool,
}

impl HybridStats {
    /// One line for the plan's notes and `--explain`.
    pub fn describe(&self, pixels: f32) -> String {
        format!(
            "meshes: {} triangles of {} leaves and {} splats ({} leaves as splats, {} transition splats) drawn; \
             leaves as triangles where splats exceed {pixels} px; selection {:.2} ms, update {:.1} ms{}",
            self.triangles,
            self.triangle_leaves,
            self.splats,
            self.splat_leaves,
            self.transition_splats,
            self.select_ms,
            self.update_ms,
            if self.changed { "" } else { " (unchanged)" },
        )
    }
}

/// The scene's triangles and the frames of the splats drawn beside them.
pub(super) struct HybridFrames {
    surfaces: SceneSurfaces,
    buffer: Option<Arc<wgpu::Buffer>>,
    selected: Option<HybridSelection>,
    /// The drawn triangles' indices on the GPU, for the last selection's triangles.
    indices: Option<Arc<wgpu::Buffer>>,
    chosen: ChosenFrames,
    /// What a frame with triangles takes from the whole scene, as a frame of every splat would.
    whole: WholeScene,
    /// Every splat is one-sided: triangles facing away can be culled by their winding.
    one_sided: bool,
    last: HybridStats,
}

impl SceneFrames {
    /// Why a GPU frame of `settings` draws the scene's meshes as their
    /// vertex splats, if it does: a mode without triangles, scene lights
    /// (translucent shadows are cast and received by splats, Gunjee §4), or a moving scene.
    fn triangles_refused(&self, settings: &RenderSettings) -> Option<String> {
        if !self.scene.has_surfaces() || !settings.mode.is_gpu() {
            return None;
        }
        // A transparent mode given an opaque scene runs the two-pass plan, which draws triangles.
        let runs_two_pass = settings.mode.runs_opaque(self.scene.has_transparency());
        let why = if !settings.mode.info().triangles && !runs_two_pass {
            let drawing: Vec<&str> =
                RenderMode::ALL.into_iter().filter(|m| m.info().triangles).map(RenderMode::name).collect();
            format!("{} cannot draw triangles ({} do)", settings.mode.name(), drawing.join(", "))
        } else if settings.lit_by_lights() {
            "the frame is lit by scene lights, whose shadows are cast and received by splats".to_string()
        } else if self.is_moving() {
            "the scene moves (triangles are drawn in still scenes)".to_string()
        } else {
            return None;
        };
        Some(format!("{why}: the scene's mesh and hybrid objects are drawn as their vertex splats"))
    }

    /// Whether a frame of `settings` draws the scene's triangles (else says once why not).
    pub fn draws_triangles(&self, settings: &RenderSettings) -> bool {
        match self.triangles_refused(settings) {
            Some(why) => {
                pointblend_core::progress::warn_once(why);
                false
            }
            None => self.scene.has_surfaces() && settings.mode.is_gpu(),
        }
    }

    /// The notes a frame of `settings` adds when it draws the scene's meshes as splats.
    pub fn mesh_notes(&self, settings: &RenderSettings) -> Vec<String> {
        self.triangles_refused(settings).into_iter().collect()
    }

    /// What the last frame with triangles drew and cost.
    pub fn last_hybrid(&self) -> Option<&HybridStats> {
        self.hybrid.as_ref().map(|h| &h.last)
    }

    /// The line on what the last frame with triangles drew, for the plan's
    /// notes (with the point budget it did not apply, if `settings` has one).
    pub fn hybrid_note(&self, settings: &RenderSettings) -> Option<String> {
        let mut note = self.last_hybrid()?.describe(settings.hybrid_pixels);
        if let Some(budget) = settings.point_budget {
            note +=
                &format!("; point budget {budget} not applied (a frame with triangles draws every splat it chooses)");
        }
        Some(note)
    }

    /// The GPU copy a frame with triangles from `camera` at `size` draws
    /// (its leaves chosen here). Such a frame draws every splat it chooses:
    /// a point budget in `settings` is not applied ([`Self::hybrid_note`]
    /// says so); draw it with [`RenderSettings::without_budget`].
    pub(super) fn hybrid_scene(
        &mut self,
        gpu: &HeadlessRenderer,
        camera: &Camera,
        settings: &RenderSettings,
        size: (u32, u32),
    ) -> Result<&mut GpuScene, FrameError> {
        if self.hybrid.is_none() {
            let flat = self.scene.flatten();
            let surfaces = self.scene.surfaces(&flat);
            let reason = "in a hybrid frame the splats drawn change with the view";
            self.hybrid = Some(Box::new(HybridFrames {
                surfaces,
                buffer: None,
                selected: None,
                indices: None,
                chosen: ChosenFrames::of(self, "hybrid", reason),
                whole: WholeScene::of(&self.cloud),
                one_sided: self.cloud.two_sided.iter().all(|&two| !two),
                last: HybridStats::default(),
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
        state.last = HybridStats {
            triangles: selection.triangle_count(),
            splats: selection.splats.len(),
            triangle_leaves: selection.triangle_leaves,
            splat_leaves: selection.splat_leaves,
            transition_splats: selection.transition_splats,
            select_ms,
            update_ms: started.elapsed().as_secs_f64() * 1e3,
            changed,
        };
        let scene = frames.gpu_scene_mut(gpu, &settings.without_budget())?;
        scene.set_triangles(Some(draw), &state.whole);
        state.selected = Some(selection);
        Ok(scene)
    }
}
