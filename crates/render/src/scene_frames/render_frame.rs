//! The one way a frame is made: [`SceneFrames::render_frame`], which
//! `pointblend render`, `bench` and the viewer's render thread all call. It
//! chooses what the frame draws once (the hybrid leaves, the nodes under a
//! point budget, or the whole scene: `frame_scene`), prepares it (upload,
//! grouping, shadows, back-to-front order), runs the mode's plan, and adds
//! what the preparation chose to the plan's notes. The exact reference is
//! ray cast on the CPU instead.

use super::{BudgetStats, FrameError, SceneFrames};
use crate::frame::{Camera, RenderSettings};
use crate::headless::HeadlessRenderer;
use crate::plan::RenderPlan;
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

/// A rendered frame and the plan that made it (a CPU plan for the reference).
/// The image is empty (0×0) for a frame drawn with [`Readback::Nothing`].
pub struct Frame {
    pub image: image::RgbaImage,
    pub plan: RenderPlan,
}

impl SceneFrames {
    /// One frame of `settings.mode` from `camera` at `size`, read back as
    /// an image ([`Self::render_frame`]; a progress bar for the reference when `progress`).
    pub fn render(
        &mut self,
        gpu: Option<&mut HeadlessRenderer>,
        camera: &Camera,
        settings: &RenderSettings,
        size: (u32, u32),
        progress: bool,
    ) -> Result<Frame, FrameError> {
        let readback = if progress { Readback::ImageWithProgress } else { Readback::Image };
        self.render_frame(gpu, camera, settings, size, readback)
    }

    /// The one way a frame is made; `render`, `bench` and the viewer all
    /// call it. A GPU mode on `gpu`: the splats it draws are prepared
    /// ([`Self::frame_scene`]: the hybrid, budgeted or whole scene's upload,
    /// its grouping and shadows), its plan runs, and the notes of what was
    /// prepared join the plan's. The exact reference renders on the CPU.
    /// `readback` says whether the image is read back (bench's timed frames
    /// are not: their image is empty).
    pub fn render_frame(
        &mut self,
        gpu: Option<&mut HeadlessRenderer>,
        camera: &Camera,
        settings: &RenderSettings,
        (width, height): (u32, u32),
        readback: Readback,
    ) -> Result<Frame, FrameError> {
        // A frame with no splats (an empty frame of a sequence) is the background,
        // which the reference draws at no cost; GPU passes need splats to bind.
        if !settings.mode.is_gpu() || self.cloud.is_empty() {
            let progress = readback == Readback::ImageWithProgress;
            let options = ReferenceOptions { progress, ..ReferenceOptions::matching(settings, &self.scene) };
            let image = reference::render(&self.scene, camera, &options, width, height);
            let plan = RenderPlan::cpu(settings.mode, width, height, self.scene.len(), options.epsilon);
            return Ok(Frame { image, plan });
        }
        let gpu = gpu.ok_or(FrameError::NoGpu(settings.mode.name()))?;
        let (scene, drawn) = self.frame_scene(gpu, camera, settings, (width, height))?;
        let (image, mut plan) = match readback {
            Readback::Nothing => (image::RgbaImage::new(0, 0), gpu.render(scene, camera, &drawn, width, height)?),
            Readback::Image | Readback::ImageWithProgress => gpu.render_image(scene, camera, &drawn, width, height)?,
        };
        plan.notes.extend(self.frame_notes(settings, &drawn));
        Ok(Frame { image, plan })
    }

    /// What the last frame of `settings` prepared, in words, for its plan's
    /// notes: the hybrid or budget selection, the shadows, the meshes drawn as splats.
    fn frame_notes(&self, settings: &RenderSettings, drawn: &RenderSettings) -> Vec<String> {
        let mut notes = Vec::new();
        if self.draws_triangles(settings) {
            notes.extend(self.hybrid_note(settings));
            notes.extend(self.shadow_notes(drawn));
        } else if self.applied_budget(settings).is_some() {
            notes.extend(self.budget_frames_shown().map(|frames| frames.shadow_notes(drawn)).unwrap_or_default());
            notes.extend(self.last_budget().map(BudgetStats::describe));
            notes.extend(self.mesh_notes(settings));
        } else {
            notes.extend(self.shadow_notes(settings));
            notes.extend(self.mesh_notes(settings));
        }
        notes
    }
}
