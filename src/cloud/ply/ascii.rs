//! ASCII PLY body decoding through `ply-rs-bw`.
//!
//! `ply-rs-bw` parses each element's lines (CRLF included) into property
//! maps; this module keeps the requested vertex columns and the face lists.

use std::io::Cursor;
use std::path::Path;

use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{DefaultElement, Header, Property};

use super::{ColumnSink, ElementSpec, PropertySpec, check_fits};
use crate::cloud::CloudError;

pub(super) fn decode(
    path: &Path,
    body: &[u8],
    header: &Header,
    elements: &[ElementSpec],
    keep: &dyn Fn(&ElementSpec, &PropertySpec) -> bool,
    sink: &mut ColumnSink,
) -> Result<(), CloudError> {
    // Every ASCII record takes at least one character and a line break.
    let total: usize = elements.iter().map(|e| e.count).fold(0usize, |a, c| a.saturating_add(c));
    if total > body.len() / 2 + 1 {
        if let Some(e) = elements.iter().find(|e| e.count > body.len() / 2 + 1) {
            check_fits(path, e, 2, body.len())?;
        }
        return Err(CloudError::format(
            path,
            format!("header declares {total} records but the body has only {} bytes", body.len()),
        ));
    }
    let parser = Parser::<DefaultElement>::new();
    let mut reader = Reader::new(Cursor::new(body));
    let mut polygon = Vec::new();
    for element in elements {
        let Some(def) = header.elements.get(&element.name) else {
            continue;
        };
        let records = parser
            .read_payload_for_element(&mut reader, def, header)
            .map_err(|e| CloudError::format(path, format!("element '{}': {e}", element.name)))?;
        let kept: Vec<&PropertySpec> = element.properties.iter().filter(|p| keep(element, p)).collect();
        if element.name == "vertex" {
            for p in &kept {
                let column =
                    records.iter().map(|r| r.get(&p.name).and_then(scalar_value).unwrap_or(f64::NAN)).collect();
                sink.vertex_columns.insert(p.name.clone(), column);
            }
        } else if let Some(list) = kept.first() {
            for r in &records {
                polygon.clear();
                if let Some(p) = r.get(&list.name) {
                    list_values(p, &mut polygon);
                }
                sink.push_face(&polygon);
            }
        }
    }
    Ok(())
}

fn scalar_value(p: &Property) -> Option<f64> {
    Some(match p {
        Property::Char(v) => *v as f64,
        Property::UChar(v) => *v as f64,
        Property::Short(v) => *v as f64,
        Property::UShort(v) => *v as f64,
        Property::Int(v) => *v as f64,
        Property::UInt(v) => *v as f64,
        Property::Float(v) => *v as f64,
        Property::Double(v) => *v,
        _ => return None,
    })
}

fn list_values(p: &Property, out: &mut Vec<i64>) {
    match p {
        Property::ListChar(v) => out.extend(v.iter().map(|&i| i as i64)),
        Property::ListUChar(v) => out.extend(v.iter().map(|&i| i as i64)),
        Property::ListShort(v) => out.extend(v.iter().map(|&i| i as i64)),
        Property::ListUShort(v) => out.extend(v.iter().map(|&i| i as i64)),
        Property::ListInt(v) => out.extend(v.iter().map(|&i| i as i64)),
        Property::ListUInt(v) => out.extend(v.iter().map(|&i| i as i64)),
        Property::ListFloat(v) => out.extend(v.iter().map(|&i| i as i64)),
        Property::ListDouble(v) => out.extend(v.iter().map(|&i| i as i64)),
        _ => {}
    }
}
