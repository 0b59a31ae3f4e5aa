//! The render plan: the steps a frame runs, the targets they use, the
//! buffers its compute passes plan for, and the notes on the choices made;
//! final when made (what a frame measures while it runs goes in its
//! `FrameReport`, `crate::report`).
//!
//! A mode's plan is one list of [`Step`]s: each is a name, the reason in one
//! line, and the render passes it records ([`Command`]s). Everything else is
//! derived from those commands: the targets each step reads and writes (what
//! its passes bind, `touches::of`), whether it draws splats, how many render
//! passes it takes (the pass timer's slots), and which of the mode's target
//! descriptions ([`TargetDesc`]: format, size, layers, why) the pool
//! allocates: only those some pass binds. `--explain`, the viewer's plan
//! panel, the timer and the pool all read the one list, so none of them can
//! drift from what runs.

use std::fmt;

use super::passes::Command;
use super::touches::{self, Access};
use crate::frame::RenderMode;

pub use super::target_id::TargetId;

/// Whether a target is read as one image or as an array of layers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Layout {
    /// One image.
    Single,
    /// `layers` images (K group images), each a render target of its own.
    Array { layers: u32 },
}

/// A texture a frame allocates.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct TargetDesc {
    pub id: TargetId,
    pub format: wgpu::TextureFormat,
    pub width: u32,
    pub height: u32,
    pub layout: Layout,
    /// Why the frame needs it.
    pub why: &'static str,
    /// Whether a compute pass writes it as a storage texture.
    pub storage: bool,
}

impl TargetDesc {
    pub fn layers(&self) -> u32 {
        match self.layout {
            Layout::Single => 1,
            Layout::Array { layers } => layers,
        }
    }

    /// Bytes one pixel of one layer takes.
    pub fn bytes_per_pixel(&self) -> u32 {
        self.format
            .block_copy_size(None)
            .or_else(|| self.format.block_copy_size(Some(wgpu::TextureAspect::DepthOnly)))
            .unwrap_or(4)
    }

    /// Bytes of the whole texture.
    pub fn bytes(&self) -> u64 {
        self.bytes_per_pixel() as u64 * self.width as u64 * self.height as u64 * self.layers() as u64
    }
}

/// A GPU buffer a frame's compute passes use (the tile pipeline's), for
/// `--explain`'s memory account.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BufferDesc {
    pub name: &'static str,
    pub bytes: u64,
    /// What it holds and how its size follows from the frame.
    pub why: String,
}

/// One step of a frame: the render passes it records (K of them for the
/// group images), named and explained. `--explain` and the pass timer count
/// steps; what a step reads and writes is what its passes bind.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    /// Short name ("visibility", "group images"), also the timer's label.
    pub name: &'static str,
    /// What it does, in one line.
    pub what: String,
    /// Its render passes, in order.
    pub commands: Vec<Command>,
}

impl Step {
    pub fn new(name: &'static str, what: impl Into<String>, commands: Vec<Command>) -> Self {
        Step { name, what: what.into(), commands }
    }

    /// The targets its passes bind with `access`, each once, in binding order.
    fn bound(&self, access: Access) -> Vec<TargetId> {
        let mut out = Vec::new();
        for (id, _, a) in self.commands.iter().flat_map(touches::of) {
            if a == access && !out.contains(&id) {
                out.push(id);
            }
        }
        out
    }

    /// The targets it reads (textures, depth tests, blending under what is there).
    pub fn reads(&self) -> Vec<TargetId> {
        self.bound(Access::Read)
    }

    /// The targets it writes.
    pub fn writes(&self) -> Vec<TargetId> {
        self.bound(Access::Write)
    }

    /// Whether it draws the splats (a geometry step) rather than the full screen.
    pub fn draws_splats(&self) -> bool {
        self.commands.iter().any(|c| matches!(c, Command::Splats(_)))
    }

    /// Whether it runs compute passes (the tile pipeline).
    pub fn computes(&self) -> bool {
        self.commands.iter().any(|c| matches!(c, Command::Compute(_)))
    }

    /// Whether some pass of it draws its splats back to front.
    pub fn back_to_front(&self) -> bool {
        self.commands.iter().any(|c| matches!(c, Command::Splats(p) if p.back_to_front))
    }

