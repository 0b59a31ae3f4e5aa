//! A full-screen pass records itself: its output (the frame or a target),
//! its inputs, its pipeline key, the scene's environment map when its
//! variant reflects one, and the draw (`passes::fullscreen::record`).

use super::{At, Recording, missing};
use crate::context::GpuError;
use crate::passes::fullscreen::record;
use crate::passes::{Blend, FullscreenPass, Output, PipelineKey, PipelineKind};
use crate::shaders::Variant;
use crate::touches::Slot;

/// Records `pass` into `encoder`; `frame` is the view (and format) that [`Output::Frame`] means.
pub fn encode(
    rec: &mut Recording<'_>,
    encoder: &mut wgpu::CommandEncoder,
    pass: &FullscreenPass,
    at: At,
    frame: (&wgpu::TextureView, wgpu::TextureFormat),
    stamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
) -> Result<(), GpuError> {
    let (output, format) = match pass.output {
        Output::Frame => frame,
        Output::Target(id) => {
            let view = rec.view(id)?;
            // Blending onto a loaded target reads it.
            let reads = !pass.clear && pass.blend != Blend::Replace;
            rec.given(at.step, Slot::Colour(0), view, reads, true);
            (view, rec.target(id)?.format)
        }
    };
    let (dims, inputs) = rec
        .inputs(at.step, &pass.inputs)?
        .ok_or_else(|| GpuError::Device(format!("{} reads no target", pass.label)))?;
    let kind = PipelineKind::Fullscreen { inputs: dims, output: format, blend: pass.blend };
    let key = PipelineKey { shader: pass.shader, entry: pass.entry, variant: pass.variant, kind };
    let environment = if pass.variant.has(Variant::ENVIRONMENT) {
        let map = rec.scene.environment.as_ref().ok_or_else(|| missing("environment map"))?;
        Some(map.bind_group(rec.device, rec.cache.environment_layout()))
    } else {
        None
    };
    let pipeline = rec.cache.pipeline(rec.device, &key)?;
    record(encoder, pass, pipeline, rec.frame, at.offset, &inputs, environment, output, stamps);
    Ok(())
}
