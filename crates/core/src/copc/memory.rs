//! A point file (LAS, LAZ, PLY without faces, E57) opened whole as a tree
//! of nodes (Schütz's PotreeConverter and Entwine prepare a file the same
//! way before it is drawn): its records are decoded into columns at once
//! (a PLY or E57 file's by its reader, every column kept:
//! `las_file::held_columns`), then sorted into the octree a COPC file of it
//! would hold ([`super::octree`]). The stream
//! then draws it as it draws a COPC file: nodes selected by projected
//! spacing under the point budget, each node's normals, radii and groups
//! made once, when it is first drawn, with its halo, and its GPU copy kept
//! in the node pool. "Loading" a node gathers its points from the columns;
//! no byte is read, so a view's `bytes_read` is 0. Which way the normals
//! estimated per node face is decided once per file ([`super::facing`]).

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use glam::DVec3;

use super::budget::StreamBudget;
use super::header::CopcHeader;
use super::held::{Described, MemoryNodes};
use super::hierarchy::CopcTree;
use super::node_estimates::FileFacing;
use super::octree::{Cube, octree};
use super::source::{ByteSource, Counters, is_streamed};
use super::stream::{CopcStream, StreamOptions};
use super::{CopcError, facing, write};
use crate::cloud::las_file::{self, Columns, extra_bytes::Field};
use crate::cloud::ply::{self, PointColumns};

/// What stands for a file held whole where a stream names its source:
/// its path and length. Nothing is read through it.
struct Held {
    name: String,
    /// The canonical path, length and modification time: a file rewritten
    /// in place is another file for the caches keyed by it.
    identity: String,
    len: u64,
    counters: Counters,
}

impl ByteSource for Held {
    fn name(&self) -> &str {
        &self.name
    }
    fn identity(&self) -> &str {
        &self.identity
    }
    fn len(&self) -> u64 {
        self.len
    }
    fn read(&self, _offset: u64, _len: u64) -> Result<Vec<u8>, CopcError> {
        Err(CopcError::new(&self.name, "the file is held in memory; nothing is read from it by range"))
    }
    fn counters(&self) -> &Counters {
        &self.counters
    }
}

impl CopcStream {
    /// Opens the point file at `path` (LAS, LAZ, PLY or E57) whole, as a tree of nodes.
    pub fn open_whole(path: &Path, options: StreamOptions) -> Result<Self, CopcError> {
        let name = path.display().to_string();
        let points = header_points(path);
        if points.is_some_and(|n| n > u64::from(u32::MAX)) {
            return Err(CopcError::new(
                &name,
                "more than 4,294,967,295 points cannot be held whole; convert it to COPC (`pointblend convert`, PDAL or Untwine) to stream it",
            ));
        }
        if let Some(refusal) = points.and_then(|n| too_large_to_hold(path, n)) {
            return Err(CopcError::new(&name, refusal));
        }
        let started = Instant::now();
        let read = if las_file::is_las(path) { read_las(path)? } else { read_other(path)? };
        let decode_s = started.elapsed().as_secs_f64();
        let columns = read.columns;
        let count = columns.len();
        if count == 0 {
            return Err(CopcError::new(&name, "the file has no points"));
        }
        let sorting = Instant::now();
        let position = |i: usize| DVec3::new(columns.x[i], columns.y[i], columns.z[i]);
        let cube = Cube::around(&position, count, read.header.transforms().x.scale);
        let (nodes, depth) = octree(&position, count, &cube);
        let sort_s = sorting.elapsed().as_secs_f64();
        log::info!(
            "{name}: {count} points decoded in {decode_s:.2} s, sorted into {} nodes ({} levels) in {sort_s:.2} s ({:.1} M points/s)",
            nodes.len(),
            depth + 1,
            count as f64 / sort_s.max(1e-9) / 1e6
        );
        let info = las::Vlr { data: write::info_data(&cube, (0, 0)), ..Default::default() };
        let info = las::copc::CopcInfoVlr::try_from(&info).map_err(|e| CopcError::new(&name, e.to_string()))?;
        let header = CopcHeader {
            las: with_bounds(&read.header, &cube),
            info,
            root_page: (0, 0),
            laz: None,
            fields: read.fields,
            warnings: read.warnings,
            file_len: read.file_len,
        };
        let tree = CopcTree::whole(&header, cube.centre, nodes.iter().map(|n| (n.key, n.points.len() as u32)));
        let facing = match &read.described {
            Some(d) => facing::of_file(&columns, &nodes[0].points, &cube, &d.info),
            None => FileFacing::Up,
        };
        let mut described = read.described;
        if let Some(d) = described.as_mut().filter(|_| facing == FileFacing::Up) {
            // Terrain far from the origin: seen from above, z up, as when loaded whole.
            (d.info.from_above, d.info.z_up) = (true, true);
        }
        let mut memory = MemoryNodes::new(columns, nodes.into_iter().map(|n| n.points).collect());
        (memory.facing, memory.described) = (facing, described);
        let identity = identity_of(path, header.file_len);
        let source = Box::new(Held { name, identity, len: header.file_len, counters: Counters::default() });
        Ok(Self::assemble(source, (header, tree), None, Some(Arc::new(memory)), options))
    }
}

