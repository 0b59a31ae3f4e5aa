//! The render plan: the passes and targets a frame needs, and nothing more.
//!
//! A mode's `plan` lists its passes, each with the targets it reads and
//! writes, and every target with its format, size, layers and the reason it
//! exists ([`TargetDesc`]). The target pool allocates exactly these
//! descriptions, `--explain` prints them and the viewer's plan panel shows
//! them, so the three cannot disagree.

use std::fmt;

use crate::view::RenderMode;

/// A target, named for what it holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TargetId(pub &'static str);

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

/// One pass of a frame, as `--explain` and the pass timer see it.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannedPass {
    /// Short name ("visibility", "group images"), also the timer's label.
    pub name: &'static str,
    /// What it does, in one line.
    pub what: String,
    pub reads: Vec<TargetId>,
    pub writes: Vec<TargetId>,
    /// Whether it draws the splats (a geometry pass) or the full screen.
    pub draws_splats: bool,
    /// wgpu render passes it takes (K for the group images).
    pub render_passes: usize,
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
    pub passes: Vec<PlannedPass>,
    pub targets: Vec<TargetDesc>,
    /// Remarks on the choices the plan made.
    pub notes: Vec<String>,
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
            passes: Vec::new(),
            targets: Vec::new(),
            notes: Vec::new(),
        }
    }

    /// Passes that draw the splats (the "2" of "2+1").
    pub fn geometry_passes(&self) -> usize {
        self.passes.iter().filter(|p| p.draws_splats).count()
    }

    /// wgpu render passes that draw splats (K for the group images).
    pub fn geometry_render_passes(&self) -> usize {
        self.passes.iter().filter(|p| p.draws_splats).map(|p| p.render_passes).sum()
    }

    /// Bytes of all targets.
    pub fn target_bytes(&self) -> u64 {
        self.targets.iter().map(TargetDesc::bytes).sum()
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
        if self.passes.is_empty() {
            return write!(
                f,
                "mode {}: {}, {} splats, {}x{}, ε = {:.4e}; no GPU passes, no targets",
                self.mode, self.variant, self.splats, self.width, self.height, self.epsilon
            );
        }
        let geometry = self.geometry_passes();
        writeln!(
            f,
            "mode {} ({}): {} geometry + {} full-screen passes, {} splats, {}x{}, ε = {:.4e}",
            self.mode,
            self.variant,
            geometry,
            self.passes.len() - geometry,
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
        for (i, pass) in self.passes.iter().enumerate() {
            writeln!(f, "  pass {}: {:<13} {}", i + 1, pass.name, pass.what)?;
            writeln!(f, "          reads {}; writes {}", names(&pass.reads), names(&pass.writes))?;
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
        write!(f, "  target memory: {:.1} MiB ({} bytes)", mib(self.target_bytes()), self.target_bytes())
    }
}
