//! A compute pass of the tile pipeline records itself: the pass takes its
//! pipeline and layout from the cache and the tile engine binds and
//! dispatches it, reporting the storage textures it was given. Every pass
//! goes into the frame's one command buffer: the lists' offsets are a
//! prefix sum taken on the GPU (`TileWork::Scan`), so nothing waits.

use super::{At, Recording};
use crate::context::GpuError;
use crate::passes::{ComputePass, TileWork};
use crate::shaders::Variant;
use crate::tile_engine::TileEngine;
use crate::tile_layout;
use crate::touches::Slot;

/// How the tile pipeline runs on this device.
pub struct TileRun<'a> {
    pub tiles: &'a TileEngine,
    /// Whether the raster reads its lists a subgroup at a time.
    pub subgroups: bool,
    /// Whether a pixel of the raster stops once its light is spent.
    pub early_stop: bool,
}

/// Records `pass` into `encoder`.
pub fn encode(
    rec: &mut Recording<'_>,
    encoder: &mut wgpu::CommandEncoder,
    run: &TileRun<'_>,
    pass: &ComputePass,
    at: At,
    stamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
) -> Result<(), GpuError> {
    let outputs = pass.outputs.iter().map(|&id| rec.view(id)).collect::<Result<Vec<_>, _>>()?;
    let format = match pass.outputs.first() {
        Some(&id) => rec.target(id)?.format,
        None => wgpu::TextureFormat::Rgba32Float,
    };
    let bindings = tile_layout::bindings(pass.work, pass.variant, format);
    let raster = pass.work == TileWork::Raster;
    let variant = pass.variant.with(Variant::SUBGROUPS, run.subgroups && raster);
    let variant = variant.with(Variant::EVERY_LAYER, !run.early_stop && raster);
    let sorts = matches!(pass.work, TileWork::SortShort | TileWork::SortLong);
    let variant = variant.with(Variant::PACKED, run.tiles.packing() && sorts);
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
