//! What the selection's and the profile's exports share: each file's
//! records read again in f64, as `convert` and `profile` read them
//! ([`crate::cloud::records::Records`]); those the colour panel's classes,
//! filters and kept or hidden selections keep and the tool takes; each file written to an output of
//! its own when there are several (`OUT-LAYER.ext`).

use std::path::{Path, PathBuf};

use glam::DVec3;

use crate::cloud::LoadOptions;
use crate::cloud::records::Records;

/// Reads each of `files`, keeps the records `style` keeps and `takes`
/// takes, and hands them to `write` with the file's output (it says whether
/// it wrote one); the records written, and the files written.
pub fn export_each(
    files: &[PathBuf],
    style: Option<&crate::style::Style>,
    output: &Path,
    takes: impl Fn(DVec3) -> bool,
    write: impl Fn(&Records, &[u32], &Path) -> Result<bool, String>,
) -> Result<(usize, Vec<String>), String> {
    let mut written = Vec::new();
    let mut total = 0;
    for file in files {
        let shown = crate::copc::shown(&file.to_string_lossy());
        crate::progress::stage(&format!("reading {shown}"));
        let records = Records::read(file, &LoadOptions::default()).map_err(|e| e.to_string())?;
        let kept = kept_by(&records, style).map_err(|e| format!("{shown}: {e}"))?;
        let keep: Vec<u32> = kept.into_iter().filter(|&i| takes(records.positions[i as usize])).collect();
        let out = output_of(output, file, files.len() > 1);
        crate::progress::stage(&format!("writing {}", out.display()));
        if write(&records, &keep, &out)? {
            total += keep.len();
            written.push(out.display().to_string());
        }
    }
    Ok((total, written))
}

/// The records `style`'s classes and filters keep (all without a style), as the view shows them.
fn kept_by(records: &Records, style: Option<&crate::style::Style>) -> Result<Vec<u32>, String> {
    match style {
        Some(s) => {
            let kept = crate::style::filter::kept_of(
                &records.attributes,
                records.len(),
                s.classes.as_deref(),
                &s.filters,
                s.returns,
            )?;
            Ok(crate::style::region::shown_by(&s.regions, kept, |i| records.positions[i]))
        }
        None => Ok((0..records.len() as u32).collect()),
    }
}

/// Where layer `file` of several is written: OUTPUT's stem, a dash and the layer's.
fn output_of(output: &Path, file: &Path, several: bool) -> PathBuf {
    if !several {
        return output.to_path_buf();
    }
    let stem = output.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let layer = crate::output::safe_stem(file);
    let extension = output.extension().map(|e| e.to_string_lossy().into_owned()).unwrap_or_default();
    output.with_file_name(format!("{stem}-{layer}.{extension}"))
}
