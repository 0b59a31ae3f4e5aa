//! From a PLY file to a repaired [`PointCloud`].
//!
//! Positions are re-centred in f64 on the bounding-box centre (`placement.rs`) before they
//! become f32, so UTM-sized coordinates keep their millimetres. Attributes the
//! file lacks are derived: normals from mesh faces (area-weighted) or by PCA
//! over neighbours, radii from 3D Gaussian scales or from neighbour distances,
//! colours from `red/green/blue` (any type) or from the Gaussian SH DC term.
//! Bad records are skipped or repaired, and each kind is counted in the report.
//! Splats that repeat another exactly are merged into it before estimation
//! ([`super::duplicates`]), with a counted warning.

use std::path::Path;
use std::time::Instant;

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::attributes::Attributes;
use super::colour::to_u8;
use super::estimate;
use super::formats::{ALPHA_NAMES, COLOR_NAMES, FileInfo, NORMAL_NAMES, is_wanted, ply_attributes};
use super::gaussians;
pub use super::given_radii::FILE_RADIUS_OVER_MEDIAN;
use super::given_radii::clamp_given_radii;
use super::load_options::use_estimates;
pub use super::load_options::{Estimates, LoadOptions};
use super::mesh::face_vertex_normals;
use super::placement::{Frame, place};
use super::ply::{self, PointColumns, Scalar};
use super::{CloudError, LoadReport, PointCloud, Provenance};

/// Colour used when a file has none (a light clay tone).
pub const DEFAULT_COLOR: [u8; 3] = [200, 190, 170];

/// Loads `path` with default options.
pub fn load(path: &Path) -> Result<(PointCloud, LoadReport), CloudError> {
    load_with(path, &LoadOptions::default())
}

/// Loads `path` (PLY, LAS, LAZ or E57, by extension), estimating and repairing as `options` say.
pub fn load_with(path: &Path, options: &LoadOptions) -> Result<(PointCloud, LoadReport), CloudError> {
    let started = Instant::now();
    let (data, attributes, info) = super::formats::read(path)?;
    let decode_seconds = started.elapsed().as_secs_f64();
    build(path, data, attributes, info, decode_seconds, options).map(|(cloud, report, _)| (cloud, report))
}

/// The cloud of columns read elsewhere (a streamed file's nodes), named
/// `name` in messages, built as a file's are, with the splat each record
/// became (`u32::MAX` for those skipped).
pub(crate) fn from_columns(
    name: &Path,
    data: PointColumns,
    (attributes, info): (Attributes, FileInfo),
    options: &LoadOptions,
) -> Result<(PointCloud, LoadReport, Vec<u32>), CloudError> {
    build(name, data, attributes, info, 0.0, options)
}

/// Loads the mesh at `path` and samples `count` splats uniformly over its
/// surface (area-weighted), with face normals and radii from the sample spacing.
pub fn load_surface_samples(
    path: &Path,
    count: usize,
    options: &LoadOptions,
) -> Result<(PointCloud, LoadReport), CloudError> {
    let bytes = crate::input::read(path, None).map_err(|e| CloudError::io(path, e))?;
    let started = Instant::now();
    let mut data = ply::parse(path, &bytes, &|name| matches!(name, "x" | "y" | "z"))?;
    drop(bytes);
    let decode_seconds = started.elapsed().as_secs_f64();
    if data.triangles.is_empty() {
        return Err(CloudError::content(path, "the file has no faces, so there is no surface to sample"));
    }
    let xyz = columns(&data, &["x", "y", "z"]).ok_or_else(|| CloudError::content(path, "vertices have no x/y/z"))?;
    let vertices: Vec<DVec3> = (0..data.vertex_count).map(|i| DVec3::new(xyz[0][i], xyz[1][i], xyz[2][i])).collect();
    let bad_faces = data.triangles.iter().filter(|t| t.iter().any(|&i| !vertices[i as usize].is_finite())).count();
    let (points, normals) = super::mesh::sample_surface(&vertices, &data.triangles, count)
        .map_err(|bytes| CloudError::content(path, format!("cannot allocate {bytes} bytes for {count} samples")))?;
    if points.is_empty() {
        return Err(CloudError::content(path, "every face has zero area or a vertex that is not finite"));
    }
    let sampled = points.len();
    data.vertex_columns.clear();
    for (name, axis) in [("x", 0), ("y", 1), ("z", 2)] {
        data.vertex_columns.insert(name.into(), points.iter().map(|p| p[axis]).collect());
    }
    for (name, axis) in [("nx", 0), ("ny", 1), ("nz", 2)] {
        data.vertex_columns.insert(name.into(), normals.iter().map(|n| n[axis]).collect());
    }
    data.vertex_count = sampled;
    data.triangles.clear();
    let (cloud, mut report, _) =
        build(path, data, Attributes::default(), FileInfo::default(), decode_seconds, options)?;
    report.normals = Provenance::FromFaces;
    if bad_faces > 0 {
        report.warnings.push(format!("{bad_faces} faces with a NaN or infinite vertex were not sampled"));
    }
    Ok((cloud, report))
}

