//! A splat pass records itself: its pipeline key (and that of the frame's
//! mesh triangles through the same fragment entry), its attachments, the
//! views it was given, and the draw (`passes::splat::record`).

use super::{At, Recording, missing};
use crate::context::GpuError;
use crate::passes::splat::{Attachments, record};
use crate::passes::{PipelineKey, PipelineKind, SplatPass};
use crate::shaders::Variant;
use crate::touches::Slot;

/// Records `pass` into `encoder`.
pub fn encode(
    rec: &mut Recording<'_>,
    encoder: &mut wgpu::CommandEncoder,
    pass: &SplatPass,
    at: At,
    stamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
) -> Result<(), GpuError> {
    let colour =
        pass.colour.iter().map(|c| Ok((rec.target(c.target)?.format, c.blend))).collect::<Result<_, GpuError>>()?;
    let depth = match pass.depth {
        Some((id, test)) => Some((rec.target(id)?.format, test.write, test.compare)),
        None => None,
    };
    let inputs = rec.inputs(at.step, &pass.inputs)?;
    let kind = PipelineKind::Splats {
        colour,
        depth,
        inputs: inputs.as_ref().map(|i| i.0.clone()).unwrap_or_default(),
        cull_back: false,
    };
    // A pass that writes only depth reads no colour: its splats are not lit.
    let variant = pass
        .variant
        .with(Variant::LIGHTS, pass.variant.has(Variant::LIGHTS) && !pass.colour.is_empty())
        .with(Variant::CLIP, rec.plan.clipped);
    let key = PipelineKey { shader: pass.shader, entry: pass.entry, variant, kind };
    // The frame's mesh triangles, through the same fragment entry.
    let triangle_key =
        rec.scene.triangles.as_ref().filter(|_| pass.triangles).map(|draw| key.for_triangles(draw.cull_back));
    if let Some(triangle_key) = &triangle_key {
        rec.cache.pipeline(rec.device, triangle_key)?;
    }
    rec.cache.pipeline(rec.device, &key)?;
    let attachments = Attachments {
        colour: pass.colour.iter().map(|c| rec.layer_view(c.target, pass.layer)).collect::<Result<_, _>>()?,
        depth: pass.depth.map(|(id, _)| rec.layer_view(id, pass.layer)).transpose()?,
    };
    // Colour attachments are cleared, then blended into: written only.
    for (i, view) in attachments.colour.iter().enumerate() {
        rec.given(at.step, Slot::Colour(i as u32), view, false, true);
    }
    if let (Some(view), Some((_, test))) = (attachments.depth, pass.depth) {
        // The depth test reads what was loaded; the pipeline writes depth or not.
        let reads = !test.clear && test.compare != wgpu::CompareFunction::Always;
        rec.given(at.step, Slot::Depth, view, reads, test.write);
    }
    let built = |key: &PipelineKey| rec.cache.built(key).ok_or_else(|| missing(key.entry));
    let pipeline = built(&key)?;
    let triangles = triangle_key.as_ref().map(built).transpose()?;
    let group = inputs.as_ref().map(|i| &i.1);
    record(encoder, pass, pipeline, rec.frame, at.offset, group, &attachments, rec.scene, triangles, stamps);
    Ok(())
}
