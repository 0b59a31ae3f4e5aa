//! Writing COPC files from LAS/LAZ (`pointblend convert IN OUT.copc.laz`),
//! so that tests and benchmarks can make files larger than the samples. Users
//! should index their own data with PDAL and Untwine; neither installs from a
//! registry here (Debian 12 has no PDAL package), so this writer exists.
//!
//! The octree follows COPC 1.0 and Entwine: a cube around the bounds, and at
//! each node one point per cell of a [`GRID`]³ grid over its cube stays there
//! (the root's spacing is the cube's side / [`GRID`]); the rest go to the
//! eight children, until a node holds at most [`LEAF_POINTS`]. Records are
//! converted to point format 6, 7 (with RGB) or 8 (with NIR), extra bytes and
//! the other VLRs kept. Each node is one layered LAZ chunk (variable-size
//! chunks), compressed in parallel; coarse levels come first in the file. The
//! hierarchy is in the EVLR: a root page for the levels above [`PAGE_LEVEL`]
//! and a page per subtree below, as large files need. The file is written to a temporary
//! file beside the output and renamed.

use std::io::{Seek, SeekFrom, Write};
use std::path::Path;

use glam::DVec3;
use las::copc::VoxelKey;
use laz::record::{LayeredPointRecordCompressor, RecordCompressor};
use rayon::prelude::*;
use rustc_hash::FxHashSet;

use super::CopcError;
use crate::cloud::CloudError;
use crate::cloud::las_file;

/// Cells per side of a node's sampling grid.
pub const GRID: u32 = 128;
/// A node with at most this many points is a leaf.
pub const LEAF_POINTS: usize = 100_000;
const MAX_LEVEL: i32 = 20;
/// Nodes from this level down are listed in pages of their own, one per subtree.
pub const PAGE_LEVEL: i32 = 3;

/// What was written.
#[derive(Debug, Clone)]
pub struct Written {
    pub points: u64,
    pub nodes: usize,
    pub depth: i32,
    pub bytes: u64,
}

struct Node {
    key: VoxelKey,
    points: Vec<u32>,
}

/// Writes `input` (LAS or LAZ) as a COPC file at `output`.
pub fn write_copc(input: &Path, output: &Path, progress: bool) -> Result<Written, CopcError> {
    let read = read_records(input, progress)?;
    let cube = Cube::around(&read.positions, read.transforms.x.scale);
    let (nodes, depth) = octree(&read.positions, &cube);
    let fail = |e: String| CopcError::new(&input.display().to_string(), e);
    let laz_vlr = laz::LazVlrBuilder::default()
        .with_point_format(read.format.to_u8().expect("6-8"), read.format.extra_bytes)
        .map_err(|e| fail(e.to_string()))?
        .with_variable_chunk_size()
        .build();
    let chunks = compress(&nodes, &read, &laz_vlr, progress).map_err(|e| fail(format!("compressing: {e}")))?;
    let bytes = write_file(output, &read, &cube, (&nodes, &chunks), &laz_vlr)?;
    Ok(Written { points: read.positions.len() as u64, nodes: nodes.len(), depth, bytes })
}

/// A LAS/LAZ file's points, as the COPC file will hold them.
struct Records {
    header: las::Header,
    /// The output's point format (6, 7 or 8, the input's extra bytes kept).
    format: las::point::Format,
    transforms: las::Vector<las::Transform>,
    /// Every point's record in `format`, one after another.
    records: Vec<u8>,
    positions: Vec<DVec3>,
}

