//! A PLY or E57 file's points as the columns a LAS file decodes into, so
//! that it can be held whole as a tree of nodes as LAS and LAZ files are
//! (`copc::memory`). Positions stay f64. Every other vertex column
//! (colours, normals, radii, opacity, a Gaussian's terms) and every
//! attribute becomes a column of its own, described by a field that keeps
//! its name and type: finished ([`Columns::finish`]), a node's columns are
//! what the file's reader gave for those points, so a node is built as the
//! whole file is. The LAS columns such a file lacks stay empty and cost nothing.

use super::Columns;
use super::extra_bytes::Field;
use crate::cloud::attributes::{Attributes, Values};
use crate::cloud::ply::PointColumns;

/// LAS extra-bytes types: u8, u16, f32 and f64.
const U8: u8 = 1;
const U16: u8 = 3;
const F32: u8 = 9;
const F64: u8 = 10;

impl Columns {
    /// The points of `data` and `attributes` (one file's, as its reader
    /// gave them), and the fields that describe the columns past x, y, z;
    /// points whose position is not finite are left out, and counted.
    pub(crate) fn of_read(mut data: PointColumns, attributes: Attributes) -> (Columns, Vec<Field>, usize) {
        let mut take = |name: &str| data.vertex_columns.remove(name).unwrap_or_default();
        let (x, y, z) = (take("x"), take("y"), take("z"));
        let n = x.len().min(y.len()).min(z.len());
        let kept: Vec<u32> = (0..n as u32)
            .filter(|&i| [x[i as usize], y[i as usize], z[i as usize]].iter().all(|v| v.is_finite()))
            .collect();
        let all = kept.len() == n;
        let pick = |column: Vec<f64>| if all { column } else { kept.iter().map(|&i| column[i as usize]).collect() };
        let mut fields = Vec::new();
        let mut extra = Vec::new();
        // The file's vertex properties in its order (positions and faces' lists left out).
        let order: Vec<String> = data
            .elements
            .iter()
            .filter(|e| e.name == "vertex")
            .flat_map(|e| e.properties.iter().map(|p| p.name.clone()))
            .collect();
        let mut names: Vec<String> = order.into_iter().filter(|p| data.vertex_columns.contains_key(p)).collect();
        let mut rest: Vec<String> = data.vertex_columns.keys().filter(|k| !names.contains(k)).cloned().collect();
        rest.sort();
        names.extend(rest);
        for name in names {
            let Some(column) = data.vertex_columns.remove(&name) else { continue };
            if column.len() < n {
                continue;
            }
            let kind = data.vertex_types.get(&name).copied().unwrap_or(crate::cloud::ply::Scalar::F64);
            fields.push(Field::column(name, F64, Some(kind)));
            extra.push(pick(column));
        }
        for attribute in attributes.channels {
            if attribute.values.len() < n {
                continue;
            }
            let kind = match attribute.values {
                Values::U8(_) => U8,
                Values::U16(_) => U16,
                Values::F32(_) => F32,
                Values::F64(_) => F64,
            };
            let values = &attribute.values;
            fields.push(Field::column(attribute.name, kind, None));
            extra.push(if all {
                (0..n).map(|i| values.get(i)).collect()
            } else {
                kept.iter().map(|&i| values.get(i as usize)).collect()
            });
        }
        let columns = Columns { x: pick(x), y: pick(y), z: pick(z), extra, ..Default::default() };
        (columns, fields, n - kept.len())
    }
}
