//! Writing COPC files from LAS/LAZ (`pointblend convert IN OUT.copc.laz`),
//! so that tests and benchmarks can make files larger than the samples. Users
//! should index their own data with PDAL and Untwine; neither installs from a
//! registry here (Debian 12 has no PDAL package), so this writer exists.
//!
//! The octree follows COPC 1.0 and Entwine ([`super::octree`]). Records are
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

use super::CopcError;
use super::octree::{Cube, Node, octree};
use crate::cloud::CloudError;
use crate::cloud::las_file;

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

/// Writes `input` (LAS or LAZ) as a COPC file at `output`.
pub fn write_copc(input: &Path, output: &Path, progress: bool) -> Result<Written, CopcError> {
    let read = read_records(input, progress)?;
    let position = |i: usize| read.positions[i];
    let cube = Cube::around(&position, read.positions.len(), read.transforms.x.scale);
    let (nodes, depth) = octree(&position, read.positions.len(), &cube);
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

/// The COPC info VLR's data, with the root hierarchy page at `root` (offset, bytes).
pub(crate) fn info_data(cube: &Cube, root: (u64, u64)) -> Vec<u8> {
    let mut data = Vec::with_capacity(160);
    for v in [cube.centre.x, cube.centre.y, cube.centre.z, cube.halfsize, cube.spacing] {
        data.extend_from_slice(&v.to_le_bytes());
    }
    data.extend_from_slice(&root.0.to_le_bytes());
    data.extend_from_slice(&root.1.to_le_bytes());
    data.extend_from_slice(&0f64.to_le_bytes());
    data.extend_from_slice(&0f64.to_le_bytes());
    data.resize(160, 0);
    data
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
    let info = info_data(cube, (0, 0));
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
            let vlr = if i == 0 { las::Vlr { data: info_data(cube, root), ..vlr.clone() } } else { vlr.clone() };
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
