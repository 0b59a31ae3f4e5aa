//! PLY reading: the header ([`header`]), then the body into typed columns.
//!
//! Only the columns a caller asks for are kept (as f64, so doubles and UTM
//! coordinates survive until re-centring); every other property is skipped.
//! Faces become triangles by fan triangulation, and `tristrips` elements
//! (Stanford's strips, `-1` restarts, alternating winding) become triangles
//! too. Binary bodies go through [`binary`], ASCII bodies through [`ascii`];
//! both are hand-written (see their module docs for why). Every count in the
//! header is checked against the bytes that follow before anything is
//! allocated, so a lying header gives an error, not an OOM.

mod ascii;
mod binary;
pub mod header;
mod scalar;

use std::collections::HashMap;
use std::path::Path;

use super::CloudError;
pub use header::{ElementSpec, Encoding, PropertyKind, PropertySpec};
pub use scalar::Scalar;

/// A point file decoded into named vertex columns (and faces), whatever its
/// format: the PLY reader fills it from the file's elements, and the LAS,
/// LAZ, COPC and E57 readers from their records, with PLY's element
/// vocabulary, so one builder ([`crate::cloud::load`]) makes every cloud.
#[derive(Debug, Default)]
pub struct PointColumns {
    pub encoding: String,
    pub comments: Vec<String>,
    pub elements: Vec<ElementSpec>,
    /// Requested vertex columns, by property name, one value per vertex.
    pub vertex_columns: HashMap<String, Vec<f64>>,
    /// Declared type of each vertex property.
    pub vertex_types: HashMap<String, Scalar>,
    pub vertex_count: usize,
    /// Triangles (fan-triangulated faces), indices checked against the vertices.
    pub triangles: Vec<[u32; 3]>,
    pub face_count: usize,
    /// Faces with fewer than three indices, skipped.
    pub degenerate_faces: usize,
    /// Triangles read from `tristrips` elements.
    pub strip_triangles: usize,
    /// Faces or strips that name a vertex that does not exist, skipped.
    pub faces_out_of_range: usize,
    /// Vertex records (ASCII) that could not be read; their values are NaN.
    pub malformed_vertices: Vec<usize>,
    /// Other records (ASCII) that could not be read, skipped.
    pub malformed_records: usize,
}

/// Names of the index list of `face` and `tristrips` elements, in order of preference.
const FACE_LIST_NAMES: [&str; 2] = ["vertex_indices", "vertex_index"];

/// Reads `bytes` (the whole file at `path`), keeping the vertex properties
/// for which `wanted` returns true.
pub fn parse(path: &Path, bytes: &[u8], wanted: &dyn Fn(&str) -> bool) -> Result<PointColumns, CloudError> {
    let header = header::parse(bytes).map_err(|e| CloudError::format(path, e))?;
    let body = &bytes[header.body_start.min(bytes.len())..];
    let elements = header.elements;
    let vertex = elements
        .iter()
        .find(|e| e.name == "vertex")
        .ok_or_else(|| CloudError::content(path, "the file has no 'vertex' element"))?;
    for axis in ["x", "y", "z"] {
        match vertex.property(axis).map(|p| p.kind) {
            Some(PropertyKind::Scalar(_)) => {}
            Some(PropertyKind::List { .. }) => {
                return Err(CloudError::content(path, format!("vertex property '{axis}' is a list")));
            }
            None => {
                return Err(CloudError::content(path, format!("vertices have no '{axis}' coordinate")));
            }
        }
    }

    let mut data = PointColumns {
        encoding: header.encoding.name().to_string(),
        comments: header.comments,
        vertex_count: vertex.count,
        ..Default::default()
    };
    for p in &vertex.properties {
        if let PropertyKind::Scalar(s) = p.kind {
            data.vertex_types.insert(p.name.clone(), s);
        }
    }
    // The first index list of a face or strip element is its polygon.
    let polygon_list = |element: &ElementSpec| {
        FACE_LIST_NAMES.iter().find(|n| matches!(element.property(n).map(|p| p.kind), Some(PropertyKind::List { .. })))
    };
    let keep = |element: &ElementSpec, property: &PropertySpec| -> bool {
        match element.name.as_str() {
            "vertex" => matches!(property.kind, PropertyKind::Scalar(_)) && wanted(&property.name),
            "face" | "tristrips" => polygon_list(element) == Some(&property.name.as_str()),
            _ => false,
        }
    };

    let mut sink = ColumnSink::default();
    match header.encoding {
        Encoding::Ascii => ascii::decode(path, body, &elements, &keep, &mut sink)?,
        Encoding::BinaryLittleEndian => binary::decode(path, body, false, &elements, &keep, &mut sink)?,
        Encoding::BinaryBigEndian => binary::decode(path, body, true, &elements, &keep, &mut sink)?,
    }

    data.vertex_columns = sink.vertex_columns;
    data.face_count = elements.iter().find(|e| e.name == "face").map_or(0, |e| e.count);
    data.strip_triangles = sink.strip_triangles;
    data.degenerate_faces = sink.degenerate_faces;
    data.malformed_vertices = sink.malformed_vertices;
    data.malformed_records = sink.malformed_records;
    let n = data.vertex_count as u64;
    let before = sink.triangles.len();
    sink.triangles.retain(|t| t.iter().all(|&i| (i as u64) < n));
    data.faces_out_of_range = sink.faces_out_of_range + (before - sink.triangles.len());
    data.triangles = sink.triangles;
    data.elements = elements;
    Ok(data)
}

