//! Corrupt LAZ files, made from the shared lidar samples by byte edits at
//! the places the format keeps its sizes: the chunk table's offset, count
//! and coded entries, a layered chunk's layer sizes, a code's first bytes,
//! the header's 64-bit point count. Each must be refused in one line that
//! says what is wrong, under a 1 GB address-space limit (the `laz` crate
//! believed these sizes: aborts on 34-68 GB reservations, panics, 4 GB per
//! chunk decoded), by `info`, by `convert` to COPC, and for a COPC node by
//! a streamed render.
//!
//! Offsets: autzen_trim.laz (LAS 1.2, format 3, 3 fixed chunks of 50,000
//! points) has its points at 2144 and its chunk table at 603333;
//! las_with_several_extra_byte_bloc.laz (LAS 1.4, format 8 + 3 extra bytes,
//! 14 layered chunks) has its points at 2123 and its table at 3239998; each
//! layered chunk holds a 41-byte first point, a u32 count, 14 u32 layer
//! sizes, then the layers.

mod common;

use std::path::{Path, PathBuf};

use common::corrupt::{i64_at, info_refused, limited, patched, refused, u32_at};

const FF4: &[u8] = &[0xff; 4];

/// autzen_trim.laz, its layout checked.
fn autzen() -> Option<PathBuf> {
    let path = common::shared_data("lidar/autzen_trim.laz")?;
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!((u32_at(&bytes, 96), i64_at(&bytes, 2144), u32_at(&bytes, 603337)), (2144, 603333, 3), "layout");
    Some(path)
}

/// las_with_several_extra_byte_bloc.laz, its layout checked.
fn extra() -> Option<PathBuf> {
    let path = common::shared_data("lidar/las_with_several_extra_byte_bloc.laz")?;
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!((u32_at(&bytes, 96), i64_at(&bytes, 2123), u32_at(&bytes, 3240002)), (2123, 3239998, 14), "layout");
    Some(path)
}

/// Where each of the 14 chunks of las_with_several_extra_byte_bloc.laz
/// starts (from its chunk table), checked by the point count each holds.
fn extra_chunks(path: &Path) -> Vec<usize> {
    let starts = [
        2131, 222712, 435171, 650139, 869087, 1096411, 1326077, 1551060, 1776219, 2003148, 2232520, 2463963, 2713163,
        2983606,
    ];
    let bytes = std::fs::read(path).unwrap();
    for s in starts {
        assert!([50_000, 697_721 - 13 * 50_000].contains(&u32_at(&bytes, s + 41)), "chunk at {s}");
    }
    starts.to_vec()
}

fn scratch() -> tempfile::TempDir {
    tempfile::Builder::new().prefix("pointblend-corrupt-").tempdir().unwrap()
}

#[test]
fn the_sound_samples_read_under_the_memory_limit() {
    for name in ["lidar/autzen_trim.laz", "lidar/las_with_several_extra_byte_bloc.laz", "lidar/lone-star.copc.laz"] {
        let path = require!(common::shared_data(name));
        let dir = scratch();
        // `convert` reads a COPC file whole, as LAZ.
        let out = limited(&[Path::new("convert"), &path, &dir.path().join("out.ply")]);
        assert!(out.status.success(), "{name}: {}", String::from_utf8_lossy(&out.stderr));
    }
}

#[test]
fn a_chunk_count_of_2_to_the_32_is_refused() {
    let source = require!(autzen());
    let dir = scratch();
    let file = patched(&source, dir.path(), "count.laz", &[(603337, FF4)]);
    let line = info_refused(&file, "a chunk table counting 2^32-1 chunks");
    assert!(line.contains("lists 4294967295 chunks"), "{line}");
}

#[test]
fn a_chunk_table_offset_into_the_points_is_refused() {
    let source = require!(autzen());
    let dir = scratch();
    let file = patched(&source, dir.path(), "offset.laz", &[(2144, &300_000i64.to_le_bytes())]);
    let line = info_refused(&file, "a chunk-table offset into the points");
    assert!(line.contains("chunk table (at byte 300000) lists"), "{line}");
}

#[test]
fn chunk_table_entries_that_do_not_decode_are_refused() {
    let source = require!(autzen());
    let dir = scratch();
    let file = patched(&source, dir.path(), "entries.laz", &[(603341, &[0xff; 12])]);
    let line = info_refused(&file, "garbage table entries (3 chunks)");
    assert!(line.contains("corrupt: its entries do not decode"), "{line}");
    let source = require!(extra());
    let file = patched(&source, dir.path(), "entries14.laz", &[(3240006, &[0xff; 16])]);
    let line = info_refused(&file, "garbage table entries (14 chunks)");
    assert!(line.contains("corrupt: its entries do not decode"), "{line}");
}

