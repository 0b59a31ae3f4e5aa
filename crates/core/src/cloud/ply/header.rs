//! The PLY header: format, comments, elements and their properties.
//!
//! Hand-written rather than taken from `ply-rs-bw`: that crate lets a second
//! property or element of the same name silently replace the first (so data
//! is misread), rejects `nan`/`inf` in ASCII bodies, and reports problems as
//! parser debug dumps. The grammar is a dozen keywords, so a plain parser
//! gives exact checks and one-line errors with the header line number.

use super::scalar::Scalar;

/// How the body is stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Encoding {
    Ascii,
    BinaryLittleEndian,
    BinaryBigEndian,
}

impl Encoding {
    pub fn name(self) -> &'static str {
        match self {
            Encoding::Ascii => "ascii",
            Encoding::BinaryLittleEndian => "binary_little_endian",
            Encoding::BinaryBigEndian => "binary_big_endian",
        }
    }
}

/// A property of an element, as declared in the header.
#[derive(Debug, Clone)]
pub struct PropertySpec {
    pub name: String,
    pub kind: PropertyKind,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PropertyKind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

/// An element of the header (`vertex`, `face`, `tristrips`, `range_grid`, ...).
#[derive(Debug, Clone)]
pub struct ElementSpec {
    pub name: String,
    pub count: usize,
    pub properties: Vec<PropertySpec>,
}

impl ElementSpec {
    pub fn property(&self, name: &str) -> Option<&PropertySpec> {
        self.properties.iter().find(|p| p.name == name)
    }

    /// Smallest size in bytes one binary record can have.
    pub fn min_record_bytes(&self) -> usize {
        self.properties
            .iter()
            .map(|p| match p.kind {
                PropertyKind::Scalar(s) => s.size(),
                PropertyKind::List { count, .. } => count.size(),
            })
            .sum()
    }

