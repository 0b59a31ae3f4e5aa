//! The one way a frame is made: [`PreparedScene::render_frame`], which
//! `pointblend render`, `bench` and the viewer's render thread all call with
//! a frame decided by [`crate::frame::resolve`] ([`PreparedScene::resolve`]
//! gives it what the scene is). It prepares what the spec selects (the
//! hybrid leaves, the nodes under a point budget, or the whole scene: its
//! upload, grouping, shadows, back-to-front order), runs the mode's plan, and
//! returns what the preparation measured in the frame's report. The exact
//! reference is ray cast on the CPU instead.

use super::{FrameError, PreparedScene};
use crate::frame::spec::Selection;
use crate::frame::{Camera, FrameSpec, RenderSettings, SceneFacts, View};
use crate::gpu_renderer::GpuRenderer;
use crate::plan::RenderPlan;
use crate::report::{FrameReport, PoolStats};
use crate::scene_cache::Slot;
use pointblend_core::reference::{self, ReferenceOptions};

/// Whether a frame's image is read back from the GPU.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Readback {
    Image,
    /// The image, with a progress bar while the (CPU) reference renders.
    ImageWithProgress,
    /// Nothing: the frame is only drawn (bench's timed frames).
    Nothing,
}

/// A rendered frame, the plan that made it (a CPU plan for the reference)
/// and what it measured. The image is empty (0×0) for a frame drawn with [`Readback::Nothing`].
pub struct Frame {
    pub image: image::RgbaImage,
    pub plan: RenderPlan,
    pub report: FrameReport,
}

impl PreparedScene {
    /// What a frame of this scene is decided over.
    pub fn facts(&self) -> SceneFacts {
        SceneFacts {
            splats: self.cloud().len(),
            transparent: self.whole().transparent,
            surfaces: self.scene.has_surfaces(),
            moving: self.is_moving(),
            streamed: self.streamed,
            mean_radius: self.mean_radius,
            shadows_at_hand: true,
        }
    }

    /// The frame of `settings` in `view`, decided over this scene.
    pub fn resolve(&self, settings: &RenderSettings, view: View) -> FrameSpec {
        crate::frame::resolve(settings, &self.facts(), &view)
    }

    /// One still frame of `settings` from `camera` at `size`, read back as
    /// an image (resolved, then [`Self::render_frame`]; a progress bar for the reference when `progress`).
    pub fn render(
        &mut self,
        gpu: Option<&mut GpuRenderer>,
        camera: &Camera,
        settings: &RenderSettings,
        size: (u32, u32),
        progress: bool,
    ) -> Result<Frame, FrameError> {
        let readback = if progress { Readback::ImageWithProgress } else { Readback::Image };
        let spec = self.resolve(settings, View::still(size));
        self.render_frame(gpu, camera, &spec, readback)
    }

    /// The one way a frame is made; `render`, `bench` and the viewer all
    /// call it. A GPU frame on `gpu`: what `spec` selects is prepared (the
    /// hybrid, budgeted or whole scene's upload, its grouping and shadows),
    /// its plan runs, and the report says what the preparation measured. The
    /// exact reference renders on the CPU. `readback` says whether the image
    /// is read back (bench's timed frames are not: their image is empty).
    pub fn render_frame(
        &mut self,
        gpu: Option<&mut GpuRenderer>,
        camera: &Camera,
        spec: &FrameSpec,
        readback: Readback,
    ) -> Result<Frame, FrameError> {
        for note in spec.notes.iter().filter(|n| n.is_warning()) {
            pointblend_core::progress::warn_once(note.to_string());
        }
        let (width, height) = spec.size;
        // A frame with no splats (an empty frame of a sequence) is the background,
        // which the reference draws at no cost; GPU passes need splats to bind.
        if spec.on_cpu {
            let progress = readback == Readback::ImageWithProgress;
            let options = ReferenceOptions { progress, ..ReferenceOptions::matching(&spec.drawn, &self.scene) };
            let image = reference::render(&self.scene, camera, &options, width, height);
            let plan = RenderPlan::cpu(spec.mode(), width, height, self.scene.len(), options.epsilon);
            return Ok(Frame { image, plan, report: FrameReport::default() });
        }
        let gpu = gpu.ok_or(FrameError::NoGpu(spec.mode().name()))?;
        let mut report = FrameReport::default();
        // What the spec selects, prepared (the splats selected here are part of the frame).
        let scene = match spec.selection {
            Selection::Hybrid(_) => self.hybrid_scene(gpu, camera, spec, &mut report)?,
            Selection::Budget(budget) => self.budgeted_scene(gpu, camera, spec, budget, &mut report)?,
            Selection::Whole | Selection::Streamed => self.gpu_scene_mut(gpu, Slot::Whole, spec, &mut report)?,
        };
        report.pool = scene.pooled_nodes().map(|(drawn, kept)| PoolStats {
            slots: scene.slot_count(),
            bytes: scene.splat_bytes(),
            drawn,
            kept,
        });
        let (image, plan, drawn) = gpu.render_spec(scene, camera, spec, readback != Readback::Nothing)?;
        report = FrameReport {
            tile_lists: drawn.tile_lists,
            window_overflows: drawn.window_overflows,
            subframes: drawn.subframes,
            ..report
        };
        Ok(Frame { image, plan, report })
    }
}