/// Memory a point takes while a file is held whole: its columns (positions
/// in f64, the LAS columns, colours, time; 55-65 bytes on lidar files),
/// its index in its node, and the octree's passes.
const HELD_BYTES_PER_POINT: u64 = 80;

/// Why the `points` of `file` cannot be held whole in the memory that is
/// free (more than half of it), or `None`. A PLY file's reader holds the
/// file's bytes while it makes a column of f64 per property.
fn too_large_to_hold(file: &Path, points: u64) -> Option<String> {
    let ply = ply_header(file).filter(|_| !las_file::is_las(file));
    let per_point = HELD_BYTES_PER_POINT + ply.as_ref().map_or(0, |h| 8 * vertex_properties(h));
    let bytes = ply.map_or(0, |_| std::fs::metadata(file).map_or(0, |m| m.len()));
    let need = points.saturating_mul(per_point).saturating_add(bytes);
    let free = crate::memory::available_bytes().filter(|&free| need > free / 2)?;
    Some(format!(
        "its {points} points take about {} held whole, and {} is free; convert it to COPC (`pointblend convert`, PDAL or Untwine) to stream it",
        crate::memory::gib(need),
        crate::memory::gib(free)
    ))
}

/// A file's points as columns, with what describes them.
struct Read {
    columns: Columns,
    /// The LAS file's header, or one made for a PLY or E57 file (its point count).
    header: las::Header,
    fields: Vec<Field>,
    warnings: Vec<String>,
    file_len: u64,
    /// What a PLY or E57 file says of itself.
    described: Option<Described>,
}

/// A LAS or LAZ file's records, decoded into columns.
fn read_las(path: &Path) -> Result<Read, CopcError> {
    let decoded = las_file::read_columns(path).map_err(|e| copc_error(path, e))?;
    Ok(Read {
        columns: decoded.columns,
        header: decoded.header,
        fields: decoded.fields,
        warnings: decoded.warnings,
        file_len: decoded.file_len,
        described: None,
    })
}

/// A PLY or E57 file, read by its reader (with its checks and messages),
/// as columns: every vertex column and attribute kept ([`Columns::of_read`]).
fn read_other(path: &Path) -> Result<Read, CopcError> {
    let (data, attributes, mut info) = crate::cloud::formats::read(path).map_err(|e| copc_error(path, e))?;
    if !data.triangles.is_empty() {
        return Err(CopcError::new(&path.display().to_string(), "a mesh is drawn whole, not as a tree of nodes"));
    }
    let encoding = data.encoding.clone();
    // What the parser skipped (its counts), before the columns take the data.
    let unread = PointColumns {
        malformed_vertices: data.malformed_vertices.clone(),
        malformed_records: data.malformed_records,
        faces_out_of_range: data.faces_out_of_range,
        ..Default::default()
    };
    let (columns, fields, skipped) = Columns::of_read(data, attributes);
    // A vertex line that could not be read holds NaN: counted as unread, not as NaN.
    let non_finite = skipped.saturating_sub(unread.malformed_vertices.len());
    crate::cloud::load::skipped_records(&unread, non_finite, &mut info.warnings);
    let header = counting_header(columns.len() as u64).map_err(|e| CopcError::new(&path.display().to_string(), e))?;
    let file_len = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
    let described = Some(Described { encoding, info });
    Ok(Read { columns, header, fields, warnings: Vec::new(), file_len, described })
}

/// `e`, a reader's error, as the stream's (its message already names the file).
fn copc_error(path: &Path, e: crate::cloud::CloudError) -> CopcError {
    let name = path.display().to_string();
    CopcError::new(&name, e.to_string().trim_start_matches(&format!("{name}: ")))
}

/// A LAS header that counts `points` (what the tree reads of a header; its
/// bounds are set from the points' by [`with_bounds`]).
fn counting_header(points: u64) -> Result<las::Header, String> {
    let mut raw = las::raw::Header {
        number_of_point_records: u32::try_from(points).map_err(|_| format!("{points} points"))?,
        x_scale_factor: 0.001,
        y_scale_factor: 0.001,
        z_scale_factor: 0.001,
        ..Default::default()
    };
    raw.number_of_points_by_return[0] = raw.number_of_point_records;
    las::Builder::new(raw).and_then(|b| b.into_header()).map_err(|e| e.to_string())
}

