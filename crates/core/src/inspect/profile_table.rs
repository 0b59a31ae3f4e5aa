//! A profile's points as CSV: a header line, then one row per point of the
//! slab: `distance,offset,x,y,z` (f64, the CRS's units; see
//! [`super::profile`]) and every attribute of the file, by the names `info`
//! lists. Numbers are written in Rust's shortest form that reads back to
//! the same f64. The file is written beside its target and renamed.

use std::io::Write;
use std::path::Path;

use crate::cloud::records::Records;

use super::profile::Profile;

/// A CSV field: quoted when it holds a comma, a quote or a line break.
fn field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) { format!("\"{}\"", text.replace('"', "\"\"")) } else { text.to_string() }
}

/// Writes the rows of the records `slab` of `records` along `profile` to `path`.
pub fn write_csv(profile: &Profile, records: &Records, slab: &[u32], path: &Path) -> std::io::Result<()> {
    let target = crate::output::prepare(path)?;
    let tmp = crate::output::Temporary::new_in(crate::output::folder_of(&target))?;
    let mut out = std::io::BufWriter::new(tmp.reopen()?);
    let channels = &records.attributes.channels;
    let mut header = vec!["distance".to_string(), "offset".into(), "x".into(), "y".into(), "z".into()];
    header.extend(channels.iter().map(|c| field(&c.name)));
    writeln!(out, "{}", header.join(","))?;
    for &i in slab {
        let p = records.positions[i as usize];
        let (distance, offset) = profile.place(p);
        write!(out, "{distance},{offset},{},{},{}", p.x, p.y, p.z)?;
        for channel in channels {
            write!(out, ",{}", channel.values.get(i as usize))?;
        }
        writeln!(out)?;
    }
    out.into_inner().map_err(|e| e.into_error())?.sync_all()?;
    crate::output::make_readable(tmp.as_file())?;
    tmp.persist(&target)?;
    Ok(())
}
