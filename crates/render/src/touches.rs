//! What a pass touches, said twice on purpose: [`of`] says which targets a
//! planned pass reads and writes (the plan and `--explain` list these), and
//! [`Bound`] records each texture view a recorded pass was actually given,
//! where its bind group or attachment is made. A test holds the one against
//! the other, naming views by identity in the pool, without trusting either.

use super::passes::{Blend, Command, Output};
use super::target_id::TargetId;

/// How a pass used a target.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Access {
    Read,
    Write,
    /// Bound but neither read nor written: a depth attachment a pass needs
    /// only because its shader writes depth (approx-peel's rest). It must be
    /// allocated, and is in no step's reads or writes.
    Attached,
}

/// Where a recorded pass was given a texture.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Slot {
    /// Group 1, binding N: a texture it samples.
    Input(u32),
    /// Colour attachment N (a full-screen pass's target is attachment 0).
    Colour(u32),
    Depth,
    /// Group 1, binding N of a compute pass: a storage texture it writes.
    Storage(u32),
}

/// A texture view one render or compute pass was given, recorded where the
/// bind group or attachment is made from it: what the GPU actually got,
/// which [`crate::targets::TargetPool::target_of`] names by identity.
#[derive(Debug, Clone)]
pub struct Bound {
    /// The plan pass the render or compute pass belongs to.
    pub pass: usize,
    pub slot: Slot,
    pub view: wgpu::TextureView,
    /// Whether the pass reads what the texture holds (sampled, depth-tested
    /// against, or blended onto as loaded), and whether it writes it, as
    /// the pipeline and the attachment's load operation were set up.
    pub reads: bool,
    pub writes: bool,
}

/// The targets `command` reads and writes: (id, layer, access).
pub fn of(command: &Command) -> Vec<(TargetId, Option<u32>, Access)> {
    let mut out = Vec::new();
    match command {
        Command::Splats(pass) => {
            out.extend(pass.inputs.iter().map(|&id| (id, None, Access::Read)));
            // Colour attachments are cleared first: written only.
            out.extend(pass.colour.iter().map(|c| (c.target, Some(pass.layer), Access::Write)));
            // A depth attachment is read when fragments test against what it
            // held, written when they write it, and only attached when it does
            // neither (a pass whose shader writes depth nobody tests).
            if let Some((id, test)) = pass.depth {
                let read = !test.clear && test.compare != wgpu::CompareFunction::Always;
                if read {
                    out.push((id, Some(pass.layer), Access::Read));
                }
                if test.write {
                    out.push((id, Some(pass.layer), Access::Write));
                }
                if !read && !test.write {
                    out.push((id, Some(pass.layer), Access::Attached));
                }
            }
        }
        Command::Compute(pass) => {
            out.extend(pass.outputs.iter().map(|&id| (id, Some(0), Access::Write)));
        }
        Command::Fullscreen(pass) => {
            out.extend(pass.inputs.iter().map(|&id| (id, None, Access::Read)));
            if let Output::Target(id) = pass.output {
                if !pass.clear && pass.blend != Blend::Replace {
                    out.push((id, Some(0), Access::Read));
                }
                out.push((id, Some(0), Access::Write));
            }
        }
    }
    out
}
