//! PLY reading: the header through `ply-rs-bw`, the body into typed columns.
//!
//! Only the columns a caller asks for are kept (as f64, so doubles and UTM
//! coordinates survive until re-centring); every other property is skipped.
//! Faces become triangles by fan triangulation. Binary bodies go through a
//! hand-written decoder ([`binary`]) because a generic per-property element
//! map costs ~50x more per vertex; ASCII bodies use `ply-rs-bw` ([`ascii`]).
//! Every count in the header is checked against the bytes that follow before
//! anything is allocated, so a lying header gives an error, not an OOM.

mod ascii;
mod binary;
mod scalar;

use std::collections::HashMap;
use std::io::Cursor;
use std::path::Path;

use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{DefaultElement, Encoding, PropertyType};

use super::CloudError;
pub use scalar::Scalar;

/// A property of an element, as declared in the header.
#[derive(Debug, Clone)]
pub struct PropertySpec {
    pub name: String,
    pub kind: PropertyKind,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PropertyKind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

/// An element of the header (`vertex`, `face`, `range_grid`, ...).
#[derive(Debug, Clone)]
pub struct ElementSpec {
    pub name: String,
    pub count: usize,
    pub properties: Vec<PropertySpec>,
}

impl ElementSpec {
    fn property(&self, name: &str) -> Option<&PropertySpec> {
        self.properties.iter().find(|p| p.name == name)
    }

    /// Smallest size in bytes one binary record can have.
    fn min_record_bytes(&self) -> usize {
        self.properties
            .iter()
            .map(|p| match p.kind {
                PropertyKind::Scalar(s) => s.size(),
                PropertyKind::List { count, .. } => count.size(),
            })
            .sum()
    }

    /// Byte size of every record when the element has no lists.
    fn fixed_record_bytes(&self) -> Option<usize> {
        self.properties
            .iter()
            .map(|p| match p.kind {
                PropertyKind::Scalar(s) => Some(s.size()),
                PropertyKind::List { .. } => None,
            })
            .sum()
    }
}

/// The decoded content of a PLY file.
#[derive(Debug, Default)]
pub struct PlyData {
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
}

/// Names of the face element's index list, in order of preference.
const FACE_LIST_NAMES: [&str; 2] = ["vertex_indices", "vertex_index"];

/// Reads `bytes` (the whole file at `path`), keeping the vertex properties
/// for which `wanted` returns true.
pub fn parse(path: &Path, bytes: &[u8], wanted: &dyn Fn(&str) -> bool) -> Result<PlyData, CloudError> {
    if !bytes.starts_with(b"ply") {
        return Err(CloudError::format(path, "the file does not start with 'ply'"));
    }
    let mut reader = Reader::new(Cursor::new(bytes));
    let parser = Parser::<DefaultElement>::new();
    let header = parser.read_header(&mut reader).map_err(|e| CloudError::format(path, format!("bad header: {e}")))?;
    let body_start = reader.into_inner().position() as usize;
    let body = &bytes[body_start.min(bytes.len())..];

    let encoding = match header.encoding {
        Encoding::Ascii => "ascii",
        Encoding::BinaryLittleEndian => "binary_little_endian",
        Encoding::BinaryBigEndian => "binary_big_endian",
    };
    let mut elements = Vec::new();
    for (name, def) in &header.elements {
        let mut properties = Vec::new();
        for (pname, pdef) in &def.properties {
            let kind = match &pdef.data_type {
                PropertyType::Scalar(s) => PropertyKind::Scalar(Scalar::from_ply(s)),
                PropertyType::List(c, i) => {
                    let count = Scalar::from_ply(c);
                    if count.is_float() {
                        return Err(CloudError::format(
                            path,
                            format!("element '{name}' list '{pname}' has a floating-point count type"),
                        ));
                    }
                    PropertyKind::List { count, item: Scalar::from_ply(i) }
                }
            };
            properties.push(PropertySpec { name: pname.clone(), kind });
        }
        elements.push(ElementSpec { name: name.clone(), count: def.count, properties });
    }

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

    let mut data = PlyData {
        encoding: encoding.to_string(),
        comments: header.comments.clone(),
        vertex_count: vertex.count,
        ..Default::default()
    };
    for p in &vertex.properties {
        if let PropertyKind::Scalar(s) = p.kind {
            data.vertex_types.insert(p.name.clone(), s);
        }
    }
    let keep = |element: &ElementSpec, property: &PropertySpec| -> bool {
        match element.name.as_str() {
            "vertex" => matches!(property.kind, PropertyKind::Scalar(_)) && wanted(&property.name),
            "face" => {
                matches!(property.kind, PropertyKind::List { .. }) && FACE_LIST_NAMES.contains(&property.name.as_str())
            }
            _ => false,
        }
    };

    let mut sink = ColumnSink::default();
    match header.encoding {
        Encoding::Ascii => ascii::decode(path, body, &header, &elements, &keep, &mut sink)?,
        Encoding::BinaryLittleEndian => binary::decode(path, body, false, &elements, &keep, &mut sink)?,
        Encoding::BinaryBigEndian => binary::decode(path, body, true, &elements, &keep, &mut sink)?,
    }

    data.vertex_columns = sink.vertex_columns;
    data.face_count = elements.iter().find(|e| e.name == "face").map_or(0, |e| e.count);
    data.degenerate_faces = sink.degenerate_faces;
    let n = data.vertex_count as u64;
    if let Some(bad) = sink.triangles.iter().flatten().find(|&&i| i as u64 >= n) {
        return Err(CloudError::content(
            path,
            format!("a face refers to vertex {bad}, but there are only {n} vertices"),
        ));
    }
    if sink.negative_index {
        return Err(CloudError::content(path, "a face has a negative vertex index"));
    }
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
    negative_index: bool,
}

impl ColumnSink {
    /// Adds one face given as a polygon of vertex indices.
    fn push_face(&mut self, indices: &[i64]) {
        if indices.len() < 3 {
            self.degenerate_faces += 1;
            return;
        }
        if indices.iter().any(|&i| i < 0) {
            self.negative_index = true;
            return;
        }
        let clamp = |i: i64| u32::try_from(i).unwrap_or(u32::MAX);
        for k in 1..indices.len() - 1 {
            self.triangles.push([clamp(indices[0]), clamp(indices[k]), clamp(indices[k + 1])]);
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
                "header declares {} '{}' records (at least {} bytes) but only {} bytes follow; the file is truncated or the header is wrong",
                element.count,
                element.name,
                needed.map_or("more than 2^64".to_string(), |n| n.to_string()),
                available
            ),
        )),
    }
}