/// What identifies the file at `path` of `len` bytes for caches: its
/// canonical path, length and modification time.
fn identity_of(path: &Path, len: u64) -> String {
    let canonical = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
    let modified = std::fs::metadata(path).and_then(|m| m.modified()).ok();
    let nanos = modified.and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok()).map_or(0, |d| d.as_nanos());
    format!("held:{}:{len}:{nanos}", canonical.display())
}

/// The file's header with the bounds of its points (a header's own may be
/// stale): what the stream frames and centres on. The file's header when
/// it cannot be rebuilt.
fn with_bounds(header: &las::Header, cube: &Cube) -> las::Header {
    let rebuilt = || -> las::Result<las::Header> {
        let mut raw = header.clone().into_raw()?;
        (raw.min_x, raw.min_y, raw.min_z) = (cube.lo.x, cube.lo.y, cube.lo.z);
        (raw.max_x, raw.max_y, raw.max_z) = (cube.hi.x, cube.hi.y, cube.hi.z);
        let mut builder = las::Builder::new(raw)?;
        builder.vlrs = header.vlrs().clone();
        builder.evlrs = header.evlrs().clone();
        builder.into_header()
    };
    rebuilt().unwrap_or_else(|_| header.clone())
}

/// Whether `file` is drawn node by node under `budget`: a COPC file or a
/// URL always; another point file ([`header_points`]) when the budget is a number of points
/// below the points its header counts (under `all`, none, or a budget
/// that holds every point, it is drawn whole, as before).
pub fn drawn_by_nodes(file: &Path, budget: StreamBudget) -> bool {
    match budget {
        _ if is_streamed(file) => true,
        StreamBudget::Points(n) => header_points(file).is_some_and(|points| (n as u64) < points),
        _ => false,
    }
}

/// Whether the viewer draws `file` node by node under `budget`: as
/// [`drawn_by_nodes`], the default budget counting as its 1,000,000
/// points (a point file of more is held as a tree of nodes).
pub fn window_draws_by_nodes(file: &Path, budget: StreamBudget) -> bool {
    let budget = match budget {
        StreamBudget::Default => StreamBudget::Points(super::budget::DEFAULT_BUDGET),
        other => other,
    };
    drawn_by_nodes(file, budget)
}

/// Opens a file [`drawn_by_nodes`]: streamed from its bytes (COPC, a URL),
/// or held whole.
pub fn open_nodes(file: &Path, options: StreamOptions) -> Result<CopcStream, CopcError> {
    if is_streamed(file) {
        CopcStream::open(&file.to_string_lossy(), options)
    } else {
        CopcStream::open_whole(file, options)
    }
}

/// The points a point file says it holds: a LAS or LAZ file's header, a
/// PLY file's vertex element, an E57 file's scans. `None` for other files,
/// for files whose header does not read, and for PLY files drawn whole
/// whatever the budget: a mesh (its faces), and 3D Gaussians (their
/// scales, not a radius, size a coarse node's splats).
pub fn header_points(file: &Path) -> Option<u64> {
    use crate::formats::{Reader, format_of};
    if is_streamed(file) {
        return None;
    }
    match format_of(file)?.reader {
        Reader::Las => las_file::open(file).ok().map(|(reader, _)| reader.header().number_of_points()),
        Reader::Ply => ply_header(file).as_ref().and_then(point_vertices),
        Reader::E57 => {
            let reader = e57::E57Reader::from_file(file).ok()?;
            Some(reader.pointclouds().iter().map(|s| s.records).sum())
        }
        Reader::Copc | Reader::Scene | Reader::Volume => None,
    }
}

/// The header of the PLY file at `file`, when it reads.
fn ply_header(file: &Path) -> Option<ply::header::Header> {
    use std::io::Read;
    // A header is text; a megabyte holds any real one with its comments.
    let mut head = Vec::new();
    std::fs::File::open(file).ok()?.take(1 << 20).read_to_end(&mut head).ok()?;
    ply::header::parse(&head).ok()
}

/// The vertices a PLY header counts, when they are points: no faces, and
/// not 3D Gaussians.
fn point_vertices(header: &ply::header::Header) -> Option<u64> {
    let count = |name: &str| header.elements.iter().filter(|e| e.name == name).map(|e| e.count as u64).sum::<u64>();
    let vertex = header.elements.iter().find(|e| e.name == "vertex")?;
    let gaussian = crate::cloud::gaussians::PROPERTIES.iter().all(|p| vertex.property(p).is_some());
    (count("face") == 0 && count("tristrips") == 0 && !gaussian).then(|| count("vertex"))
}

/// The properties of a PLY header's vertex element.
fn vertex_properties(header: &ply::header::Header) -> u64 {
    header.elements.iter().filter(|e| e.name == "vertex").map(|e| e.properties.len() as u64).sum()
}
