//! Writing a GPU copy's splat records only where they changed: a deforming
//! model's next frame, or a streamed selection whose nodes stay in their
//! slots of a node pool ([`crate::node_pool`]). What was written last is
//! kept as one 64-bit key per record (FNV-1a over its nine words, not the
//! 36-byte record itself: a quarter of the memory, and a changed record
//! goes unwritten only if its key collides with the old one's, once in
//! 2^64). Runs of changed records are joined across short unchanged gaps,
//! one write each.

use crate::gpu_data::SplatInstance;

/// Unchanged records a rewrite writes over rather than start a new write.
pub const REWRITE_GAP: usize = 64;

/// What identifies a record's contents.
pub fn record_key(record: &SplatInstance) -> u64 {
    let words: &[u32; 9] = bytemuck::cast_ref(record);
    words.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &w| (h ^ w as u64).wrapping_mul(0x0000_0100_0000_01b3))
}

/// The keys of `records`.
pub fn keys_of(records: &[SplatInstance]) -> Vec<u64> {
    records.iter().map(record_key).collect()
}

/// Records made and compared at a time (a bounded buffer, whatever the splats).
pub const PIECE: usize = 1 << 16;

/// How a rewrite treats a run of records.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rewrite<'a> {
    /// Every record written.
    All,
    /// Those whose keys changed, except where `leave` is true: those
    /// records (a node pool's residents) stay as they are, their keys too,
    /// and no write spans them.
    Changed { leave: &'a [bool] },
}

/// Writes `records` into `buffer` from record `first` on as `how` says,
/// and keeps the keys of what it wrote in `kept`. Returns the bytes written.
pub fn write_changed(
    queue: &wgpu::Queue,
    (buffer, first): (&wgpu::Buffer, usize),
    records: &[SplatInstance],
    kept: &mut [u64],
    how: Rewrite<'_>,
) -> u64 {
    let size = std::mem::size_of::<SplatInstance>() as u64;
    let (all, leave) = match how {
        Rewrite::All => (true, &[][..]),
        Rewrite::Changed { leave } => (false, leave),
    };
    let left = |i: usize| leave.get(i).copied().unwrap_or(false);
    let mut changed = vec![all; records.len()];
    for (i, ((record, key), changed)) in records.iter().zip(kept.iter_mut()).zip(&mut changed).enumerate() {
        if left(i) {
            continue;
        }
        let new = record_key(record);
        *changed |= new != *key;
        *key = new;
    }
    let mut written = 0;
    let mut at = 0;
    while at < records.len() {
        if !changed[at] {
            at += 1;
            continue;
        }
        let (mut end, mut unchanged) = (at + 1, 0);
        while end < records.len() && unchanged < REWRITE_GAP && !left(end) {
            unchanged = if changed[end] { 0 } else { unchanged + 1 };
            end += 1;
        }
        let end = end - unchanged;
        queue.write_buffer(buffer, (first + at) as u64 * size, bytemuck::cast_slice(&records[at..end]));
        written += (end - at) as u64 * size;
        at = end;
    }
    written
}
