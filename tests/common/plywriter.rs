//! A test-side PLY writer, independent of the library, for files in every
//! encoding and scalar type, with comments, unknown properties and faces.

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    Ascii,
    Little,
    Big,
}

pub struct Element<'a> {
    pub name: &'a str,
    /// (type, name); a list is written as ("list uchar int", name).
    pub properties: Vec<(&'a str, &'a str)>,
    /// One row per record; a list row item holds its values after the count.
    pub rows: Vec<Vec<f64>>,
}

fn write_scalar(out: &mut Vec<u8>, ty: &str, v: f64, enc: Encoding) {
    macro_rules! put {
        ($t:ty) => {{
            let x = v as $t;
            out.extend_from_slice(&if enc == Encoding::Big { x.to_be_bytes() } else { x.to_le_bytes() });
        }};
    }
    match ty {
        "char" | "int8" => put!(i8),
        "uchar" | "uint8" => put!(u8),
        "short" | "int16" => put!(i16),
        "ushort" | "uint16" => put!(u16),
        "int" | "int32" => put!(i32),
        "uint" | "uint32" => put!(u32),
        "float" | "float32" => put!(f32),
        "double" | "float64" => put!(f64),
        other => panic!("unknown type {other}"),
    }
}

/// Builds a PLY file. `crlf` ends header (and ASCII body) lines with CR LF.
pub fn ply(enc: Encoding, elements: &[Element], comments: &[&str], crlf: bool) -> Vec<u8> {
    let nl = if crlf { "\r\n" } else { "\n" };
    let format = match enc {
        Encoding::Ascii => "ascii",
        Encoding::Little => "binary_little_endian",
        Encoding::Big => "binary_big_endian",
    };
    let mut text = format!("ply{nl}format {format} 1.0{nl}");
    for c in comments {
        text.push_str(&format!("comment {c}{nl}"));
    }
    text.push_str(&format!("obj_info written by the pointblend tests{nl}"));
    for e in elements {
        text.push_str(&format!("element {} {}{nl}", e.name, e.rows.len()));
        for (ty, name) in &e.properties {
            text.push_str(&format!("property {ty} {name}{nl}"));
        }
    }
    text.push_str(&format!("end_header{nl}"));
    let mut out = text.into_bytes();
    for e in elements {
        for row in &e.rows {
            let mut values = row.iter();
            let mut words = Vec::new();
            for (ty, _) in &e.properties {
                if let Some(list) = ty.strip_prefix("list ") {
                    let mut parts = list.split_whitespace();
                    let (count_ty, item_ty) = (parts.next().unwrap(), parts.next().unwrap());
                    let n = *values.next().unwrap();
                    if enc == Encoding::Ascii {
                        words.push(format!("{n}"));
                    } else {
                        write_scalar(&mut out, count_ty, n, enc);
                    }
                    for _ in 0..n as usize {
                        let v = *values.next().unwrap();
                        if enc == Encoding::Ascii {
                            words.push(format!("{v}"));
                        } else {
                            write_scalar(&mut out, item_ty, v, enc);
                        }
                    }
                } else {
                    let v = *values.next().unwrap();
                    if enc == Encoding::Ascii {
                        words.push(if ty.contains("float") || *ty == "double" {
                            format!("{v:e}")
                        } else {
                            format!("{v}")
                        });
                    } else {
                        write_scalar(&mut out, ty, v, enc);
                    }
                }
            }
            if enc == Encoding::Ascii {
                out.extend_from_slice(words.join(" ").as_bytes());
                out.extend_from_slice(nl.as_bytes());
            }
        }
    }
    out
}

/// Writes `bytes` into a fresh temporary file named `name`.
pub fn temp_file(dir: &tempfile::TempDir, name: &str, bytes: &[u8]) -> std::path::PathBuf {
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).expect("temp file");
    path
}