    /// wgpu render passes it takes.
    pub fn render_passes(&self) -> usize {
        self.commands.len()
    }
}

/// The passes and targets of one frame.
#[derive(Debug, Clone)]
pub struct RenderPlan {
    pub mode: RenderMode,
    /// The variant in words ("filtered, lit", ...).
    pub variant: String,
    pub width: u32,
    pub height: u32,
    pub splats: usize,
    /// ε in view-depth units.
    pub epsilon: f32,
    /// Groups K (1 unless the mode draws groups).
    pub groups: usize,
    pub steps: Vec<Step>,
    /// The targets the steps bind: what the pool allocates.
    pub targets: Vec<TargetDesc>,
    /// The buffers its compute passes use (besides the scene's splats).
    pub buffers: Vec<BufferDesc>,
    /// Remarks on the choices the plan made.
    pub notes: Vec<String>,
    /// The frame is clipped: its splat passes and tile raster are built
    /// with `CLIP` and test every fragment's point (crates/core/src/frame/clip.rs).
    pub clipped: bool,
    /// The target left holding the nearest surface per pixel, if the plan
    /// keeps one (what the cursor's coordinates are read from).
    pub front_depth: Option<FrontDepthTarget>,
}

/// A depth target holding the frame's nearest surface per pixel: view
/// depth mapped to 0..1 over near..far, pushed back by `push` view units
/// ([`pointblend_core::frame::FrontDepth::from_buffer`] undoes both).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrontDepthTarget {
    pub target: TargetId,
    pub push: f32,
}

impl RenderPlan {
    /// The plan of a mode that runs no GPU pass (the CPU reference).
    pub fn cpu(mode: RenderMode, width: u32, height: u32, splats: usize, epsilon: f32) -> Self {
        RenderPlan {
            mode,
            variant: "exact A-buffer ray casting on the CPU".into(),
            width,
            height,
            splats,
            epsilon,
            groups: 1,
            steps: Vec::new(),
            targets: Vec::new(),
            buffers: Vec::new(),
            notes: Vec::new(),
            clipped: false,
            front_depth: None,
        }
    }

    /// A plan of `steps`, keeping of `targets` those some step binds.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        mode: RenderMode,
        variant: String,
        (width, height): (u32, u32),
        splats: usize,
        epsilon: f32,
        groups: usize,
        steps: Vec<Step>,
        targets: Vec<TargetDesc>,
    ) -> Self {
        let bound: Vec<TargetId> =
            steps.iter().flat_map(|s| &s.commands).flat_map(touches::of).map(|(id, _, _)| id).collect();
        let targets = targets.into_iter().filter(|t| bound.contains(&t.id)).collect();
        RenderPlan {
            mode,
            variant,
            width,
            height,
            splats,
            epsilon,
            groups,
            steps,
            targets,
            buffers: Vec::new(),
            notes: Vec::new(),
            clipped: false,
            front_depth: None,
        }
    }

    /// The render passes in order, each with the index of its step.
    pub fn commands(&self) -> impl Iterator<Item = (usize, &Command)> {
        self.steps.iter().enumerate().flat_map(|(i, s)| s.commands.iter().map(move |c| (i, c)))
    }

    /// Steps that draw the splats (the "2" of "2+1").
    pub fn geometry_passes(&self) -> usize {
        self.steps.iter().filter(|p| p.draws_splats()).count()
    }

    /// wgpu render passes that draw splats (K for the group images).
    pub fn geometry_render_passes(&self) -> usize {
        self.steps.iter().filter(|p| p.draws_splats()).map(Step::render_passes).sum()
    }

    /// Whether some pass draws its splats back to front (the renderer sorts
    /// the scene's instances for the view first).
    pub fn back_to_front(&self) -> bool {
        self.steps.iter().any(Step::back_to_front)
    }

    /// Bytes of all targets.
    pub fn target_bytes(&self) -> u64 {
        self.targets.iter().map(TargetDesc::bytes).sum()
    }

    /// Bytes of the compute passes' buffers.
    pub fn buffer_bytes(&self) -> u64 {
        self.buffers.iter().map(|b| b.bytes).sum()
    }

    /// Steps that run compute passes.
    pub fn compute_passes(&self) -> usize {
        self.steps.iter().filter(|s| s.computes()).count()
    }

    pub fn target(&self, id: TargetId) -> Option<&TargetDesc> {
        self.targets.iter().find(|t| t.id == id)
    }

    /// Checks that this device can hold the plan's targets: array layers
    /// within its limit, bytes within `budget` (see `GpuContext::target_budget`).
    pub fn check_fits(&self, limits: &wgpu::Limits, budget: u64) -> Result<(), super::GpuError> {
        let hint = "use a grouping with a fixed, small K (--group hash-k8 or wgc-k8)";
        let layers = self.targets.iter().map(TargetDesc::layers).max().unwrap_or(1);
        if layers > limits.max_texture_array_layers {
            return Err(super::GpuError::TooLarge(format!(
                "{} needs {layers} group layers, more than the {} texture layers this GPU allows; {hint}",
                self.mode, limits.max_texture_array_layers
            )));
        }
        let bytes = self.target_bytes();
        if bytes > budget {
            return Err(super::GpuError::TooLarge(format!(
                "{} with K = {} at {}x{} needs {} of render targets, more than the {} this GPU can give (POINTBLEND_GPU_MEMORY_MB sets it); {hint} or a smaller --size",
                self.mode,
                self.groups,
                self.width,
                self.height,
                crate::memory::gib(bytes),
                crate::memory::gib(budget)
            )));
        }
        Ok(())
    }
}