/// Loads the mesh at `path` as its vertices' splats (as [`load_with`] does)
/// and its triangles over those splats (indices into the cloud).
///
/// Faces that name a vertex the file lacks, and triangles with zero area,
/// a repeated vertex or a vertex that is not finite, are skipped with a
/// warning that counts them; a triangle wound against the file's own vertex
/// normals is turned, and counted too, since back-face culling reads the
/// winding. A file with no faces, or with none
/// left, is an error.
pub fn load_mesh(path: &Path, options: &LoadOptions) -> Result<(PointCloud, Vec<[u32; 3]>, LoadReport), CloudError> {
    let bytes = crate::input::read(path, None).map_err(|e| CloudError::io(path, e))?;
    let started = Instant::now();
    let mut data = ply::parse(path, &bytes, &is_wanted)?;
    drop(bytes);
    let attributes = ply_attributes(&mut data);
    if data.triangles.is_empty() {
        let why = if data.face_count > 0 { "none of its faces is usable" } else { "the file has no faces" };
        return Err(CloudError::content(
            path,
            format!("{why}; a mesh or hybrid object needs triangles (`ply =` reads a point cloud)"),
        ));
    }
    let file_triangles = data.triangles.clone();
    let decode_seconds = started.elapsed().as_secs_f64();
    let (cloud, mut report, splat_of) = build(path, data, attributes, FileInfo::default(), decode_seconds, options)?;
    let splat_of = |v: u32| Some(splat_of[v as usize]).filter(|&s| s != u32::MAX);
    let mut triangles = Vec::with_capacity(file_triangles.len());
    let mut degenerate = 0;
    let mut turned = 0;
    let own_normals = report.normals == Provenance::FromFile;
    for t in &file_triangles {
        let mapped = [splat_of(t[0]), splat_of(t[1]), splat_of(t[2])];
        let [Some(a), Some(b), Some(c)] = mapped else {
            degenerate += 1;
            continue;
        };
        let [pa, pb, pc] = [a, b, c].map(|i| cloud.positions[i as usize]);
        let area2 = (pb - pa).cross(pc - pa).length();
        if a == b || b == c || a == c || area2.is_nan() || area2 <= 0.0 {
            degenerate += 1;
            continue;
        }
        // Facing (and so culling) follows the winding: where the file gives its own
        // normals, wind the triangle as they face. (Normals made from the faces
        // follow the winding already, up to folds, which must not turn.)
        let normals = cloud.normals[a as usize] + cloud.normals[b as usize] + cloud.normals[c as usize];
        if own_normals && (pb - pa).cross(pc - pa).dot(normals) < 0.0 {
            turned += 1;
            triangles.push([a, c, b]);
        } else {
            triangles.push([a, b, c]);
        }
    }
    if turned > 0 {
        report.warnings.push(format!(
            "{turned} triangles were wound against their vertices' normals and were turned to face as they do"
        ));
    }
    if degenerate > 0 {
        report.warnings.push(format!(
            "{degenerate} triangles with zero area, a repeated vertex or a vertex that is not finite were skipped"
        ));
    }
    if triangles.is_empty() {
        return Err(CloudError::content(
            path,
            "every triangle has zero area, a repeated vertex or a vertex that is not finite",
        ));
    }
    Ok((cloud, triangles, report))
}

fn columns<'a>(data: &'a PointColumns, names: &[&str; 3]) -> Option<[&'a Vec<f64>; 3]> {
    let c = &data.vertex_columns;
    Some([c.get(names[0])?, c.get(names[1])?, c.get(names[2])?])
}

