//! LAS 1.4 extra-bytes descriptors (the `LASF_Spec` VLRs, record 4, in file
//! order when a writer split them over several) and the values they describe, hand-read because the `las` crate hands a record's
//! extra bytes over undecoded.
//!
//! Each descriptor is 192 bytes: reserved (2), data type (1), options (1),
//! name (32), unused (4), no-data (24), min (24), max (24), scale (24),
//! offset (24), description (32). Types 1-10 are the scalars u8 ... f64; type
//! 0 is `options` undocumented bytes (skipped); types 11-30 are the
//! deprecated 2- and 3-element arrays (their first element is read, with a
//! warning); any other type is an error. Option bit 3 says the scale is
//! given, bit 4 the offset: value = raw · scale + offset (a scale of 0 or
//! not finite is taken as 1, an offset not finite as 0, with a warning). A
//! name already taken (by an earlier field or a standard attribute) gets a
//! suffix, `_2` and up, with a warning.

use rayon::prelude::*;

use crate::cloud::attributes::Values;

/// One named extra-bytes field of a record.
#[derive(Debug, Clone)]
pub struct Field {
    pub name: String,
    /// Byte offset in the record.
    offset: usize,
    kind: u8,
    scale: f64,
    add: f64,
    /// A vertex column of another format's file held as columns
    /// ([`super::Columns::of_read`]), of this type: kept a vertex column
    /// when the columns are finished, not an attribute.
    pub(crate) vertex: Option<crate::cloud::ply::Scalar>,
}

/// The fields the descriptors name, and what was skipped.
#[derive(Debug, Default)]
pub struct Descriptors {
    pub fields: Vec<Field>,
    pub warnings: Vec<String>,
}

const DESCRIPTOR_LEN: usize = 192;

/// Size in bytes of a scalar of data type `kind` (1-10).
fn scalar_size(kind: u8) -> usize {
    match kind {
        1 | 2 => 1,
        3 | 4 => 2,
        5 | 6 | 9 => 4,
        _ => 8,
    }
}

/// Reads the descriptors of `header`; `extra_bytes` is how many bytes each record has beyond its format's.
pub fn descriptors(header: &las::Header, extra_bytes: u16) -> Result<Descriptors, String> {
    // Some writers describe the fields in several records (one per field block): they follow in order.
    let data: Vec<u8> = header
        .all_vlrs()
        .filter(|v| v.user_id.trim_matches(char::from(0)) == "LASF_Spec" && v.record_id == 4)
        .flat_map(|v| v.data.iter().copied())
        .collect();
    if data.is_empty() {
        return Ok(Descriptors::default());
    }
    let base = header.point_format().len() as usize - extra_bytes as usize;
    let mut out = Descriptors::default();
    let mut offset = base;
    for (i, d) in data.chunks_exact(DESCRIPTOR_LEN).enumerate() {
        let kind = d[2];
        let options = d[3];
        let name = String::from_utf8_lossy(&d[4..36]).trim_matches(char::from(0)).trim().to_string();
        let name = if name.is_empty() { format!("extra_{i}") } else { name };
        let (size, first) = match kind {
            0 => (options as usize, None),
            1..=10 => (scalar_size(kind), Some(kind)),
            11..=30 => {
                let scalar = (kind - 11) % 10 + 1;
                let count = if kind <= 20 { 2 } else { 3 };
                out.warnings.push(format!(
                    "extra-bytes field '{name}' is a deprecated {count}-element array; its first element is read"
                ));
                (scalar_size(scalar) * count, Some(scalar))
            }
            _ => return Err(format!("extra-bytes field '{name}' has data type {kind}, which LAS does not define")),
        };
        if offset + size > base + extra_bytes as usize {
            return Err(format!(
                "the extra-bytes descriptors describe more than the {extra_bytes} extra bytes each record has"
            ));
        }
        if let Some(kind) = first {
            let name = unique(name, &mut out);
            let number = |at: usize| f64::from_le_bytes(d[at..at + 8].try_into().unwrap_or([0; 8]));
            let mut scale = if options & 8 != 0 { number(112) } else { 1.0 };
            let mut add = if options & 16 != 0 { number(136) } else { 0.0 };
            if !(scale.is_finite() && scale != 0.0) {
                out.warnings.push(format!("extra-bytes field '{name}' has a scale of {scale}; 1 is used"));
                scale = 1.0;
            }
            if !add.is_finite() {
                out.warnings.push(format!("extra-bytes field '{name}' has an offset of {add}; 0 is used"));
                add = 0.0;
            }
            out.fields.push(Field { name, offset, kind, scale, add, vertex: None });
        }
        offset += size;
    }
    Ok(out)
}

/// `name`, or when a field read before or a standard attribute already has
/// it, `name_2` (or the first free `name_N`), with a warning: two columns
/// of one name would be kept as one.
fn unique(name: String, out: &mut Descriptors) -> String {
    use crate::cloud::attributes::names;
    let standard = |n: &str| names::LAS_STANDARD.contains(&n) || n == names::NODE_LEVEL;
    let taken = |n: &str| standard(n) || out.fields.iter().any(|f| f.name == n);
    if !taken(&name) {
        return name;
    }
    let free = (2..).map(|k| format!("{name}_{k}")).find(|n| !taken(n)).expect("a free name");
    out.warnings.push(format!("two fields are named '{name}'; the second is kept as '{free}'"));
    free
}

impl Field {
    /// A column of another format's file, named `name`, of LAS extra-bytes
    /// type `kind` (1 u8, 3 u16, 9 f32, 10 f64): nothing is read from
    /// records through it; it names the column and the type it is finished in.
    pub(crate) fn column(name: String, kind: u8, vertex: Option<crate::cloud::ply::Scalar>) -> Self {
        Field { name, offset: 0, kind, scale: 1.0, add: 0.0, vertex }
    }

    /// The field's value in `record`, scale and offset applied.
    pub fn value(&self, record: &[u8]) -> f64 {
        let b = &record[self.offset..];
        let raw = match self.kind {
            1 => b[0] as f64,
            2 => b[0] as i8 as f64,
            3 => u16::from_le_bytes([b[0], b[1]]) as f64,
            4 => i16::from_le_bytes([b[0], b[1]]) as f64,
            5 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            6 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            9 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            7 => u64::from_le_bytes(b[..8].try_into().unwrap_or([0; 8])) as f64,
            8 => i64::from_le_bytes(b[..8].try_into().unwrap_or([0; 8])) as f64,
            _ => f64::from_le_bytes(b[..8].try_into().unwrap_or([0; 8])),
        };
        raw * self.scale + self.add
    }

    /// The column in the narrowest type that holds its values exactly.
    pub fn narrowest(&self, values: Vec<f64>) -> Values {
        let unscaled = self.scale == 1.0 && self.add == 0.0;
        match self.kind {
            1 if unscaled => Values::U8(values.par_iter().map(|&v| v as u8).collect()),
            3 if unscaled => Values::U16(values.par_iter().map(|&v| v as u16).collect()),
            2 | 4 | 9 if unscaled => Values::F32(values.par_iter().map(|&v| v as f32).collect()),
            _ => Values::F64(values),
        }
    }
}