/// Reads `input` whole, through the checks of a whole-file read (header,
/// records, LAZ chunks) and with its messages, converting each record to
/// point format 6, 7 (RGB) or 8 (NIR).
fn read_records(input: &Path, progress: bool) -> Result<Records, CopcError> {
    let name = input.display().to_string();
    let fail = |e: String| CopcError::new(&name, e);
    let reason = |e: CloudError| match e {
        CloudError::Content { reason, .. } => reason,
        e => e.to_string(),
    };
    let (mut reader, _) = las_file::open(input).map_err(|e| fail(reason(e)))?;
    let header = reader.header().clone();
    let in_format = *header.point_format();
    let mut format = las::point::Format::new(match (in_format.has_nir, in_format.has_color) {
        (true, _) => 8,
        (false, true) => 7,
        _ => 6,
    })
    .expect("formats 6-8 exist");
    format.extra_bytes = in_format.extra_bytes;
    let transforms = *header.transforms();
    let bar = crate::progress::bar(header.number_of_points(), "reading", progress);
    let mut records: Vec<u8> = Vec::new();
    let mut positions: Vec<DVec3> = Vec::new();
    let mut batch = las::PointDataBuilder::new().for_header(&header).build();
    loop {
        let n = reader
            .fill_points(1 << 20, &mut batch)
            .map_err(|e| fail(reason(las_file::points_error(input, e, in_format.is_compressed))))?;
        if n == 0 {
            break;
        }
        positions.extend(batch.x().zip(batch.y()).zip(batch.z()).map(|((x, y), z)| DVec3::new(x, y, z)));
        if in_format == format {
            records.extend_from_slice(batch.raw_bytes());
        } else {
            for record in batch.raw_bytes().chunks_exact(usize::from(in_format.len())) {
                let raw = las::raw::Point::read_from(record, &in_format).map_err(|e| fail(e.to_string()))?;
                let point = las::Point::new(raw, &transforms);
                let raw = point.into_raw(&transforms).map_err(|e| fail(e.to_string()))?;
                raw.write_to(&mut records, &format).map_err(|e| fail(e.to_string()))?;
            }
        }
        bar.inc(n);
    }
    bar.finish();
    if positions.is_empty() {
        return Err(fail("the file has no points".into()));
    }
    Ok(Records { header, format, transforms, records, positions })
}

/// The octree's cube around the points, and their bounds.
struct Cube {
    lo: DVec3,
    hi: DVec3,
    centre: DVec3,
    halfsize: f64,
    /// The root's point spacing: the cube's side / [`GRID`].
    spacing: f64,
}