fn mib(bytes: u64) -> f64 {
    bytes as f64 / (1u64 << 20) as f64
}

fn names(ids: &[TargetId]) -> String {
    if ids.is_empty() { "-".into() } else { ids.iter().map(|t| t.0).collect::<Vec<_>>().join(", ") }
}

impl fmt::Display for RenderPlan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.steps.is_empty() {
            return write!(
                f,
                "mode {}: {}, {} splats, {}x{}, ε = {:.4e}; no GPU passes, no targets",
                self.mode, self.variant, self.splats, self.width, self.height, self.epsilon
            );
        }
        let geometry = self.geometry_passes();
        let compute = self.compute_passes();
        let computing = if compute > 0 { format!(" + {compute} compute") } else { String::new() };
        writeln!(
            f,
            "mode {} ({}): {} geometry + {} full-screen{computing} passes, {} splats, {}x{}, ε = {:.4e}",
            self.mode,
            self.variant,
            geometry,
            self.steps.len() - geometry - compute,
            self.splats,
            self.width,
            self.height,
            self.epsilon
        )?;
        writeln!(
            f,
            "  {} groups; each splat is drawn {} time(s) per frame in {} render pass(es)",
            self.groups,
            geometry,
            self.geometry_render_passes()
        )?;
        for note in &self.notes {
            writeln!(f, "  note: {note}")?;
        }
        for (i, step) in self.steps.iter().enumerate() {
            writeln!(f, "  pass {}: {:<13} {}", i + 1, step.name, step.what)?;
            writeln!(f, "          reads {}; writes {}", names(&step.reads()), names(&step.writes()))?;
        }
        for t in &self.targets {
            writeln!(
                f,
                "  target: {:<26} {:<13} x{:<3} {:>7.1} MiB ({} bytes)  ({})",
                t.id.0,
                format!("{:?}", t.format),
                t.layers(),
                mib(t.bytes()),
                t.bytes(),
                t.why
            )?;
        }
        for b in &self.buffers {
            writeln!(f, "  buffer: {:<26} {:>7.1} MiB ({} bytes)  ({})", b.name, mib(b.bytes), b.bytes, b.why)?;
        }
        write!(f, "  target memory: {:.1} MiB ({} bytes)", mib(self.target_bytes()), self.target_bytes())?;
        if !self.buffers.is_empty() {
            let total = self.target_bytes() + self.buffer_bytes();
            write!(
                f,
                "\n  buffer memory: {:.1} MiB; GPU memory of the frame: {:.1} MiB ({} bytes), besides the scene's splats",
                mib(self.buffer_bytes()),
                mib(total),
                total
            )?;
        }
        Ok(())
    }
}