#[test]
fn a_layer_larger_than_its_chunk_is_refused_in_one_chunk_or_all() {
    let source = require!(extra());
    let dir = scratch();
    let file = patched(&source, dir.path(), "layer.laz", &[(2176, FF4)]);
    let line = info_refused(&file, "chunk 0's first layer size flipped");
    assert!(line.contains("LAZ chunk 0 of 14 (at byte 2131): its layers add up to"), "{line}");
    let edits: Vec<(usize, &[u8])> = extra_chunks(&source).into_iter().map(|s| (s + 45, FF4)).collect();
    let file = patched(&source, dir.path(), "layers.laz", &edits);
    let line = info_refused(&file, "every chunk's first layer size flipped");
    assert!(line.contains("layers add up to"), "{line}");
    // `convert` to COPC reads its input through the same checks.
    let out = limited(&[Path::new("convert"), &file, &dir.path().join("out.copc.laz")]);
    let line = refused(&out, &file, "convert to COPC of a file with flipped layer sizes");
    assert!(line.contains("layers add up to"), "{line}");
    assert!(!dir.path().join("out.copc.laz").exists());
}

#[test]
fn codes_that_start_with_four_ff_bytes_are_refused() {
    // Point-wise: chunk 0's code follows its 34-byte first point.
    let source = require!(autzen());
    let dir = scratch();
    let file = patched(&source, dir.path(), "pointwise.laz", &[(2152 + 34, FF4)]);
    let line = info_refused(&file, "a point-wise code starting with ff ff ff ff");
    assert!(line.contains("starts with ff ff ff ff"), "{line}");
    // Layered: chunk 0's first layer, after the first point, the count and 14 sizes.
    let source = require!(extra());
    let file = patched(&source, dir.path(), "layered.laz", &[(2131 + 41 + 4 + 56, FF4)]);
    let line = info_refused(&file, "a layer starting with ff ff ff ff");
    assert!(line.contains("starts with ff ff ff ff"), "{line}");
}

#[test]
fn a_point_count_of_2_to_the_40_and_a_table_offset_of_2_to_the_60_say_what_is_wrong() {
    let source = require!(extra());
    let dir = scratch();
    let file = patched(&source, dir.path(), "count.laz", &[(247, &(1u64 << 40).to_le_bytes())]);
    let count = info_refused(&file, "a 64-bit point count of 2^40");
    assert!(count.contains("counts 1099511627776 points, more than the LAZ chunk table lists"), "{count}");
    let file = patched(&source, dir.path(), "table.laz", &[(2123, &(1i64 << 60).to_le_bytes())]);
    let table = info_refused(&file, "a chunk-table offset of 2^60");
    assert!(table.contains("chunk table is said to start at byte 1152921504606846976, past the file's end"), "{table}");
    for line in [count, table] {
        assert!(!line.contains("os error"), "{line}");
    }
}

#[test]
fn compressed_data_that_does_not_decode_is_called_corrupt_not_truncated() {
    // Chunk 0's code (after its 34-byte first point) zeroed over 64 bytes: the
    // decoder runs past the chunk's end, which in a file whose chunks all lie
    // within it is corrupt data.
    let source = require!(autzen());
    let dir = scratch();
    let file = patched(&source, dir.path(), "garbled.laz", &[(2152 + 34 + 4, &[0u8; 64])]);
    let line = info_refused(&file, "corrupt compressed points");
    assert!(line.contains("corrupt compressed data"), "{line}");
    assert!(!line.contains("truncated"), "{line}");
}

/// lone-star.copc.laz with the first layer size of its root node's chunk
/// (at 1642789: a 30-byte first point, the u32 count, 9 sizes) flipped.
fn corrupt_copc(dir: &Path) -> Option<PathBuf> {
    let source = common::shared_data("lidar/lone-star.copc.laz")?;
    let bytes = std::fs::read(&source).unwrap();
    assert_eq!(u32_at(&bytes, 1642789 + 30), 58393, "the root node's chunk");
    Some(patched(&source, dir, "lone-star-layer.copc.laz", &[(1642789 + 34, FF4)]))
}

#[test]
fn a_copc_node_with_a_flipped_layer_size_is_refused_read_whole() {
    let dir = scratch();
    let file = require!(corrupt_copc(dir.path()));
    let out = limited(&[Path::new("convert"), &file, &dir.path().join("out.ply")]);
    let line = refused(&out, &file, "a COPC file read whole");
    assert!(line.contains("(at byte 1642789): its layers add up to"), "{line}");
}

#[test]
fn a_copc_node_with_a_flipped_layer_size_is_skipped_when_streamed() {
    let dir = scratch();
    let file = require!(corrupt_copc(dir.path()));
    let image = dir.path().join("frame.png");
    // The GPU's driver takes more address space than a reader: 4 GiB, still below the 4.1 GB node.
    let out = std::process::Command::new("sh")
        .arg("-c")
        .arg("ulimit -v 4194304; exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_pointblend"))
        .args(["render", "--point-budget", "all", "--size", "64x64", "--out"])
        .arg(&image)
        .arg(&file)
        .env("MALLOC_ARENA_MAX", "2")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.code().is_some() && !stderr.contains("panicked"), "{:?}: {stderr}", out.status);
    assert!(!stderr.contains("memory allocation"), "{stderr}");
    let skipped = stderr.lines().find(|l| l.contains("skipped")).unwrap_or_else(|| panic!("no node skipped: {stderr}"));
    assert!(skipped.contains("lone-star-layer.copc.laz") && skipped.contains("layers add up to"), "{skipped}");
}
