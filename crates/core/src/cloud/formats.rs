//! From a file of any supported format to the loader's input: vertex
//! columns (positions, and normals, colours, radii and opacity where the
//! file has them), the other per-point attributes, and what the file says
//! beyond its points. Each format's row in the registry
//! ([`crate::formats::FORMATS`]) names its reader; a name with no known
//! extension is tried as PLY.

use std::path::Path;

use super::CloudError;
use super::attributes::{Attributes, Values};
pub use super::file_info::FileInfo;
use super::gaussians;
use super::ply::{self, PointColumns, Scalar};
use crate::formats::{Format, Reader};

/// Reads `path` by the reader of its format's row in the registry
/// ([`crate::formats`]; a COPC file opened whole is a LAZ file), and as PLY
/// when its name has no known extension.
pub fn read(path: &Path) -> Result<(PointColumns, Attributes, FileInfo), CloudError> {
    use crate::formats;
    let format = formats::format_of(path);
    if formats::is_url(&path.to_string_lossy()) && !format.is_some_and(|f| f.streamed) {
        let streamed = formats::names_with_extensions(|f| f.streamed);
        return Err(CloudError::content(
            path,
            format!("only {streamed} files are read over http(s); download this one first"),
        ));
    }
    match format {
        Some(format) => match reader_of(format.reader) {
            Some(read) => read(path),
            None => {
                let known = formats::names(opened_whole, "or");
                Err(CloudError::content(
                    path,
                    format!("a {}, not a point cloud; this command reads {known}", format.name),
                ))
            }
        },
        None => {
            let bytes = crate::input::read(path, None).map_err(|e| CloudError::io(path, e))?;
            if !bytes.starts_with(b"ply") {
                let known = formats::names_with_extensions(opened_whole);
                return Err(CloudError::content(path, format!("not a point cloud format pointblend reads: {known}")));
            }
            parse_ply(path, bytes)
        }
    }
}

/// Reads a whole point file at a path into named columns, attributes and what the file says.
pub type ReadWhole = fn(&Path) -> Result<(PointColumns, Attributes, FileInfo), CloudError>;

/// The reader that opens a file of kind `reader` whole, for the kinds that
/// hold points (a COPC file opened whole is a LAZ file). The match has no
/// catch-all arm: a kind added to the registry is given its reader here.
pub fn reader_of(reader: Reader) -> Option<ReadWhole> {
    match reader {
        Reader::Ply => Some(read_ply),
        Reader::Las | Reader::Copc => Some(super::las_file::read),
        Reader::E57 => Some(super::e57_file::read),
        Reader::Scene | Reader::Volume => None,
    }
}

/// Clouds opened whole: every format with a reader here, but the streamed one.
pub fn opened_whole(format: &Format) -> bool {
    reader_of(format.reader).is_some() && !format.streamed
}

/// Reads the PLY file at `path` (the registry's PLY reader).
pub fn read_ply(path: &Path) -> Result<(PointColumns, Attributes, FileInfo), CloudError> {
    let bytes = crate::input::read(path, None).map_err(|e| CloudError::io(path, e))?;
    parse_ply(path, bytes)
}

/// The PLY file `bytes` read from `path`, as columns and attributes (the
/// bytes are freed before the attributes are made).
fn parse_ply(path: &Path, bytes: Vec<u8>) -> Result<(PointColumns, Attributes, FileInfo), CloudError> {
    let mut data = ply::parse(path, &bytes, &is_wanted)?;
    drop(bytes);
    let attributes = ply_attributes(&mut data);
    Ok((data, attributes, FileInfo::default()))
}

pub const NORMAL_NAMES: [[&str; 3]; 2] = [["nx", "ny", "nz"], ["normal_x", "normal_y", "normal_z"]];
pub const COLOR_NAMES: [[&str; 3]; 3] =
    [["red", "green", "blue"], ["r", "g", "b"], ["diffuse_red", "diffuse_green", "diffuse_blue"]];
/// Per-splat opacity columns, 0..1 (floats) or 0..max (integers). `opacity`
/// counts here unless the file is 3D Gaussian splats, whose `opacity` is a logit.
pub const ALPHA_NAMES: [&str; 3] = ["alpha", "diffuse_alpha", "opacity"];

/// The vertex properties that make the splats (position, normal, colour,
/// opacity, radius, Gaussian parameters); every other scalar is an attribute.
fn is_splat_property(name: &str) -> bool {
    matches!(name, "x" | "y" | "z" | "radius")
        || NORMAL_NAMES.iter().flatten().any(|n| *n == name)
        || COLOR_NAMES.iter().flatten().any(|n| *n == name)
        || ALPHA_NAMES.contains(&name)
        || gaussians::PROPERTIES.contains(&name)
}

/// Every vertex property but a Gaussian's higher spherical-harmonic terms
/// (45 columns no renderer here reads).
pub fn is_wanted(name: &str) -> bool {
    !name.starts_with("f_rest_")
}

/// Moves a PLY file's vertex scalars that are not splat properties (`scalar_*`,
/// `confidence`, `intensity`, `quality`, ...) out of `data` into attributes.
pub fn ply_attributes(data: &mut PointColumns) -> Attributes {
    let mut attributes = Attributes::default();
    let Some(vertex) = data.elements.iter().find(|e| e.name == "vertex") else { return attributes };
    let names: Vec<String> = vertex
        .properties
        .iter()
        .filter(|p| matches!(p.kind, ply::PropertyKind::Scalar(_)) && !is_splat_property(&p.name))
        .map(|p| p.name.clone())
        .collect();
    for name in names {
        let (Some(column), Some(kind)) = (data.vertex_columns.remove(&name), data.vertex_types.get(&name)) else {
            continue;
        };
        let values = match kind {
            Scalar::U8 => Values::U8(column.iter().map(|&v| v as u8).collect()),
            Scalar::U16 => Values::U16(column.iter().map(|&v| v as u16).collect()),
            Scalar::I8 | Scalar::I16 | Scalar::F32 => Values::F32(column.iter().map(|&v| v as f32).collect()),
            Scalar::I32 | Scalar::U32 | Scalar::F64 => Values::F64(column),
        };
        attributes.push(name, values);
    }
    attributes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_clouds_opened_whole_are_the_kinds_with_a_reader_but_the_streamed_one() {
        assert_eq!(crate::formats::names(opened_whole, "or"), "PLY, LAS, LAZ or E57");
        let copc = crate::formats::FORMATS.iter().find(|f| f.streamed).unwrap();
        assert!(reader_of(copc.reader).is_some() && !opened_whole(copc), "a COPC file opened whole is a LAZ file");
    }
}