/// Where the body decoders put what they keep.
#[derive(Default)]
struct ColumnSink {
    vertex_columns: HashMap<String, Vec<f64>>,
    triangles: Vec<[u32; 3]>,
    degenerate_faces: usize,
    /// Faces or strips with a negative index (other than a strip's -1 restart).
    faces_out_of_range: usize,
    strip_triangles: usize,
    /// Vertex records (ASCII) whose line could not be read.
    malformed_vertices: Vec<usize>,
    /// Other records (ASCII) whose line could not be read.
    malformed_records: usize,
}

impl ColumnSink {
    /// Adds the polygon list of one record of `element` (`face` or `tristrips`).
    fn push_list(&mut self, element: &str, indices: &[i64]) {
        if element == "tristrips" {
            self.push_strips(indices);
        } else {
            self.push_face(indices);
        }
    }

    /// Adds one face given as a polygon of vertex indices (fan triangulation).
    fn push_face(&mut self, indices: &[i64]) {
        if indices.len() < 3 {
            self.degenerate_faces += 1;
            return;
        }
        if indices.iter().any(|&i| i < 0 || i > u32::MAX as i64) {
            self.faces_out_of_range += 1;
            return;
        }
        for k in 1..indices.len() - 1 {
            self.triangles.push([indices[0] as u32, indices[k] as u32, indices[k + 1] as u32]);
        }
    }

    /// Adds triangle strips separated by -1: triangle i of a strip is
    /// (v_i, v_i+1, v_i+2), with the first two swapped for odd i so that every
    /// triangle keeps the strip's winding. Triangles with a repeated vertex
    /// (strips use them to turn corners) are dropped.
    fn push_strips(&mut self, indices: &[i64]) {
        for strip in indices.split(|&i| i == -1) {
            if strip.iter().any(|&i| i < 0 || i > u32::MAX as i64) {
                self.faces_out_of_range += 1;
                continue;
            }
            for (k, w) in strip.windows(3).enumerate() {
                let [a, b, c] = [w[0] as u32, w[1] as u32, w[2] as u32];
                if a == b || b == c || a == c {
                    continue;
                }
                self.triangles.push(if k % 2 == 0 { [a, b, c] } else { [b, a, c] });
                self.strip_triangles += 1;
            }
        }
    }
}

/// Checks that `count` records of at least `min_bytes` each fit in `available` bytes.
fn check_fits(path: &Path, element: &ElementSpec, min_bytes: usize, available: usize) -> Result<(), CloudError> {
    let needed = element.count.checked_mul(min_bytes.max(1));
    match needed {
        Some(needed) if needed <= available => Ok(()),
        _ => Err(CloudError::format(
            path,
            format!(
                "the header declares {} '{}' records, which need {} bytes, but only {} bytes follow; the file is truncated or the header is wrong",
                element.count,
                element.name,
                needed.map_or("more than 2^64".to_string(), |n| format!("at least {n}")),
                available
            ),
        )),
    }
}
