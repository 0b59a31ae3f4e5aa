//! Writing clouds as binary PLY (`x y z nx ny nz radius red green blue
//! [alpha]`, then one property per attribute, in its own type).
//!
//! The file is written to a temporary file beside the target and renamed, so
//! a failed or interrupted write never leaves a partial file.

use std::io::{BufWriter, Write};
use std::path::Path;

use super::{CloudError, PointCloud, Values};

/// Writes `cloud` to `path` as binary little-endian PLY, atomically.
///
/// Positions get the cloud's origin added back (in f64), so the written file
/// has the same coordinates as the source. `alpha` is written only when some
/// splat is not opaque.
pub fn write_ply(cloud: &PointCloud, path: &Path, comments: &[String]) -> Result<(), CloudError> {
    let with_alpha = cloud.has_transparency();
    let target = crate::output::prepare(path).map_err(|e| CloudError::io(path, e))?;
    let dir = crate::output::folder_of(&target);
    let mut tmp = crate::output::Temporary::new_in(dir).map_err(|e| CloudError::io(path, e))?;
    {
        let mut w = BufWriter::new(tmp.as_file_mut());
        let io = |e| CloudError::io(path, e);
        let mut header = String::from("ply\nformat binary_little_endian 1.0\n");
        for c in comments {
            header.push_str(&format!("comment {}\n", c.replace(['\n', '\r'], " ")));
        }
        header.push_str(&format!("element vertex {}\n", cloud.len()));
        let unit = cloud.unit();
        let double = cloud.origin.iter().any(|&o| o.abs() > 1e4) || cloud.scale_exponent != 0;
        let ptype = if double { "double" } else { "float" };
        for p in ["x", "y", "z"] {
            header.push_str(&format!("property {ptype} {p}\n"));
        }
        for p in ["nx", "ny", "nz"] {
            header.push_str(&format!("property float {p}\n"));
        }
        header.push_str(&format!("property {ptype} radius\n"));
        for p in ["red", "green", "blue"] {
            header.push_str(&format!("property uchar {p}\n"));
        }
        if with_alpha {
            header.push_str("property uchar alpha\n");
        }
        for channel in &cloud.attributes.channels {
            let kind = match channel.values {
                Values::U8(_) => "uchar",
                Values::U16(_) => "ushort",
                Values::F32(_) => "float",
                Values::F64(_) => "double",
            };
            let name: String = channel.name.chars().map(|c| if c.is_whitespace() { '_' } else { c }).collect();
            header.push_str(&format!("property {kind} {name}\n"));
        }
        header.push_str("end_header\n");
        w.write_all(header.as_bytes()).map_err(io)?;
        let mut record = Vec::with_capacity(64);
        for i in 0..cloud.len() {
            record.clear();
            let p = cloud.positions[i];
            for (c, o) in p.to_array().iter().zip(cloud.origin) {
                let v = *c as f64 * unit + o;
                if double {
                    record.extend_from_slice(&v.to_le_bytes());
                } else {
                    record.extend_from_slice(&(v as f32).to_le_bytes());
                }
            }
            for v in cloud.normals[i].to_array() {
                record.extend_from_slice(&v.to_le_bytes());
            }
            let radius = cloud.radii[i] as f64 * unit;
            if double {
                record.extend_from_slice(&radius.to_le_bytes());
            } else {
                record.extend_from_slice(&(radius as f32).to_le_bytes());
            }
            record.extend_from_slice(&cloud.colours[i]);
            if with_alpha {
                record.push((cloud.opacity[i] * 255.0).round() as u8);
            }
            for channel in &cloud.attributes.channels {
                match &channel.values {
                    Values::U8(v) => record.push(v[i]),
                    Values::U16(v) => record.extend_from_slice(&v[i].to_le_bytes()),
                    Values::F32(v) => record.extend_from_slice(&v[i].to_le_bytes()),
                    Values::F64(v) => record.extend_from_slice(&v[i].to_le_bytes()),
                }
            }
            w.write_all(&record).map_err(io)?;
        }
        w.flush().map_err(io)?;
    }
    crate::output::make_readable(tmp.as_file()).map_err(|e| CloudError::io(path, e))?;
    tmp.persist(&target).map_err(|e| CloudError::io(path, e))?;
    Ok(())
}
