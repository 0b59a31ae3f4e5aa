//! `tiled`: the exact reference (Zhang & Pajarola's transparency model as
//! `reference` computes it: every hit, ε-layers split by facing, Eq. 1 per
//! layer, front-to-back compositing with no layer cap) on the GPU, with
//! tile-based compute rasterisation in the manner of the 3D Gaussian
//! splatting renderers, but blending within ε-layers instead of per splat.
//!
//! Four compute steps and one full-screen step (`crate::tile_engine` holds
//! the buffers and describes each): project the splats and count the tiles
//! each may cover; bin them into per-tile lists at offsets from the counts'
//! prefix sum, taken on the GPU (a frame whose lists pass their buffer's
//! room is drawn again with more, and nothing is read back mid-frame); sort each list by the nearest depth on each disc; per pixel,
//! cast the ray on the tile's discs in that order, keep hits in exact depth
//! order through a small window, group them into ε-layers, normalise, shade
//! and composite (`shaders/tiled_raster.wgsl`); then the image becomes the
//! frame, where a scene's environment map is reflected and refracted by the
//! nearest transparent layer with the exact layer count behind it
//! (`shaders/tiled_present.wgsl`). An opaque scene runs the same steps: its
//! first layer is opaque and ends every ray, and facing is not split, as in
//! the opaque reference. A frame's mesh triangles (`mesh` and `hybrid`
//! objects) are projected after the splats into the same tile lists, and
//! the raster intersects them exactly, as the reference does
//! (`shaders/tiled_triangles.wgsl`).

use super::{FrameDesc, GpuMode};
use crate::passes::{Command, ComputePass, FullscreenPass, TileWork};
use crate::plan::{RenderPlan, Step, TargetId};
use crate::shaders::Variant;
use crate::{tile_engine, tile_layout};

pub struct Tiled;

const IMAGE: TargetId = TargetId("tiled image");
const GLASS_FRONT: TargetId = TargetId("nearest transparent layer");
const GLASS_NORMAL: TargetId = TargetId("its normal, layers behind");
const GLASS_BEHIND: TargetId = TargetId("layers behind it");
/// What the raster writes: f32, so the layer count and the glass sums are exact.
const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

impl GpuMode for Tiled {
    fn plan(&self, frame: &FrameDesc<'_>) -> RenderPlan {
        let glassy = frame.environment.is_some() && frame.transparent;
        // Scene lights light each splat once, when it is projected; the raster blends lit colours.
        let variant = frame.shading_variant().with(Variant::LIGHTS, false).with(Variant::ENVIRONMENT, glassy);
        let project_variant = Variant::NONE.with(Variant::LIGHTS, frame.lights);
        let uniforms = frame.uniforms(0, 1, frame.transparent as u32);
        let mut targets =
            vec![frame.storage_target(IMAGE, FORMAT, "rgb composited over the background, layers per pixel")];
        let mut outputs = vec![IMAGE];
        if glassy {
            targets.extend([
                frame.storage_target(GLASS_FRONT, FORMAT, "the nearest transparent layer, shaded, and its opacity"),
                frame.storage_target(GLASS_NORMAL, FORMAT, "its normal and the layers behind it, counted exactly"),
                frame.storage_target(GLASS_BEHIND, FORMAT, "the layers behind it composited, and their transmittance"),
            ]);
            outputs.extend([GLASS_FRONT, GLASS_NORMAL, GLASS_BEHIND]);
        }
        let compute = |label, shader, entry, work, outputs: Vec<TargetId>| {
            vec![Command::Compute(ComputePass {
                label,
                shader,
                entry,
                variant: match work {
                    TileWork::Raster => variant
                        .with(Variant::TRIANGLES, frame.triangles > 0)
                        .with(Variant::CLIP, !frame.settings.clip.is_empty()),
                    TileWork::Project => project_variant,
                    _ => Variant::NONE,
                },
                work,
                outputs,
                uniforms,
            })]
        };
        let present = FullscreenPass::into_frame(
            "TiledPresent::pass",
            ("tiled_present.wgsl", "fs_tiled_present"),
            variant.with(Variant::LIT, false),
            outputs.clone(),
            uniforms,
        );
        let tile = tile_engine::TILE;
        let steps = vec![
            Step::new(
                "project",
                format!(
                    "compute, per splat: eye space, footprint, count the {tile}x{tile} tiles its disc may cover{}",
                    if frame.triangles > 0 { "; per mesh triangle: its tiles" } else { "" }
                ),
                if frame.triangles > 0 {
                    let triangles = compute(
                        "Tiled::project_triangles",
                        "tiled_triangles.wgsl",
                        "cs_project_triangles",
                        TileWork::ProjectTriangles,
                        Vec::new(),
                    );
                    [
                        compute("Tiled::project", "tiled_project.wgsl", "cs_project", TileWork::Project, Vec::new()),
                        triangles,
                    ]
                    .concat()
                } else {
                    compute("Tiled::project", "tiled_project.wgsl", "cs_project", TileWork::Project, Vec::new())
                },
            ),
            Step::new(
                "bin",
                "compute: the counts' prefix sum into offsets, on the GPU within the lists' room; per splat: an entry \
                 in each covered tile's list",
                [
                    compute("Tiled::scan", "tiled_scan.wgsl", "cs_scan", TileWork::Scan, Vec::new()),
                    compute("Tiled::bin", "tiled_bin.wgsl", "cs_bin", TileWork::Bin, Vec::new()),
                ]
                .concat(),
            ),
            Step::new(
                "sort",
                format!(
                    "compute, per tile: the list by nearest depth on each disc (merge sort up to {} entries, else bitonic)",
                    tile_engine::SHORT_LIST
                ),
                [
                    compute("Tiled::sort_short", "tiled_sort.wgsl", "cs_sort_short", TileWork::SortShort, Vec::new()),
                    compute("Tiled::sort_long", "tiled_sort.wgsl", "cs_sort", TileWork::SortLong, Vec::new()),
                ]
                .concat(),
            ),
            Step::new(
                "raster",
                "compute, per pixel: hits in depth order, ε-layers by facing, Eq. 1, front to back",
                compute("Tiled::raster", "tiled_raster.wgsl", "cs_raster", TileWork::Raster, outputs),
            ),
            Step::new(
                "present",
                if glassy {
                    "full screen: environment effects with the exact layer count -> output"
                } else {
                    "full screen: the image -> output"
                },
                vec![Command::Fullscreen(present)],
            ),
        ];
        let what = format!(
            "exact per-pixel ε-layers, {}{}",
            frame.lighting_name(),
            if frame.transparent { "" } else { ", first layer (opaque scene)" }
        );
        let mut plan = frame.plan(what, 1, steps, targets);
        plan.buffers =
            tile_layout::planned_buffers(frame.splats + frame.triangles as usize, (frame.width, frame.height), None);
        plan
    }
}
