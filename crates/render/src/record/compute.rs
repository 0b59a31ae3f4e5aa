//! A compute pass of the tile pipeline records itself: the binning step
//! first submits what came before and reads the tiles' counts back (the
//! entries cannot be placed before), then the pass takes its pipeline and
//! layout from the cache and the tile engine binds and dispatches it,
//! reporting the storage textures it was given.

use super::{At, Recording, new_encoder};
use crate::context::{GpuContext, GpuError};
use crate::passes::{ComputePass, TileWork};
use crate::shaders::Variant;
use crate::tile_engine::{self, TileEngine};
use crate::touches::Slot;

/// How the tile pipeline runs on this device.
pub struct TileRun<'a> {
    pub ctx: &'a GpuContext,
    pub tiles: &'a mut TileEngine,
    /// Whether the raster reads its lists a subgroup at a time.
    pub subgroups: bool,
    /// Bytes the tile lists may take beside the frame's targets and buffers.
    pub budget: u64,
}

/// Records `pass` into `encoder` (which a binning step submits and replaces).
pub fn encode(
    rec: &mut Recording<'_>,
    encoder: &mut wgpu::CommandEncoder,
    run: &mut TileRun<'_>,
    pass: &ComputePass,
    at: At,
    stamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
) -> Result<(), GpuError> {
    if pass.work == TileWork::Bin {
        // The counts must come back before the entries can be placed.
        run.ctx.queue.submit([std::mem::replace(encoder, new_encoder(rec.device)).finish()]);
        run.tiles.bin_offsets(run.ctx, run.budget)?;
    }
    let outputs = pass.outputs.iter().map(|&id| rec.view(id)).collect::<Result<Vec<_>, _>>()?;
    let format = match pass.outputs.first() {
        Some(&id) => rec.target(id)?.format,
        None => wgpu::TextureFormat::Rgba32Float,
    };
    let bindings = tile_engine::bindings(pass.work, pass.variant, format);
    let variant = pass.variant.with(Variant::SUBGROUPS, run.subgroups && pass.work == TileWork::Raster);
    let (pipeline, layout) = rec.cache.compute(rec.device, (pass.shader, pass.entry, variant), &bindings)?;
    let stamps = stamps.map(|s| wgpu::ComputePassTimestampWrites {
        query_set: s.query_set,
        beginning_of_pass_write_index: s.beginning_of_pass_write_index,
        end_of_pass_write_index: s.end_of_pass_write_index,
    });
    let frame = (rec.frame, at.offset);
    let given = run.tiles.record(rec.device, encoder, pass, (pipeline, layout), frame, rec.scene, &outputs, stamps);
    for (binding, view) in given {
        rec.given(at.step, Slot::Storage(binding), &view, false, true);
    }
    Ok(())
}
