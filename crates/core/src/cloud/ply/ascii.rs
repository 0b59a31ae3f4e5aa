//! ASCII PLY body decoding: one record per line, values separated by blanks.
//!
//! Values are read with Rust's float parser, so `nan`, `inf` and `1e999`
//! (organised scans write `nan` for missing points) become NaN or infinity
//! and are repaired or skipped later like any bad binary value. A record
//! whose line has the wrong number of values, or a value that is not a number,
//! is a bad record: its values become NaN and it is counted, not fatal. A body
//! with fewer lines than the header declares is an error (a truncated file).

use std::path::Path;

use super::{ColumnSink, ElementSpec, PropertyKind, PropertySpec};
use crate::cloud::CloudError;

pub(super) fn decode(
    path: &Path,
    body: &[u8],
    elements: &[ElementSpec],
    keep: &dyn Fn(&ElementSpec, &PropertySpec) -> bool,
    sink: &mut ColumnSink,
) -> Result<(), CloudError> {
    // Every record takes at least one character and a line break: a lying
    // count fails here, before anything is allocated for it.
    let total = elements.iter().fold(0usize, |a, e| a.saturating_add(e.count));
    if total > body.len() / 2 + 1 {
        return Err(CloudError::format(
            path,
            format!("the header declares {total} records but the body has only {} bytes", body.len()),
        ));
    }
    let mut lines = body
        .split(|&b| b == b'\n')
        .enumerate()
        .map(|(i, l)| (i + 1, l.strip_suffix(b"\r").unwrap_or(l)))
        .filter(|(_, l)| l.iter().any(|b| !b.is_ascii_whitespace()));
    let mut values: Vec<f64> = Vec::new();
    let mut polygon: Vec<i64> = Vec::new();
    for element in elements {
        let kept: Vec<bool> = element.properties.iter().map(|p| keep(element, p)).collect();
        let is_vertex = element.name == "vertex";
        let mut columns: Vec<Vec<f64>> =
            kept.iter().map(|&k| if k && is_vertex { Vec::with_capacity(element.count) } else { Vec::new() }).collect();
        for record in 0..element.count {
            let Some((_, line)) = lines.next() else {
                return Err(CloudError::format(
                    path,
                    format!(
                        "the body ends after {record} of {} '{}' records (truncated file?)",
                        element.count, element.name
                    ),
                ));
            };
            values.clear();
            let mut not_numbers = 0;
            for token in line.split(|b| b.is_ascii_whitespace()).filter(|t| !t.is_empty()) {
                let value = std::str::from_utf8(token).ok().and_then(|t| t.parse::<f64>().ok());
                not_numbers += value.is_none() as usize;
                values.push(value.unwrap_or(f64::NAN));
            }
            let mut at = 0usize;
            let mut well_formed = not_numbers == 0;
            for (pi, p) in element.properties.iter().enumerate() {
                match p.kind {
                    PropertyKind::Scalar(_) => {
                        let v = values.get(at).copied();
                        well_formed &= v.is_some();
                        if kept[pi] && is_vertex {
                            columns[pi].push(v.unwrap_or(f64::NAN));
                        }
                        at += 1;
                    }
                    PropertyKind::List { .. } => {
                        let n = values.get(at).copied().filter(|n| n.is_finite() && *n >= 0.0 && n.fract() == 0.0);
                        at += 1;
                        let items = n.and_then(|n| values.get(at..at.saturating_add(n as usize)));
                        match items {
                            Some(items) => {
                                at += items.len();
                                if kept[pi] && not_numbers == 0 {
                                    polygon.clear();
                                    polygon.extend(items.iter().map(|&v| v as i64));
                                    sink.push_list(&element.name, &polygon);
                                }
                            }
                            None => {
                                well_formed = false;
                                at = values.len();
                            }
                        }
                    }
                }
            }
            well_formed &= at == values.len();
            if !well_formed {
                if is_vertex {
                    // The record's values cannot be trusted: the loader skips it.
                    sink.malformed_vertices.push(record);
                    for column in columns.iter_mut().zip(&kept).filter(|(_, k)| **k).map(|(c, _)| c) {
                        if let Some(last) = column.last_mut() {
                            *last = f64::NAN;
                        }
                    }
                } else {
                    sink.malformed_records += 1;
                }
            }
        }
        if is_vertex {
            for ((p, column), _) in element.properties.iter().zip(columns).zip(&kept).filter(|(_, k)| **k) {
                sink.vertex_columns.insert(p.name.clone(), column);
            }
        }
    }
    Ok(())
}