/// The cloud and report of parsed `data`, in stages: positions, mesh faces,
/// re-centring, normals, colours, opacity, radii, merging, estimation; and
/// the splat each file vertex became (`u32::MAX` for those skipped).
fn build(
    path: &Path,
    data: PointColumns,
    attributes: Attributes,
    info: FileInfo,
    decode_seconds: f64,
    options: &LoadOptions,
) -> Result<(PointCloud, LoadReport, Vec<u32>), CloudError> {
    let n = data.vertex_count;
    let mut warnings = info.warnings;
    let (positions, mut keep) = read_positions(path, &data, &mut warnings)?;
    let face_normals = drop_off_surface_vertices(&data, &positions, &mut keep, &mut warnings);
    let kept: Vec<usize> = (0..n).filter(|&i| keep[i]).collect();
    if kept.is_empty() {
        return Err(CloudError::content(path, "the file has no vertex with finite coordinates"));
    }
    let (mut cloud, frame) = place(&positions, &kept, options.origin, &mut warnings);

    let source = Source {
        data: &data,
        kept: &kept,
        unit: frame.unit,
        gaussians: gaussians::PROPERTIES.iter().all(|g| data.vertex_columns.contains_key(*g)),
    };
    cloud.normals = vec![Vec3::ZERO; kept.len()];
    cloud.radii = vec![0.0; kept.len()];
    let mut needs = Needs { normal: vec![true; kept.len()], radius: vec![true; kept.len()] };
    let (mut normals_from, mut radii_from) =
        source.normals(&mut cloud, &mut needs, face_normals.as_deref(), &mut warnings);
    let colours_from = source.colours(&mut cloud);
    cloud.colourless = colours_from == Provenance::Default;
    let opacity_from = source.opacity(&mut cloud, &mut warnings);
    if let Some(from) = source.radii(&mut cloud, &mut needs, frame.diagonal, &mut warnings) {
        radii_from = from;
    }

    let before_merge = cloud.len();
    let merged_into = super::duplicates::merge_indexed(&mut cloud, &mut needs.normal, &mut needs.radius);
    let merged = before_merge - cloud.len();
    let records = super::duplicates::first_of_each(&merged_into, &kept, cloud.len());
    cloud.attributes = attributes.gather(&records);
    drop(attributes);
    // Estimates made before the build (a streamed file's nodes) fill what the file lacks;
    // copies were merged as if they were still to be estimated, as copies get one estimate.
    let given = options.estimated.as_deref().filter(|e| e.normals.len() == n && e.radii.len() == n);
    if let Some(given) = given {
        use_estimates(&mut cloud, (&mut needs.normal, &mut needs.radius), &records, given);
    }
    if merged > 0 {
        warnings.push(format!(
            "{merged} splats that repeat another's position, normal and radius exactly were merged into it (colour and opacity averaged)"
        ));
    }
    // What the report keeps of the file; its columns go before the
    // estimation, whose neighbour tables are the peak of a load.
    let file = (
        data.encoding.clone(),
        data.comments.clone(),
        data.elements
            .iter()
            .map(|e| (e.name.clone(), e.count, e.properties.iter().map(|p| p.name.clone()).collect()))
            .collect(),
        data.face_count + data.strip_triangles,
    );
    drop((data, positions, face_normals));
    let from_above = info.from_above || is_geo_terrain(&cloud, &frame);
    let options = &LoadOptions {
        estimate: super::estimate::EstimateOptions { orient_up: from_above, ..options.estimate.clone() },
        ..options.clone()
    };
    cloud.z_up = from_above || info.z_up;
    cloud.units = info.units.clone();
    let estimate_seconds = estimate_missing(&mut cloud, &needs, &frame, options, &mut warnings);
    if given.is_none() && !needs.normal.iter().any(|&b| b) && normals_from == Provenance::Estimated {
        normals_from = Provenance::FromFile;
    }

    let (encoding, comments, elements, faces_in_file) = file;
    let report = LoadReport {
        encoding,
        comments,
        elements,
        vertices_in_file: n,
        faces_in_file,
        normals: normals_from,
        radii: radii_from,
        colours: colours_from,
        opacity: opacity_from,
        warnings,
        decode_seconds,
        estimate_seconds,
        format_details: info.details,
        crs: info.crs,
    };
    debug_assert!(cloud.is_consistent());
    let mut splat_of = vec![u32::MAX; n];
    for (k, &file_vertex) in kept.iter().enumerate() {
        splat_of[file_vertex] = merged_into[k];
    }
    Ok((cloud, report, splat_of))
}

