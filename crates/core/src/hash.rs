//! FNV-1a, 64 bits: the content hash of model files and the keys of the
//! caches (groupings, reference images) and of scenes. Tiny, and stable
//! across runs and builds where `std`'s hasher is not.

use std::io::Read;
use std::path::Path;

/// The FNV-1a 64 offset basis: the hash of no bytes.
pub const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

/// FNV-1a, 64 bits, continued from `hash` over `bytes`.
pub fn fnv1a(hash: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(hash, |h, &b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3))
}

/// FNV-1a of the file's bytes (the model hash that screenshot sidecars carry).
pub fn file_hash(model: &Path) -> std::io::Result<u64> {
    let mut hash = FNV_OFFSET;
    let mut file = std::fs::File::open(model)?;
    let mut buffer = vec![0u8; 1 << 20];
    loop {
        let read = file.read(&mut buffer)?;
        if read == 0 {
            return Ok(hash);
        }
        hash = fnv1a(hash, &buffer[..read]);
    }
}