impl Cube {
    /// The cube around `positions` (not empty), widened by the file's `scale` so every point is inside.
    fn around(positions: &[DVec3], scale: f64) -> Cube {
        let (lo, hi) = positions.iter().fold((positions[0], positions[0]), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        let halfsize = ((hi - lo).max_element() * 0.5).max(1e-3) * (1.0 + 1e-9) + scale.abs();
        Cube { lo, hi, centre: (lo + hi) * 0.5, halfsize, spacing: 2.0 * halfsize / f64::from(GRID) }
    }

    /// The COPC info VLR's data, with the root hierarchy page at `root` (offset, bytes).
    fn info(&self, root: (u64, u64)) -> Vec<u8> {
        let mut data = Vec::with_capacity(160);
        for v in [self.centre.x, self.centre.y, self.centre.z, self.halfsize, self.spacing] {
            data.extend_from_slice(&v.to_le_bytes());
        }
        data.extend_from_slice(&root.0.to_le_bytes());
        data.extend_from_slice(&root.1.to_le_bytes());
        data.extend_from_slice(&0f64.to_le_bytes());
        data.extend_from_slice(&0f64.to_le_bytes());
        data.resize(160, 0);
        data
    }
}

/// The octree's nodes, level by level (so the file holds the coarse ones
/// first), empty ones left out; and the deepest level.
fn octree(positions: &[DVec3], cube: &Cube) -> (Vec<Node>, i32) {
    let mut nodes = Vec::new();
    let mut level = vec![Node { key: VoxelKey::ROOT, points: (0..positions.len() as u32).collect() }];
    let mut depth = 0;
    while !level.is_empty() {
        let next: Vec<Vec<Node>> =
            level.par_iter_mut().map(|node| split(node, positions, cube.centre, cube.halfsize)).collect();
        depth = level[0].key.l;
        nodes.extend(level.into_iter().filter(|n| !n.points.is_empty()));
        level = next.into_iter().flatten().collect();
    }
    (nodes, depth)
}

/// Each node's points as one layered LAZ chunk, compressed in parallel.
fn compress(nodes: &[Node], read: &Records, laz_vlr: &laz::LazVlr, progress: bool) -> std::io::Result<Vec<Vec<u8>>> {
    let record_len = usize::from(read.format.len());
    let bar = crate::progress::bar(nodes.len() as u64, "compressing nodes", progress);
    let chunks = nodes
        .par_iter()
        .map(|node| {
            let mut compressor = LayeredPointRecordCompressor::new(std::io::Cursor::new(Vec::new()));
            compressor.set_fields_from(laz_vlr.items()).map_err(std::io::Error::other)?;
            for &i in &node.points {
                let at = i as usize * record_len;
                compressor.compress_next(&read.records[at..at + record_len])?;
            }
            compressor.done()?;
            bar.inc(1);
            Ok(compressor.get_mut().get_ref().clone())
        })
        .collect::<std::io::Result<_>>();
    bar.finish();
    chunks
}

/// Writes the COPC file: the header and VLRs, the chunks and their table,
/// then the hierarchy EVLR, and the header again with where the EVLR and
/// the root page are; to a temporary file beside `output`, then renamed.
/// Returns the file's bytes.
fn write_file(
    output: &Path,
    read: &Records,
    cube: &Cube,
    (nodes, chunks): (&[Node], &[Vec<u8>]),
    laz_vlr: &laz::LazVlr,
) -> Result<u64, CopcError> {
    let out_name = output.display().to_string();
    let fail = |e: String| CopcError::new(&out_name, e);
    let wfail = |e: std::io::Error| CopcError::new(&out_name, e.to_string());
    let target = crate::output::prepare(output).map_err(wfail)?;
    let mut file = crate::output::Temporary::new_in(crate::output::folder_of(&target)).map_err(wfail)?;
    crate::output::make_readable(file.as_file()).map_err(wfail)?;
    let mut laz_data = Vec::new();
    laz_vlr.write_to(&mut laz_data).map_err(wfail)?;
    // Its data is rewritten with the root page's place once that is known (the same 160 bytes).
    let info = cube.info((0, 0));
    let copc_info =
        las::Vlr { user_id: las::copc::USER_ID.into(), record_id: 1, description: "copc info".into(), data: info };
    let mut vlrs = vec![
        copc_info,
        las::Vlr { user_id: "laszip encoded".into(), record_id: 22204, description: "laz-rs".into(), data: laz_data },
    ];
    let kept =
        read.header.vlrs().iter().filter(|v| !(v.user_id == "laszip encoded" || v.user_id == las::copc::USER_ID));
    vlrs.extend(kept.cloned());
    let mut builder = las::Builder::from((1, 4));
    builder.point_format = read.format;
    builder.point_format.is_compressed = true;
    builder.transforms = read.transforms;
    builder.vlrs = vlrs.clone();
    builder.generating_software = "pointblend".into();
    let out_header = builder.into_header().map_err(|e| fail(e.to_string()))?;
    let write_head = |file: &mut std::fs::File, root: (u64, u64), evlr_at: u64| -> Result<(), CopcError> {
        let mut raw = out_header.clone().into_raw().map_err(|e| fail(e.to_string()))?;
        (raw.min_x, raw.min_y, raw.min_z) = (cube.lo.x, cube.lo.y, cube.lo.z);
        (raw.max_x, raw.max_y, raw.max_z) = (cube.hi.x, cube.hi.y, cube.hi.z);
        raw.number_of_point_records = 0;
        raw.number_of_points_by_return = [0; 5];
        raw.large_file = Some(las::raw::header::LargeFile {
            number_of_point_records: read.positions.len() as u64,
            number_of_points_by_return: [0; 15],
        });
        raw.evlr = Some(las::raw::header::Evlr { start_of_first_evlr: evlr_at, number_of_evlrs: 1 });
        file.seek(SeekFrom::Start(0)).map_err(wfail)?;
        raw.write_to(&mut *file).map_err(|e| fail(e.to_string()))?;
        for (i, vlr) in vlrs.iter().enumerate() {
            let vlr = if i == 0 { las::Vlr { data: cube.info(root), ..vlr.clone() } } else { vlr.clone() };
            vlr.into_raw(false).and_then(|r| r.write_to(&mut *file)).map_err(|e| fail(e.to_string()))?;
        }
        Ok(())
    };
    let f = file.as_file_mut();
    write_head(f, (0, 0), 0)?;
    let mut out = std::io::BufWriter::new(f);
    let table_offset_at = out.stream_position().map_err(wfail)?;
    out.write_all(&(-1i64).to_le_bytes()).map_err(wfail)?;
    let mut entries = Vec::with_capacity(nodes.len());
    let mut table = laz::laszip::ChunkTable::with_capacity(nodes.len());
    for (node, chunk) in nodes.iter().zip(chunks) {
        let offset = out.stream_position().map_err(wfail)?;
        out.write_all(chunk).map_err(wfail)?;
        entries.push((node.key, offset, chunk.len() as i32, node.points.len() as i32));
        let (point_count, byte_count) = (node.points.len() as u64, chunk.len() as u64);
        table.push(laz::laszip::ChunkTableEntry { point_count, byte_count });
    }
    let table_at = out.stream_position().map_err(wfail)?;
    table.write_to(&mut out, laz_vlr).map_err(wfail)?;
    let evlr_at = out.stream_position().map_err(wfail)?;
    // The EVLR's data (after its 60-byte header): the root page, then one page per subtree below PAGE_LEVEL.
    let data_at = evlr_at + 60;
    let (data, root_len) = hierarchy_pages(&entries, data_at);
    let evlr =
        las::Vlr { user_id: las::copc::USER_ID.into(), record_id: 1000, description: "EPT hierarchy".into(), data };
    evlr.into_raw(true).and_then(|r| r.write_to(&mut out)).map_err(|e| fail(e.to_string()))?;
    out.seek(SeekFrom::Start(table_offset_at)).map_err(wfail)?;
    out.write_all(&(table_at as i64).to_le_bytes()).map_err(wfail)?;
    let f = out.into_inner().map_err(|e| wfail(e.into_error()))?;
    write_head(f, (data_at, root_len), evlr_at)?;
    let bytes = f.seek(SeekFrom::End(0)).map_err(wfail)?;
    file.persist(&target).map_err(wfail)?;
    Ok(bytes)
}

/// Hierarchy entries: (key, chunk offset, chunk bytes, points).
type Entry = (VoxelKey, u64, i32, i32);

/// The hierarchy pages of `entries`, to be written at `at`: the root page
/// holds the levels above [`PAGE_LEVEL`] and points (a count of −1) to one
/// page per subtree rooted there, so a reader reads the deep levels' pages
/// only when it reaches them. Returns the pages' bytes and the root page's size.
fn hierarchy_pages(entries: &[Entry], at: u64) -> (Vec<u8>, u64) {
    let mut top: Vec<Entry> = Vec::new();
    let mut subtrees: std::collections::BTreeMap<(i32, i32, i32), Vec<Entry>> = Default::default();
    for &entry in entries {
        let key = entry.0;
        if key.l < PAGE_LEVEL {
            top.push(entry);
        } else {
            let shift = key.l - PAGE_LEVEL;
            subtrees.entry((key.x >> shift, key.y >> shift, key.z >> shift)).or_default().push(entry);
        }
    }
    let root_len = ((top.len() + subtrees.len()) * 32) as u64;
    let mut pages = Vec::new();
    let mut next = at + root_len;
    for ((x, y, z), page) in &subtrees {
        let len = (page.len() * 32) as u64;
        top.push((VoxelKey { l: PAGE_LEVEL, x: *x, y: *y, z: *z }, next, len as i32, -1));
        pages.extend(page.iter().copied());
        next += len;
    }
    let mut data = Vec::with_capacity((top.len() + pages.len()) * 32);
    for (key, offset, size, count) in top.iter().chain(&pages) {
        for v in [key.l, key.x, key.y, key.z] {
            data.extend_from_slice(&v.to_le_bytes());
        }
        data.extend_from_slice(&offset.to_le_bytes());
        data.extend_from_slice(&size.to_le_bytes());
        data.extend_from_slice(&count.to_le_bytes());
    }
    (data, root_len)
}

/// Keeps one point per grid cell in `node` (all of them in a leaf) and
/// returns its children with the rest.
fn split(node: &mut Node, positions: &[DVec3], centre: DVec3, halfsize: f64) -> Vec<Node> {
    if node.points.len() <= LEAF_POINTS || node.key.l >= MAX_LEVEL {
        return Vec::new();
    }
    let side = 2.0 * halfsize / f64::from(1u32 << node.key.l);
    let min =
        centre - DVec3::splat(halfsize) + DVec3::new(node.key.x as f64, node.key.y as f64, node.key.z as f64) * side;
    let cell = side / f64::from(GRID);
    let mut taken = FxHashSet::default();
    let mut children: [Vec<u32>; 8] = Default::default();
    let mut kept = Vec::new();
    for &i in &node.points {
        let local = (positions[i as usize] - min) / cell;
        let c = local.floor().clamp(DVec3::ZERO, DVec3::splat(f64::from(GRID - 1)));
        let (cx, cy, cz) = (c.x as u32, c.y as u32, c.z as u32);
        if taken.insert((cx * GRID + cy) * GRID + cz) {
            kept.push(i);
        } else {
            let half = GRID / 2;
            let octant = (cx >= half) as usize | ((cy >= half) as usize) << 1 | ((cz >= half) as usize) << 2;
            children[octant].push(i);
        }
    }
    node.points = kept;
    children
        .into_iter()
        .enumerate()
        .filter(|(_, points)| !points.is_empty())
        .map(|(octant, points)| {
            let k = node.key;
            let bit = |b: usize| ((octant >> b) & 1) as i32;
            let key = VoxelKey { l: k.l + 1, x: 2 * k.x + bit(0), y: 2 * k.y + bit(1), z: 2 * k.z + bit(2) };
            Node { key, points }
        })
        .collect()
}