/// The file's vertex positions, and which of them are usable (finite, and
/// on a line that could be read); warns of the records the parser skipped.
fn read_positions(
    path: &Path,
    data: &PointColumns,
    warnings: &mut Vec<String>,
) -> Result<(Vec<DVec3>, Vec<bool>), CloudError> {
    let n = data.vertex_count;
    let xyz = columns(data, &["x", "y", "z"]).ok_or_else(|| CloudError::content(path, "vertices have no x/y/z"))?;
    // In parallel: on one thread these passes were a twentieth of a 2M-point file's load.
    let positions: Vec<DVec3> = (0..n).into_par_iter().map(|i| DVec3::new(xyz[0][i], xyz[1][i], xyz[2][i])).collect();
    let mut malformed = vec![false; n];
    for &i in &data.malformed_vertices {
        if let Some(m) = malformed.get_mut(i) {
            *m = true;
        }
    }
    let keep: Vec<bool> = positions.par_iter().zip(&malformed).map(|(p, m)| p.is_finite() && !m).collect();
    let non_finite = positions.par_iter().zip(&malformed).filter(|(p, m)| !p.is_finite() && !**m).count();
    skipped_records(data, non_finite, warnings);
    Ok((positions, keep))
}

/// Warns of the records skipped: `non_finite` vertices whose coordinates
/// are NaN or infinite, and what the parser of `data` could not read.
pub(crate) fn skipped_records(data: &PointColumns, non_finite: usize, warnings: &mut Vec<String>) {
    if non_finite > 0 {
        warnings.push(format!("{non_finite} vertices with NaN or infinite coordinates were skipped"));
    }
    if !data.malformed_vertices.is_empty() {
        warnings.push(format!(
            "{} vertex lines could not be read (a wrong number of values, or text that is not a number) and were skipped",
            data.malformed_vertices.len()
        ));
    }
    if data.malformed_records > 0 {
        warnings.push(format!("{} face or other lines could not be read and were skipped", data.malformed_records));
    }
    if data.faces_out_of_range > 0 {
        warnings.push(format!(
            "{} faces that refer to vertices the file does not have were skipped",
            data.faces_out_of_range
        ));
    }
}

/// Mesh faces: area-weighted vertex normals (per file vertex), and the
/// vertices no face uses are dropped from `keep`. `None` without faces.
fn drop_off_surface_vertices(
    data: &PointColumns,
    positions: &[DVec3],
    keep: &mut [bool],
    warnings: &mut Vec<String>,
) -> Option<Vec<DVec3>> {
    let mut face_normals: Option<Vec<DVec3>> = None;
    if !data.triangles.is_empty() {
        let (normals, used) = face_vertex_normals(positions, keep, &data.triangles);
        let unused = (0..keep.len()).filter(|&i| keep[i] && !used[i]).count();
        if unused > 0 {
            warnings.push(format!("{unused} vertices not used by any face were skipped (they lie off the surface)"));
        }
        for (k, u) in keep.iter_mut().zip(&used) {
            *k &= *u;
        }
        face_normals = Some(normals);
    }
    if data.degenerate_faces > 0 {
        warnings.push(format!("{} faces with fewer than 3 vertices were skipped", data.degenerate_faces));
    }
    face_normals
}

/// What the attributes are read from: the file's columns, the vertices kept
/// (splat k is file vertex `kept[k]`), and the unit lengths are divided by.
struct Source<'a> {
    data: &'a PointColumns,
    kept: &'a [usize],
    unit: f64,
    /// The file holds 3D Gaussian splats.
    gaussians: bool,
}

/// Which splats still need a normal or a radius estimated.
struct Needs {
    normal: Vec<bool>,
    radius: Vec<bool>,
}

