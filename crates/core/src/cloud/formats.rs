//! From a file of any supported format to the loader's input: vertex
//! columns (positions, and normals, colours, radii and opacity where the
//! file has them), the other per-point attributes, and what the file says
//! beyond its points. PLY through [`super::ply`], LAS and LAZ through
//! [`super::las_file`], E57 through [`super::e57_file`], by extension.

use std::path::Path;

use super::CloudError;
use super::attributes::{Attributes, Values};
pub use super::file_info::FileInfo;
use super::gaussians;
use super::ply::{self, PlyData, Scalar};

/// Reads `path` by its format in the registry ([`crate::formats`]): LAS,
/// LAZ and COPC (a COPC file opened whole is a LAZ file), E57, and PLY,
/// which is also tried on a name with no known extension.
pub fn read(path: &Path) -> Result<(PlyData, Attributes, FileInfo), CloudError> {
    use crate::formats::{self, Reader};
    let format = formats::format_of(path);
    if formats::is_url(&path.to_string_lossy()) && !format.is_some_and(|f| f.streamed) {
        let streamed = formats::names_with_extensions(|f| f.streamed);
        return Err(CloudError::content(
            path,
            format!("only {streamed} files are read over http(s); download this one first"),
        ));
    }
    match format.map(|f| f.reader) {
        Some(Reader::Las | Reader::Copc) => super::las_file::read(path),
        Some(Reader::E57) => super::e57_file::read(path),
        Some(Reader::Ply) | None => {
            let bytes = crate::input::read(path, None).map_err(|e| CloudError::io(path, e))?;
            if format.is_none() && !bytes.starts_with(b"ply") {
                let known = formats::names_with_extensions(formats::is_cloud_opened_whole);
                return Err(CloudError::content(path, format!("not a point cloud format pointblend reads: {known}")));
            }
            let mut data = ply::parse(path, &bytes, &is_wanted)?;
            drop(bytes);
            let attributes = ply_attributes(&mut data);
            Ok((data, attributes, FileInfo::default()))
        }
        Some(Reader::Scene | Reader::Volume) => {
            let name = format.map_or("", |f| f.name);
            let known = formats::names(formats::is_cloud_opened_whole, "or");
            Err(CloudError::content(path, format!("a {name}, not a point cloud; this command reads {known}")))
        }
    }
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
pub fn ply_attributes(data: &mut PlyData) -> Attributes {
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
