//! PDAL's virtual point cloud (`.vpc`): a STAC FeatureCollection whose
//! features are the files of one dataset (a city as hundreds of COPC
//! tiles), which QGIS opens as one layer and pointblend too
//! ([`super::layers`]).
//!
//! Each feature names its file in `assets.data.href`, taken relative to
//! the `.vpc` file (an absolute path or an http(s) URL as it is). Its
//! bounds, in the files' own coordinates, come from
//! `properties["proj:bbox"]` (PDAL writes the native CRS's box there), else
//! from `bbox`; either may be 2D (4 numbers) or 3D (6). `geometry` may be
//! null. `pc:count` and `proj:epsg`, where given, are read for `info`.
//! Anything else is read past.

use std::path::{Path, PathBuf};

use glam::DVec3;
use serde_json::Value;

/// One file of a virtual point cloud.
#[derive(Debug, Clone, PartialEq)]
pub struct VpcFile {
    pub path: PathBuf,
    /// Its bounds (min, max) in file coordinates, if the feature gives them;
    /// a 2D box spans every height.
    pub bounds: Option<(DVec3, DVec3)>,
    /// Its points, as `properties["pc:count"]` states them.
    pub points: Option<u64>,
    /// Its CRS's EPSG code, as `properties["proj:epsg"]` states it.
    pub epsg: Option<u32>,
}

/// Whether `path` names a virtual point cloud.
pub fn is_vpc(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("vpc"))
}

/// A box of 4 or 6 numbers.
fn bounds_of(value: &Value) -> Option<(DVec3, DVec3)> {
    let numbers: Vec<f64> = value.as_array()?.iter().map(Value::as_f64).collect::<Option<_>>()?;
    let (min, max) = match numbers[..] {
        [x0, y0, x1, y1] => (DVec3::new(x0, y0, f64::NEG_INFINITY), DVec3::new(x1, y1, f64::INFINITY)),
        [x0, y0, z0, x1, y1, z1] => (DVec3::new(x0, y0, z0), DVec3::new(x1, y1, z1)),
        _ => return None,
    };
    (min.cmple(max).all() && min.truncate().is_finite() && max.truncate().is_finite()).then_some((min, max))
}

/// Reads the `.vpc` file at `path`: its files, in order, or why it cannot be read.
pub fn read(path: &Path) -> Result<Vec<VpcFile>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    let json: Value = serde_json::from_str(&text).map_err(|e| format!("not JSON: {e}"))?;
    if json.get("type").and_then(Value::as_str) != Some("FeatureCollection") {
        return Err("not a virtual point cloud: its \"type\" is not \"FeatureCollection\"".into());
    }
    let features = json.get("features").and_then(Value::as_array).ok_or("it has no \"features\" array")?;
    let folder = path.parent().unwrap_or(Path::new("."));
    let mut files = Vec::with_capacity(features.len());
    for (k, feature) in features.iter().enumerate() {
        let href = feature
            .pointer("/assets/data/href")
            .and_then(Value::as_str)
            .ok_or_else(|| format!("feature {} has no assets.data.href", k + 1))?;
        let href = href.strip_prefix("./").unwrap_or(href);
        let is_url = href.starts_with("http://") || href.starts_with("https://");
        let path = if is_url || Path::new(href).is_absolute() { PathBuf::from(href) } else { folder.join(href) };
        let bounds = feature
            .pointer("/properties/proj:bbox")
            .and_then(bounds_of)
            .or_else(|| feature.get("bbox").and_then(bounds_of));
        let points = feature.pointer("/properties/pc:count").and_then(Value::as_u64);
        let epsg = feature.pointer("/properties/proj:epsg").and_then(Value::as_u64).and_then(|c| u32::try_from(c).ok());
        files.push(VpcFile { path, bounds, points, epsg });
    }
    if files.is_empty() {
        return Err("it lists no files (\"features\" is empty)".into());
    }
    Ok(files)
}

/// How a `.vpc` names `path`: a URL as it is, a file by its absolute path.
pub fn href(path: &Path) -> std::io::Result<String> {
    let text = path.to_string_lossy();
    if text.starts_with("http://") || text.starts_with("https://") {
        return Ok(text.into_owned());
    }
    Ok(std::fs::canonicalize(path)?.to_string_lossy().into_owned())
}

/// Writes a virtual point cloud at `path` listing `hrefs` in order (absolute
/// paths or URLs, as [`read`] takes them; no bounds: they are read from the files).
pub fn write(hrefs: &[String], path: &Path) -> std::io::Result<()> {
    let features: Vec<Value> = hrefs
        .iter()
        .map(|href| {
            serde_json::json!({"type": "Feature", "geometry": null, "properties": {}, "assets": {"data": {"href": href}}})
        })
        .collect();
    let collection = serde_json::json!({"type": "FeatureCollection", "features": features});
    let text = serde_json::to_string_pretty(&collection).map_err(std::io::Error::other)?;
    std::fs::write(path, text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_vpc_lists_its_files_relative_to_itself_with_their_boxes() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("city.vpc");
        let text = r#"{"type": "FeatureCollection", "features": [
            {"type": "Feature", "geometry": null, "bbox": [-123.1, 44.0, 100, -123.0, 44.1, 200],
             "properties": {"proj:bbox": [637000.5, 849000, 10, 637100, 849100, 60], "pc:count": 1234, "proj:epsg": 2992},
             "assets": {"data": {"href": "./tiles/a.copc.laz", "roles": ["data"]}}},
            {"type": "Feature", "geometry": {"type": "Polygon", "coordinates": []}, "bbox": [1, 2, 3, 4],
             "properties": {}, "assets": {"data": {"href": "/data/b.laz"}}}
        ]}"#;
        std::fs::write(&path, text).unwrap();
        let files = read(&path).unwrap();
        assert_eq!(files[0].path, dir.path().join("tiles/a.copc.laz"));
        assert_eq!(files[0].bounds, Some((DVec3::new(637000.5, 849000.0, 10.0), DVec3::new(637100.0, 849100.0, 60.0))));
        assert_eq!((files[0].points, files[0].epsg), (Some(1234), Some(2992)));
        assert_eq!((files[1].points, files[1].epsg), (None, None));
        assert_eq!(files[1].path, PathBuf::from("/data/b.laz"));
        assert_eq!(files[1].bounds.unwrap().0.truncate(), glam::DVec2::new(1.0, 2.0));
        for bad in [
            r#"{"type": "Feature"}"#,
            r#"{"type": "FeatureCollection", "features": []}"#,
            "[1",
            r#"{"type": "FeatureCollection", "features": [{"assets": {}}]}"#,
        ] {
            std::fs::write(&path, bad).unwrap();
            assert!(read(&path).is_err(), "{bad}");
        }
    }
}
