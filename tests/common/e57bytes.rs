//! E57 files rewritten byte by byte, for the tests of bad E57 input.
//!
//! An E57 file (ASTM E2807) is pages of `page_size` bytes, each ending in the
//! CRC-32C of the rest of the page, stored big-endian; the bytes without
//! those words are the "logical" file. Its first 48 logical bytes are the
//! header: the signature, the version, the physical length (u64 at 16), the
//! XML's physical offset (u64 at 24) and logical length (u64 at 32), and the
//! page size (u64 at 40). The XML comes last. [`E57::rebuilt`] puts new XML
//! in place of the old one and recomputes every page's CRC, so a test can
//! make a file whose scans say anything while every page stays sound.
//!
//! The CRC and the page arithmetic are written out here: the `e57` crate
//! keeps its own private, and the tests need them to write files the crate
//! would never write.

/// CRC-32C (Castagnoli, reflected polynomial 0x82F63B78), as E57 pages carry it.
pub fn crc32c(bytes: &[u8]) -> u32 {
    let mut table = [0u32; 256];
    for (i, entry) in table.iter_mut().enumerate() {
        let mut c = i as u32;
        for _ in 0..8 {
            c = if c & 1 != 0 { (c >> 1) ^ 0x82F6_3B78 } else { c >> 1 };
        }
        *entry = c;
    }
    !bytes.iter().fold(!0u32, |c, &b| table[((c ^ u32::from(b)) & 0xff) as usize] ^ (c >> 8))
}

/// One E57 file, read into its logical bytes.
pub struct E57 {
    pub page: u64,
    logical: Vec<u8>,
    xml_phys: u64,
    pub xml: String,
}

fn u64_at(bytes: &[u8], at: usize) -> u64 {
    u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap())
}

impl E57 {
    pub fn parse(raw: &[u8]) -> E57 {
        let page = u64_at(raw, 40);
        assert!(page > 4 && raw.len() as u64 % page == 0, "an E57 file of whole pages");
        let payload = (page - 4) as usize;
        let logical: Vec<u8> = raw.chunks_exact(page as usize).flat_map(|p| p[..payload].to_vec()).collect();
        let (xml_phys, xml_len) = (u64_at(&logical, 24), u64_at(&logical, 32));
        let mut e = E57 { page, logical, xml_phys, xml: String::new() };
        let at = e.logical_of(xml_phys) as usize;
        e.xml = String::from_utf8(e.logical[at..at + xml_len as usize].to_vec()).unwrap();
        e
    }

    fn payload(&self) -> u64 {
        self.page - 4
    }

    pub fn logical_of(&self, physical: u64) -> u64 {
        physical - physical / self.page * 4
    }

    pub fn physical_of(&self, logical: u64) -> u64 {
        logical / self.payload() * self.page + logical % self.payload()
    }

    /// A compressed vector section's header at `physical`: its length and its first data packet's offset.
    pub fn section_header(&self, physical: u64) -> (u64, u64) {
        let at = self.logical_of(physical) as usize;
        assert_eq!(self.logical[at], 1, "a compressed vector section at byte {physical}");
        (u64_at(&self.logical, at + 8), u64_at(&self.logical, at + 16))
    }

    /// The file with its XML replaced by `xml` (the binary sections untouched).
    pub fn rebuilt(&self, xml: &str) -> Vec<u8> {
        let keep = self.logical_of(self.xml_phys) as usize;
        let mut logical = self.logical[..keep].to_vec();
        logical.extend_from_slice(xml.as_bytes());
        self.paged(logical, self.xml_phys, xml.len())
    }

    /// The file with `extra` bytes placed where the XML was (8-aligned) and the
    /// XML after them; `xml_for` makes the XML given the extra bytes' physical offset.
    pub fn with_extra(&self, extra: &[u8], xml_for: impl Fn(u64) -> String) -> Vec<u8> {
        let old = self.logical_of(self.xml_phys) as usize;
        let at = old.next_multiple_of(8);
        let mut logical = self.logical[..old].to_vec();
        logical.resize(at, 0);
        logical.extend_from_slice(extra);
        let xml_at = logical.len().next_multiple_of(8);
        logical.resize(xml_at, 0);
        let xml = xml_for(self.physical_of(at as u64));
        logical.extend_from_slice(xml.as_bytes());
        let xml_phys = self.physical_of(xml_at as u64);
        self.paged(logical, xml_phys, xml.len())
    }

    /// Where [`E57::with_extra`] puts its extra bytes.
    pub fn extra_at(&self) -> u64 {
        self.physical_of((self.logical_of(self.xml_phys) as usize).next_multiple_of(8) as u64)
    }

    /// The section at `physical`, as it would read at `new_physical`: its data
    /// offset moved with it, or set to `data` (pointing elsewhere).
    pub fn section_moved(&self, physical: u64, new_physical: u64, data: Option<u64>) -> Vec<u8> {
        let (length, first) = self.section_header(physical);
        let start = self.logical_of(physical);
        let mut body = self.logical[start as usize..(start + length) as usize].to_vec();
        let moved = self.physical_of(self.logical_of(new_physical) + (self.logical_of(first) - start));
        body[16..24].copy_from_slice(&data.unwrap_or(moved).to_le_bytes());
        body
    }

    /// Logical bytes to pages: padded, the header's length and XML fields set, every CRC written.
    fn paged(&self, mut logical: Vec<u8>, xml_phys: u64, xml_len: usize) -> Vec<u8> {
        let payload = self.payload() as usize;
        logical.resize(logical.len().next_multiple_of(payload), 0);
        let pages = (logical.len() / payload) as u64;
        logical[16..24].copy_from_slice(&(pages * self.page).to_le_bytes());
        logical[24..32].copy_from_slice(&xml_phys.to_le_bytes());
        logical[32..40].copy_from_slice(&(xml_len as u64).to_le_bytes());
        let mut out = Vec::with_capacity((pages * self.page) as usize);
        for chunk in logical.chunks_exact(payload) {
            out.extend_from_slice(chunk);
            out.extend_from_slice(&crc32c(chunk).to_be_bytes());
        }
        out
    }
}

/// `text` with the span `from..to` replaced by `with`.
pub fn splice(text: &str, from: usize, to: usize, with: &str) -> String {
    format!("{}{with}{}", &text[..from], &text[to..])
}

/// The byte span of the content of the first `<tag ...>...</tag>` element in `text`.
pub fn content_of(text: &str, tag: &str) -> (usize, usize) {
    let open = text.find(&format!("<{tag}")).unwrap_or_else(|| panic!("no <{tag}>"));
    let from = open + text[open..].find('>').unwrap() + 1;
    let to = from + text[from..].find(&format!("</{tag}>")).unwrap_or_else(|| panic!("no </{tag}>"));
    (from, to)
}

/// The whole first `<tag ...>...</tag>` (or `<tag .../>`) element of `text`, as a span.
pub fn element(text: &str, tag: &str) -> (usize, usize) {
    let open = text.find(&format!("<{tag} ")).unwrap_or_else(|| panic!("no <{tag}>"));
    let head_end = open + text[open..].find('>').unwrap() + 1;
    if text[..head_end].ends_with("/>") {
        return (open, head_end);
    }
    let close = format!("</{tag}>");
    let to = head_end + text[head_end..].find(&close).unwrap() + close.len();
    (open, to)
}