impl Source<'_> {
    /// Normals (and, for Gaussians, radii): the Gaussian's own axes first,
    /// then the file's normals, then the faces'. Returns where normals and radii came from.
    fn normals(
        &self,
        cloud: &mut PointCloud,
        needs: &mut Needs,
        face_normals: Option<&[DVec3]>,
        warnings: &mut Vec<String>,
    ) -> (Provenance, Provenance) {
        let (data, kept, unit) = (self.data, self.kept, self.unit);
        let mut normals_from = Provenance::Estimated;
        let mut radii_from = Provenance::Estimated;
        if self.gaussians {
            normals_from = Provenance::FromGaussians;
            radii_from = Provenance::FromGaussians;
            let c = &data.vertex_columns;
            let mut bad = 0;
            for (k, &i) in kept.iter().enumerate() {
                let scales = [c["scale_0"][i], c["scale_1"][i], c["scale_2"][i]];
                let rotation = [c["rot_0"][i], c["rot_1"][i], c["rot_2"][i], c["rot_3"][i]];
                match gaussians::disc(scales, rotation) {
                    Some((normal, radius)) if ((radius as f64) / unit).is_finite() => {
                        cloud.normals[k] = normal;
                        cloud.radii[k] = (radius as f64 / unit) as f32;
                        needs.normal[k] = false;
                        needs.radius[k] = false;
                    }
                    _ => bad += 1,
                }
            }
            if bad > 0 {
                warnings.push(format!(
                    "{bad} Gaussians with degenerate scales or rotation got normals and radii from their neighbours"
                ));
            }
        } else if let Some(cols) = NORMAL_NAMES.iter().find_map(|names| columns(data, names)) {
            normals_from = Provenance::FromFile;
            let mut bad = 0;
            for (k, &i) in kept.iter().enumerate() {
                let v = Vec3::new(cols[0][i] as f32, cols[1][i] as f32, cols[2][i] as f32);
                let len = v.length();
                if len.is_finite() && len > 1e-12 {
                    cloud.normals[k] = v / len;
                    needs.normal[k] = false;
                } else {
                    bad += 1;
                }
            }
            if bad > 0 {
                warnings.push(format!("{bad} zero or non-finite normals were re-estimated from neighbours"));
            }
        } else if let Some(face_normals) = face_normals {
            normals_from = Provenance::FromFaces;
            let mut bad = 0;
            for (k, &i) in kept.iter().enumerate() {
                let v = face_normals[i];
                if v.length() > 0.0 && v.is_finite() {
                    cloud.normals[k] = v.normalize().as_vec3();
                    needs.normal[k] = false;
                } else {
                    bad += 1;
                }
            }
            if bad > 0 {
                warnings.push(format!("{bad} vertices whose faces have zero area got normals from neighbours"));
            }
        }
        (normals_from, radii_from)
    }

    /// Colours: the file's, else the Gaussians' SH DC term, else [`DEFAULT_COLOR`].
    fn colours(&self, cloud: &mut PointCloud) -> Provenance {
        let (data, kept) = (self.data, self.kept);
        let mut colours_from = Provenance::Default;
        cloud.colours = vec![DEFAULT_COLOR; kept.len()];
        if let Some((names, cols)) = COLOR_NAMES.iter().find_map(|names| Some((names, columns(data, names)?))) {
            colours_from = Provenance::FromFile;
            let scale = 255.0 / data.vertex_types.get(names[0]).map_or(1.0, |t: &Scalar| t.unit_max());
            let floats_above_one = data.vertex_types.get(names[0]).is_some_and(|t| t.is_float())
                && kept.iter().any(|&i| cols[0][i] > 1.0 || cols[1][i] > 1.0 || cols[2][i] > 1.0);
            // Float colours above 1 are taken as 0-255 values.
            let scale = if floats_above_one { 1.0 } else { scale };
            for (k, &i) in kept.iter().enumerate() {
                cloud.colours[k] = [0, 1, 2].map(|c| to_u8(cols[c][i] * scale));
            }
        } else if self.gaussians {
            colours_from = Provenance::FromGaussians;
            let c = &data.vertex_columns;
            for (k, &i) in kept.iter().enumerate() {
                cloud.colours[k] = gaussians::colour([c["f_dc_0"][i], c["f_dc_1"][i], c["f_dc_2"][i]]);
            }
        }
        colours_from
    }

    /// Opacity: an alpha column, else the Gaussians' logit, else opaque (and
    /// opaque too where every value is 0, an unused channel).
    fn opacity(&self, cloud: &mut PointCloud, warnings: &mut Vec<String>) -> Provenance {
        let (data, kept, gaussians) = (self.data, self.kept, self.gaussians);
        let gather = |col: &Vec<f64>| -> Vec<f64> { kept.iter().map(|&i| col[i]).collect() };
        let mut opacity_from = Provenance::Default;
        cloud.opacity = vec![1.0; kept.len()];
        let alpha_column =
            ALPHA_NAMES.iter().find(|n| data.vertex_columns.contains_key(**n) && !(gaussians && **n == "opacity"));
        if let Some(name) = alpha_column {
            opacity_from = Provenance::FromFile;
            let col = gather(&data.vertex_columns[*name]);
            let unit = data.vertex_types.get(*name).map_or(1.0, |t| t.unit_max());
            let mut clamped = 0;
            for (a, v) in cloud.opacity.iter_mut().zip(&col) {
                let x = v / unit;
                if !(0.0..=1.0).contains(&x) {
                    clamped += 1;
                }
                *a = if x.is_finite() { x.clamp(0.0, 1.0) as f32 } else { 1.0 };
            }
            if clamped > 0 {
                warnings.push(format!("{clamped} {name} values outside 0..1 were clamped"));
            }
        } else if gaussians {
            opacity_from = Provenance::FromGaussians;
            for (a, &i) in cloud.opacity.iter_mut().zip(kept) {
                *a = gaussians::opacity(data.vertex_columns["opacity"][i]);
            }
        }
        if cloud.opacity.iter().all(|&a| a <= 0.0) {
            warnings.push("alpha is 0 for every vertex (an unused channel); the cloud is rendered opaque".into());
            cloud.opacity.iter_mut().for_each(|a| *a = 1.0);
        }
        opacity_from
    }

    /// Radii from the file (Gaussians have theirs already), then every given
    /// radius clamped against outliers; `Some(FromFile)` when the file has radii.
    fn radii(
        &self,
        cloud: &mut PointCloud,
        needs: &mut Needs,
        diagonal: f32,
        warnings: &mut Vec<String>,
    ) -> Option<Provenance> {
        let mut radii_from = None;
        if let (Some(col), false) = (self.data.vertex_columns.get("radius"), self.gaussians) {
            radii_from = Some(Provenance::FromFile);
            let mut bad = 0;
            for (k, &i) in self.kept.iter().enumerate() {
                let r = (col[i] / self.unit) as f32;
                if r.is_finite() && r > 0.0 {
                    cloud.radii[k] = r;
                    needs.radius[k] = false;
                } else {
                    bad += 1;
                }
            }
            if bad > 0 {
                warnings.push(format!("{bad} radii that were zero, negative or not finite were re-estimated"));
            }
        }
        // A splat larger than a quarter of the model is no surface sample.
        let (clamped, limit) = clamp_given_radii(&mut cloud.radii, &needs.radius, diagonal);
        if clamped > 0 {
            warnings.push(format!(
                "{clamped} radii larger than {limit:.4e} ({FILE_RADIUS_OVER_MEDIAN}x the median radius, at most a quarter of the model's size) were clamped to it; such outliers would cover the view"
            ));
        }
        radii_from
    }
}

