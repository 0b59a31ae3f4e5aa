//! The one way a frame is made: [`SceneFrames::render_frame`], which
//! `pointblend render`, `bench` and the viewer's render thread all call. It
//! chooses what the frame draws once (the hybrid leaves, the nodes under a
//! point budget, or the whole scene: [`Chosen`]), prepares it (upload,
//! grouping, shadows, back-to-front order), runs the mode's plan, and adds
//! what the preparation chose to the plan's notes. The exact reference is
//! ray cast on the CPU instead.

use super::{BudgetStats, FrameError, SceneFrames};
use crate::frame::{Camera, RenderSettings};
use crate::gpu_scene::GpuScene;
use crate::headless::HeadlessRenderer;
use crate::plan::RenderPlan;
use pointblend_core::reference::{self, ReferenceOptions};

/// Whether a frame's image is read back from the GPU.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Readback {
    Image,
    /// The image, with a progress bar while the (CPU) reference renders.
    ImageWithProgress,
    /// Nothing: the frame is only drawn (bench's timed frames), and its plan
    /// carries the mode's notes only, not those of what was prepared.
    Nothing,
}

/// What a GPU frame draws, chosen once per frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Chosen {
    /// A hybrid object's leaves as triangles, and the splats beside them.
    Hybrid,
    /// The octree's nodes under a point budget.
    Budget,
    /// Every splat of the scene.
    Whole,
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
    /// call it. A GPU mode on `gpu`: what it draws is chosen once
    /// ([`Chosen`]) and prepared (the hybrid, budgeted or whole scene's
    /// upload, its grouping and shadows), its plan runs, and the notes of what was
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
        let chosen = self.choose(settings);
        let (scene, drawn) = self.prepare(chosen, gpu, camera, settings, (width, height))?;
        if readback == Readback::Nothing {
            let plan = gpu.render(scene, camera, &drawn, width, height)?;
            return Ok(Frame { image: image::RgbaImage::new(0, 0), plan });
        }
        let (image, mut plan) = gpu.render_image(scene, camera, &drawn, width, height)?;
        plan.notes.extend(self.frame_notes(chosen, settings, &drawn));
        Ok(Frame { image, plan })
    }

    /// What a GPU frame of `settings` draws.
    fn choose(&self, settings: &RenderSettings) -> Chosen {
        if self.draws_triangles(settings) {
            Chosen::Hybrid
        } else if self.applied_budget(settings).is_some() {
            Chosen::Budget
        } else {
            Chosen::Whole
        }
    }

    /// The GPU copy that draws `chosen` from `camera` at `size` (the splats
    /// selected here are part of the frame), and the settings to draw it
    /// with: a chosen selection is drawn whole, with no budget left to apply.
    fn prepare(
        &mut self,
        chosen: Chosen,
        gpu: &HeadlessRenderer,
        camera: &Camera,
        settings: &RenderSettings,
        size: (u32, u32),
    ) -> Result<(&mut GpuScene, RenderSettings), FrameError> {
        match (chosen, settings.point_budget) {
            (Chosen::Hybrid, _) => Ok((self.hybrid_scene(gpu, camera, settings, size)?, settings.without_budget())),
            (Chosen::Budget, Some(budget)) => self.budgeted_scene(gpu, camera, settings, size, budget),
            _ => Ok((self.gpu_scene_mut(gpu, settings)?, *settings)),
        }
    }

    /// What the frame of `settings` that drew `chosen` prepared, in words,
    /// for its plan's notes: the hybrid or budget selection, the shadows
    /// (`drawn`'s), the meshes drawn as splats.
    fn frame_notes(&self, chosen: Chosen, settings: &RenderSettings, drawn: &RenderSettings) -> Vec<String> {
        let mut notes: Vec<String> = match chosen {
            Chosen::Hybrid => self.hybrid_note(settings).into_iter().chain(self.shadow_notes(drawn)).collect(),
            Chosen::Budget => {
                let shadows = self.budget_frames_shown().map(|f| f.shadow_notes(drawn)).unwrap_or_default();
                shadows.into_iter().chain(self.last_budget().map(BudgetStats::describe)).collect()
            }
            Chosen::Whole => self.shadow_notes(drawn),
        };
        if chosen != Chosen::Hybrid {
            notes.extend(self.mesh_notes(settings));
        }
        notes
    }
}