    /// Byte size of every record when the element has no lists.
    pub fn fixed_record_bytes(&self) -> Option<usize> {
        self.properties
            .iter()
            .map(|p| match p.kind {
                PropertyKind::Scalar(s) => Some(s.size()),
                PropertyKind::List { .. } => None,
            })
            .sum()
    }
}

/// A parsed header and where the body starts.
#[derive(Debug, Clone)]
pub struct Header {
    pub encoding: Encoding,
    pub comments: Vec<String>,
    pub elements: Vec<ElementSpec>,
    /// Byte offset of the body in the file.
    pub body_start: usize,
}

/// Reads the header at the start of `bytes`. Errors are one line without the
/// file name (the caller adds it).
pub fn parse(bytes: &[u8]) -> Result<Header, String> {
    const END: &[u8] = b"end_header";
    if !bytes.starts_with(b"ply") {
        return Err("the file does not start with 'ply'".into());
    }
    let end = find_end(bytes).ok_or("the header has no 'end_header' line (truncated file?)")?;
    let text = std::str::from_utf8(&bytes[..end]).map_err(|_| "the header is not plain text".to_string())?;
    let mut body_start = end + END.len();
    // The line break after end_header: LF or CR LF.
    if bytes.get(body_start) == Some(&b'\r') {
        body_start += 1;
    }
    if bytes.get(body_start) == Some(&b'\n') {
        body_start += 1;
    }
    let mut encoding = None;
    let mut comments = Vec::new();
    let mut elements: Vec<ElementSpec> = Vec::new();
    for (index, line) in text.lines().enumerate() {
        let number = index + 1;
        let words: Vec<&str> = line.split_whitespace().collect();
        let bad = |what: &str| format!("bad header: line {number} ('{}'): {what}", line.trim());
        match words.as_slice() {
            [] => {}
            ["ply"] if number == 1 => {}
            ["format", name, _version] => {
                if encoding.is_some() {
                    return Err(bad("a second 'format' line"));
                }
                encoding = Some(match *name {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::BinaryLittleEndian,
                    "binary_big_endian" => Encoding::BinaryBigEndian,
                    _ => return Err(bad("the format must be ascii, binary_little_endian or binary_big_endian")),
                });
            }
            ["comment", ..] => comments.push(line.trim_start()["comment".len()..].trim().to_string()),
            ["obj_info", ..] => {}
            ["element", name, count] => {
                let count = count.parse::<usize>().map_err(|_| bad("the count is not a whole number"))?;
                if elements.iter().any(|e| e.name == *name) {
                    return Err(bad(&format!("element '{name}' is declared twice")));
                }
                elements.push(ElementSpec { name: name.to_string(), count, properties: Vec::new() });
            }
            ["element", ..] => return Err(bad("expected 'element NAME COUNT'")),
            ["property", "list", count, item, name] => {
                let count = scalar(count).ok_or_else(|| bad(&format!("'{count}' is not a PLY type")))?;
                let item = scalar(item).ok_or_else(|| bad(&format!("'{item}' is not a PLY type")))?;
                if count.is_float() {
                    return Err(bad("a list count must have an integer type"));
                }
                add_property(&mut elements, name, PropertyKind::List { count, item }).map_err(|e| bad(&e))?;
            }
            ["property", ty, name] => {
                let ty = scalar(ty).ok_or_else(|| bad(&format!("'{ty}' is not a PLY type")))?;
                add_property(&mut elements, name, PropertyKind::Scalar(ty)).map_err(|e| bad(&e))?;
            }
            ["property", ..] => return Err(bad("expected 'property TYPE NAME' or 'property list COUNT ITEM NAME'")),
            _ => return Err(bad("not a header keyword")),
        }
    }
    let encoding = encoding.ok_or("bad header: no 'format' line")?;
    Ok(Header { encoding, comments, elements, body_start })
}

fn add_property(elements: &mut [ElementSpec], name: &str, kind: PropertyKind) -> Result<(), String> {
    let element = elements.last_mut().ok_or("a property before any element")?;
    if element.property(name).is_some() {
        return Err(format!("property '{name}' of element '{}' is declared twice", element.name));
    }
    element.properties.push(PropertySpec { name: name.to_string(), kind });
    Ok(())
}

/// Where the `end_header` keyword starts, at the start of a line.
fn find_end(bytes: &[u8]) -> Option<usize> {
    const END: &[u8] = b"end_header";
    let mut at = 0;
    while let Some(found) = bytes[at..].windows(END.len()).position(|w| w == END) {
        let start = at + found;
        let line_start = start == 0 || bytes[start - 1] == b'\n';
        let after = bytes.get(start + END.len());
        let line_end = matches!(after, None | Some(b'\n') | Some(b'\r') | Some(b' ') | Some(b'\t'));
        if line_start && line_end {
            return Some(start);
        }
        at = start + 1;
    }
    None
}

/// A PLY scalar type name, in the classic or the sized spelling.
fn scalar(name: &str) -> Option<Scalar> {
    Some(match name {
        "char" | "int8" => Scalar::I8,
        "uchar" | "uint8" => Scalar::U8,
        "short" | "int16" => Scalar::I16,
        "ushort" | "uint16" => Scalar::U16,
        "int" | "int32" => Scalar::I32,
        "uint" | "uint32" => Scalar::U32,
        "float" | "float32" => Scalar::F32,
        "double" | "float64" => Scalar::F64,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_header_with_every_kind_of_line_parses() {
        let text = b"ply\r\nformat binary_big_endian 1.0\r\ncomment made by hand\r\nobj_info x\r\nelement vertex 2\r\nproperty float32 x\r\nproperty list uchar int vertex_indices\r\nend_header\r\nBODY";
        let h = parse(text).unwrap();
        assert_eq!(h.encoding, Encoding::BinaryBigEndian);
        assert_eq!(h.comments, ["made by hand"]);
        assert_eq!(h.elements[0].properties.len(), 2);
        assert_eq!(&text[h.body_start..], b"BODY");
    }

    #[test]
    fn duplicates_and_bad_lines_are_named_with_their_line() {
        let dup = b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float x\nend_header\n";
        let e = parse(dup).unwrap_err();
        assert!(e.contains("line 5") && e.contains("declared twice"), "{e}");
        let dup = b"ply\nformat ascii 1.0\nelement a 1\nelement a 1\nend_header\n";
        assert!(parse(dup).unwrap_err().contains("element 'a' is declared twice"));
        let typo = b"ply\nformat ascii 1.0\nelement vertex 1\nproperty flot x\nend_header\n";
        let e = parse(typo).unwrap_err();
        assert!(e.contains("line 4") && e.contains("'flot' is not a PLY type"), "{e}");
        let count = b"ply\nformat ascii 1.0\nelement vertex 3 x\nend_header\n";
        assert!(parse(count).unwrap_err().contains("expected 'element NAME COUNT'"));
        assert!(parse(b"ply\nformat ascii 1.0\nelement vertex 3\n").unwrap_err().contains("no 'end_header'"));
    }
}