/// Whether a cloud is geo-referenced terrain (map coordinates, its centre
/// more than 10 km from the file origin, and flatter than it is wide), which
/// was scanned from above.
fn is_geo_terrain(cloud: &PointCloud, frame: &Frame) -> bool {
    let Some(b) = cloud.bounds() else { return false };
    let size = (b.max - b.min).as_dvec3() * frame.unit;
    let far = frame.origin.x.abs().max(frame.origin.y.abs()) > 1e4;
    far && size.z < 0.5 * size.x.max(size.y)
}

/// Estimates the normals and radii the splats still `need` (and where a
/// single-view scan was taken from); returns the seconds it took.
fn estimate_missing(
    cloud: &mut PointCloud,
    needs: &Needs,
    frame: &Frame,
    options: &LoadOptions,
    warnings: &mut Vec<String>,
) -> f64 {
    let estimate_started = Instant::now();
    let scanner = (-frame.origin / frame.unit).as_vec3();
    let estimated =
        estimate::complete(cloud, &needs.normal, &needs.radius, scanner, &options.estimate, options.progress);
    if estimated.isolated_points > 0 {
        warnings.push(format!(
            "{} points whose nearest neighbours all coincide with them got the median radius",
            estimated.isolated_points
        ));
    }
    if estimated.clamped_radii > 0 {
        warnings.push(format!(
            "{} outlier radii were clamped to {}x the median",
            estimated.clamped_radii,
            estimate::MAX_RADIUS_OVER_MEDIAN
        ));
    }
    if let Some(normal) = estimated.line_normal {
        warnings.push(format!(
            "the points lie on a line, so their normals are undefined; they were set to ({:.2}, {:.2}, {:.2}), across the line and towards the front view",
            normal.x, normal.y, normal.z
        ));
    }
    cloud.scanner_position = estimated.scanner_position;
    estimate_started.elapsed().as_secs_f64()
}
