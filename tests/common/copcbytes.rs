//! COPC files rewritten byte by byte, for the tests of bad hierarchies.
//!
//! A COPC file's first VLR is the COPC info VLR: its data starts at byte
//! 375 + 54 (after the LAS 1.4 header and the VLR's own header) and holds
//! the octree's centre, half-size and spacing (f64 each), then the root
//! hierarchy page's offset and size (u64 at 40 and 48). A hierarchy page is
//! 32-byte entries: a key (level, x, y, z as i32), an offset (u64), a byte
//! size and a point count (i32 each); a count of -1 points at a child page
//! of that size at that offset.

/// Where the info VLR's data starts.
pub const INFO_AT: usize = 375 + 54;
pub const ENTRY_BYTES: usize = 32;

/// One hierarchy entry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Entry {
    pub key: [i32; 4],
    pub offset: u64,
    pub byte_size: i32,
    pub count: i32,
}

impl Entry {
    pub fn bytes(&self) -> [u8; ENTRY_BYTES] {
        let mut b = [0u8; ENTRY_BYTES];
        for (i, k) in self.key.iter().enumerate() {
            b[4 * i..4 * i + 4].copy_from_slice(&k.to_le_bytes());
        }
        b[16..24].copy_from_slice(&self.offset.to_le_bytes());
        b[24..28].copy_from_slice(&self.byte_size.to_le_bytes());
        b[28..32].copy_from_slice(&self.count.to_le_bytes());
        b
    }

    fn read(b: &[u8]) -> Entry {
        let i32_at = |at: usize| i32::from_le_bytes(b[at..at + 4].try_into().unwrap());
        Entry {
            key: [i32_at(0), i32_at(4), i32_at(8), i32_at(12)],
            offset: u64::from_le_bytes(b[16..24].try_into().unwrap()),
            byte_size: i32_at(24),
            count: i32_at(28),
        }
    }
}

/// Entries as one page's bytes.
pub fn page(entries: &[Entry]) -> Vec<u8> {
    entries.iter().flat_map(|e| e.bytes()).collect()
}

/// A COPC file's bytes, open for patching.
pub struct Copc {
    pub bytes: Vec<u8>,
}

impl Copc {
    pub fn new(bytes: Vec<u8>) -> Copc {
        assert_eq!(&bytes[375 + 2..375 + 6], b"copc", "the first VLR is the COPC info VLR");
        Copc { bytes }
    }

    fn f64_at(&self, at: usize) -> f64 {
        f64::from_le_bytes(self.bytes[at..at + 8].try_into().unwrap())
    }

    /// The octree's centre and half-size.
    pub fn octree(&self) -> ([f64; 3], f64) {
        ([0, 8, 16].map(|d| self.f64_at(INFO_AT + d)), self.f64_at(INFO_AT + 24))
    }

    pub fn set_centre(&mut self, centre: [f64; 3]) {
        for (i, c) in centre.iter().enumerate() {
            self.bytes[INFO_AT + 8 * i..INFO_AT + 8 * i + 8].copy_from_slice(&c.to_le_bytes());
        }
    }

    /// The root page's offset and size.
    pub fn root_page(&self) -> (u64, u64) {
        let word = |at: usize| u64::from_le_bytes(self.bytes[at..at + 8].try_into().unwrap());
        (word(INFO_AT + 40), word(INFO_AT + 48))
    }

    pub fn set_root_page(&mut self, at: u64, size: u64) {
        self.bytes[INFO_AT + 40..INFO_AT + 48].copy_from_slice(&at.to_le_bytes());
        self.bytes[INFO_AT + 48..INFO_AT + 56].copy_from_slice(&size.to_le_bytes());
    }

    pub fn entries(&self, at: u64, size: u64) -> Vec<Entry> {
        self.bytes[at as usize..(at + size) as usize].chunks_exact(ENTRY_BYTES).map(Entry::read).collect()
    }

    /// Writes `entries` over the page at `at`.
    pub fn put_entries(&mut self, at: u64, entries: &[Entry]) {
        let bytes = page(entries);
        self.bytes[at as usize..at as usize + bytes.len()].copy_from_slice(&bytes);
    }

    /// Appends `blob` at the end of the file; its offset.
    pub fn append(&mut self, blob: &[u8]) -> u64 {
        let at = self.bytes.len() as u64;
        self.bytes.extend_from_slice(blob);
        at
    }
}
