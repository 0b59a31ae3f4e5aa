//! What the tile pipeline of `tiled` binds and holds, as the plan states
//! it: each pass's group-1 bindings in binding order (checked against the
//! WGSL by tests/render_core.rs), and the buffers a frame uses with their
//! sizes, so that `--explain` gives the frame's whole GPU memory. The
//! engine that owns the buffers and records the passes is
//! [`crate::tile_engine`].

use super::passes::TileWork;
use super::passes::compute::Binding;
use super::plan::BufferDesc;
use super::shaders::Variant;
use super::tile_engine::{ENTRY_BYTES, EYE_SPLAT_BYTES, LIST_STATE_BYTES, READBACK_BYTES, RECT_BYTES, TILE, grid};

/// The buffers a frame of `splats` splats (the per-splat buffers' slots:
/// the scene's splats, or fewer into which a part of the frame packs those
/// that reach it) at `width` x `height` uses, as the plan states them; the
/// entries' size is known only once the splats are projected, and the
/// renderer fills it in after the frame.
/// `entries` is (this frame's entries, the room allocated for them).
pub fn planned_buffers(splats: usize, (width, height): (u32, u32), entries: Option<(u64, u64)>) -> Vec<BufferDesc> {
    let (columns, rows) = grid(width, height);
    let n = splats as u64;
    vec![
        BufferDesc {
            name: "eye splats",
            bytes: n * EYE_SPLAT_BYTES,
            why: "48 B per splat: eye space, plane, colour".into(),
        },
        BufferDesc { name: "splat tiles", bytes: n * RECT_BYTES, why: "16 B per splat: pixel bounds, sort key".into() },
        BufferDesc {
            name: "tile tables",
            bytes: table_bytes((width, height)),
            why: format!(
                "{columns}x{rows} tiles of {TILE} px: counts, offsets, entries kept, the long lists; the lists' state and its readback"
            ),
        },
        BufferDesc {
            name: "tile entries",
            bytes: entries.map_or(0, |(_, room)| room * ENTRY_BYTES),
            why: match entries {
                Some((used, room)) => format!("8 B per (tile, splat) pair: {used} this frame, room for {room}"),
                None => "8 B per (tile, splat) pair, counted when the splats are projected".into(),
            },
        },
        BufferDesc {
            name: "sort scratch",
            bytes: entries.map_or(0, |(_, room)| room * ENTRY_BYTES),
            why: "as large as the entries: the merge sort's other half".into(),
        },
    ]
}

/// Bytes of the per-tile tables of a `width` x `height` frame (counts,
/// offsets, entries kept, the long lists) and of the lists' state.
pub fn table_bytes((width, height): (u32, u32)) -> u64 {
    let (columns, rows) = grid(width, height);
    (4 * (columns * rows) as u64 + 2) * 4 + LIST_STATE_BYTES + READBACK_BYTES
}

/// The group-1 bindings of a pass, in binding order.
pub fn bindings(work: TileWork, variant: Variant, output: wgpu::TextureFormat) -> Vec<Binding> {
    let (ro, rw) = (Binding::Storage { read_only: true }, Binding::Storage { read_only: false });
    match work {
        TileWork::Project if variant.has(Variant::LIGHTS) => vec![Binding::Uniform, ro, rw, rw, rw, ro, rw, ro],
        TileWork::Project => vec![Binding::Uniform, ro, rw, rw, rw, ro, rw],
        TileWork::ProjectTriangles => vec![Binding::Uniform, ro, ro, rw, rw],
        TileWork::Scan => vec![Binding::Uniform, ro, rw, rw, rw],
        TileWork::Bin => vec![Binding::Uniform, ro, rw, rw, ro, ro],
        TileWork::SortShort => vec![Binding::Uniform, ro, rw, rw, ro],
        TileWork::SortLong => vec![Binding::Uniform, ro, rw, rw, ro, ro],
        TileWork::Raster => {
            let mut b = vec![Binding::Uniform, ro, ro, ro, Binding::StorageTexture(output), rw, ro];
            if variant.has(Variant::ENVIRONMENT) {
                b.extend([Binding::StorageTexture(output); 3]);
            }
            if variant.has(Variant::TRIANGLES) {
                b.extend([ro, ro]);
            }
            b
        }
    }
}
