//! Where a streamed selection's nodes sit in the GPU's instance buffers:
//! each node drawn keeps the slots it was first written to for as long as
//! it stays drawn, so a new selection writes only the nodes it adds (a
//! node pool, as Potree and Schütz et al.'s streaming renderers keep one;
//! no paper of ours covers it). The records themselves are written by
//! [`crate::gpu_scene::GpuScene`], which compares each slot with what it
//! last wrote.
//!
//! A node a selection drops stays *resident*: its records stay in its
//! slots, undrawn (no pass reads them: the raster passes draw the drawn
//! runs, [`Placement::live`], and `tiled` projects only the slots the
//! scene's live mask marks), so a node that comes back (a pan back, a zoom
//! out and in again) takes its old slots and writes nothing. Residents are
//! evicted least recently drawn first, when a node that arrives fits in no
//! vacant run and the pool has reached [`RESIDENT_ROOM`]: as the CPU's node
//! cache evicts (`copc::cache`).
//!
//! A pool is laid out with [`HEADROOM`] times the splats of its first
//! selection. A node that arrives takes the first run of vacant slots it
//! fits in (first fit, in slot order); a node whose splat count changed
//! (copies merged across a border it shares) is placed anew. When no vacant
//! run fits it, the pool grows at its end (new buffers, the old ones kept
//! as they are) by a quarter, or what the node lacks, while it is smaller
//! than `HEADROOM + RESIDENT_ROOM` times its largest selection (and not
//! past that by the quarter); past that, residents are evicted until a run
//! fits, and only when none is left does it grow again. When the selection
//! and the residents hold less than [`SHRINK`] of the slots, the pool is
//! laid out anew: every node packed in selection order, every record
//! written again, no resident kept. Vacant slots are never drawn: those
//! written hold a record the splat shaders cull (`SplatInstance::VACANT`),
//! and those a growth added are left as the new buffer holds them until a
//! node is placed there.

use std::collections::HashMap;
use std::ops::Range;

use crate::frame::subset::NodeSpans;

/// A slot no splat is in (in an `InstanceLayout`'s order).
pub const VACANT: u32 = u32::MAX;

/// A pool's slots over the splats of the selection it is laid out for:
/// room for the nodes a pan adds before those it drops are reused (the
/// pool grows when that is not enough; more room costs memory, lavapipe's
/// host memory included).
pub const HEADROOM: f64 = 1.1;

/// Room a pool may grow to for residents, beyond [`HEADROOM`], in
/// selections: up to `HEADROOM + RESIDENT_ROOM` times its largest
/// selection's splats it grows to keep them, and past that it evicts. One
/// selection's worth, so that a zoom out and back, or a pan and back,
/// writes nothing for the nodes it brings back (it costs a selection's
/// records of memory: 36 MB for a million splats, host memory on lavapipe).
pub const RESIDENT_ROOM: f64 = 1.0;

/// A pool whose selection and residents hold less than this fraction of its slots is laid out anew, smaller.
pub const SHRINK: f64 = 0.5;

/// Each drawn node's slots, and each resident one's.
#[derive(Debug, Clone, Default)]
pub struct SlotPool {
    /// The nodes of the last selection placed.
    placed: HashMap<u32, Range<u32>>,
    /// Nodes not drawn whose records are still in their slots, with the
    /// selection they were last drawn in.
    resident: HashMap<u32, (Range<u32>, u64)>,
    capacity: u32,
    /// Selections placed so far.
    selections: u64,
    /// Splats of the largest selection placed since the pool was laid out.
    largest: u32,
    /// [`RESIDENT_ROOM`], or another room.
    resident_room: f64,
}

/// Where one selection's nodes go.
#[derive(Debug, Clone, PartialEq)]
pub struct Placement {
    /// The slots of each node of the selection, in its order.
    pub slots: Vec<Range<u32>>,
    /// The pool's slots.
    pub capacity: u32,
    /// Whether the pool was laid out anew (every node moved).
    pub relaid: bool,
    /// The slots of resident nodes, not drawn: their records are left as
    /// they are (sorted by start).
    pub resident: Vec<Range<u32>>,
}

impl Placement {
    /// The runs of slots that hold splats, in slot order, adjacent runs joined.
    pub fn live(&self) -> Vec<Range<u32>> {
        let mut runs: Vec<Range<u32>> = self.slots.iter().filter(|r| !r.is_empty()).cloned().collect();
        runs.sort_by_key(|r| r.start);
        let mut joined: Vec<Range<u32>> = Vec::with_capacity(runs.len());
        for run in runs {
            match joined.last_mut() {
                Some(last) if last.end == run.start => last.end = run.end,
                _ => joined.push(run),
            }
        }
        joined
    }
}

impl SlotPool {
    /// A pool laid out for `spans`: its nodes packed in order.
    pub fn laid_out(spans: &NodeSpans) -> (Self, Placement) {
        let capacity = ((spans.splats() as f64 * HEADROOM).ceil() as u32).max(1);
        let largest = spans.splats();
        let mut pool = SlotPool {
            placed: HashMap::new(),
            resident: HashMap::new(),
            capacity,
            selections: 1,
            largest,
            resident_room: RESIDENT_ROOM,
        };
        let mut at = 0;
        for (node, splats) in &spans.0 {
            pool.placed.insert(*node, at..at + splats.len() as u32);
            at += splats.len() as u32;
        }
        let placement = pool.placement(spans, true);
        (pool, placement)
    }

    /// Slots in the pool.
    pub fn capacity(&self) -> u32 {
        self.capacity
    }

    /// Places the nodes of `spans`: those placed before (drawn or
    /// resident), with as many splats, keep their slots; the others take the
    /// first vacant run they fit in, evicting the least recently drawn
    /// residents when none fits, or grow the pool. Laid out anew when the
    /// selection and the residents fill less than [`SHRINK`] of the pool.
    pub fn place(&mut self, spans: &NodeSpans) -> Placement {
        let in_selection: std::collections::HashSet<u32> = spans.0.iter().map(|(node, _)| *node).collect();
        // Splats the pool would hold: the selection's and the residents' (the last selection's included).
        let kept_aside = self.placed.iter().chain(self.resident.iter().map(|(node, (slots, _))| (node, slots)));
        let aside: usize = kept_aside.filter(|(node, _)| !in_selection.contains(node)).map(|(_, s)| s.len()).sum();
        if ((spans.splats() as usize + aside) as f64) < SHRINK * self.capacity as f64 {
            return self.relaid(spans);
        }
        let last = self.selections;
        self.selections += 1;
        self.largest = self.largest.max(spans.splats());
        let room = (self.largest as f64 * (HEADROOM + self.resident_room)).ceil() as u32;
        // The last selection's nodes this one drops become residents.
        for (node, slots) in std::mem::take(&mut self.placed) {
            if !in_selection.contains(&node) {
                self.resident.insert(node, (slots, last));
            } else {
                self.placed.insert(node, slots);
            }
        }
        let mut placed: HashMap<u32, Range<u32>> = HashMap::with_capacity(spans.0.len());
        for (node, splats) in &spans.0 {
            let before = self.placed.remove(node).or_else(|| self.resident.remove(node).map(|(slots, _)| slots));
            if let Some(slots) = before.filter(|s| s.len() == splats.len()) {
                placed.insert(*node, slots);
            }
        }
        let mut vacant = self.vacant_runs(&placed);
        let arriving: Vec<&(u32, Range<u32>)> = spans.0.iter().filter(|(node, _)| !placed.contains_key(node)).collect();
        for (node, splats) in arriving {
            let need = splats.len() as u32;
            // Residents are evicted when the pool has no room left to grow for them.
            while !vacant.iter().any(|r| r.len() as u32 >= need) && self.capacity >= room && self.evict_oldest() {
                vacant = self.vacant_runs(&placed);
            }
            if !vacant.iter().any(|r| r.len() as u32 >= need) {
                let tail = vacant.last().filter(|r| r.end == self.capacity).map_or(0, |r| r.len() as u32);
                // By a quarter, but not past the room for residents while growing for them.
                let quarter = self.capacity / 4;
                let step = if self.capacity < room { quarter.min(room - self.capacity) } else { quarter };
                let grown = self.capacity + (need - tail).max(step);
                match vacant.last_mut().filter(|r| r.end == self.capacity) {
                    Some(tail) => tail.end = grown,
                    None => vacant.push(self.capacity..grown),
                }
                self.capacity = grown;
            }
            let run = vacant.iter_mut().find(|r| r.len() as u32 >= need).expect("grown to fit");
            placed.insert(*node, run.start..run.start + need);
            run.start += need;
        }
        self.placed = placed;
        self.placement(spans, false)
    }

    /// Nodes of the last selection placed (drawn).
    pub fn drawn(&self) -> usize {
        self.placed.len()
    }

    /// Nodes resident (not drawn, their records kept).
    pub fn residents(&self) -> usize {
        self.resident.len()
    }

    /// Evicts the least recently drawn resident; false when there is none.
    fn evict_oldest(&mut self) -> bool {
        let oldest = self.resident.iter().min_by_key(|(node, (_, drawn))| (*drawn, **node)).map(|(node, _)| *node);
        oldest.is_some_and(|node| self.resident.remove(&node).is_some())
    }

    /// The runs of slots neither `placed` nor resident, in slot order.
    fn vacant_runs(&self, placed: &HashMap<u32, Range<u32>>) -> Vec<Range<u32>> {
        let mut taken: Vec<Range<u32>> =
            placed.values().cloned().chain(self.resident.values().map(|(slots, _)| slots.clone())).collect();
        taken.sort_by_key(|r| r.start);
        vacant_runs(&taken, self.capacity)
    }

    fn relaid(&mut self, spans: &NodeSpans) -> Placement {
        let (pool, placement) = Self::laid_out(spans);
        *self = SlotPool { resident_room: self.resident_room, ..pool };
        placement
    }

    /// The same pool, growing for residents up to `room` selections instead of [`RESIDENT_ROOM`].
    pub fn with_resident_room(self, room: f64) -> Self {
        SlotPool { resident_room: room, ..self }
    }

    /// The slots of `spans`'s nodes as placed.
    fn placement(&self, spans: &NodeSpans, relaid: bool) -> Placement {
        let slots = spans.0.iter().map(|(node, _)| self.placed[node].clone()).collect();
        let mut resident: Vec<Range<u32>> = self.resident.values().map(|(slots, _)| slots.clone()).collect();
        resident.sort_by_key(|r| r.start);
        Placement { slots, capacity: self.capacity, relaid, resident }
    }
}

/// The runs of `0..capacity` outside `taken` (sorted, disjoint).
fn vacant_runs(taken: &[Range<u32>], capacity: u32) -> Vec<Range<u32>> {
    let mut runs = Vec::with_capacity(taken.len() + 1);
    let mut at = 0;
    for t in taken {
        if t.start > at {
            runs.push(at..t.start);
        }
        at = at.max(t.end);
    }
    if at < capacity {
        runs.push(at..capacity);
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Nodes `(id, splat count)` one after another in the splats' order.
    fn spans(nodes: &[(u32, u32)]) -> NodeSpans {
        let mut at = 0;
        NodeSpans(
            nodes
                .iter()
                .map(|&(node, count)| {
                    at += count;
                    (node, at - count..at)
                })
                .collect(),
        )
    }

    /// The slot of splat `splat` of `spans` as `placement` placed them.
    fn slot_of(spans: &NodeSpans, placement: &Placement, splat: u32) -> u32 {
        let k = spans.0.iter().position(|(_, s)| s.contains(&splat)).expect("a node holds every splat");
        placement.slots[k].start + splat - spans.0[k].1.start
    }

    #[test]
    fn a_node_still_drawn_keeps_its_slots_and_one_that_arrives_takes_a_dropped_ones() {
        let before = spans(&[(1, 40), (2, 30), (3, 30)]);
        let (pool, first) = SlotPool::laid_out(&before);
        // No room kept for residents: a dropped node's slots are taken as soon as they are needed.
        let mut pool = pool.with_resident_room(0.0);
        assert_eq!(pool.capacity(), (100.0 * HEADROOM).ceil() as u32);
        assert_eq!(first.live(), vec![0..100]);
        // Node 2 dropped, node 4 added: node 3 is now splats 40..70 of the selection.
        let after = spans(&[(1, 40), (3, 30), (4, 20)]);
        let next = pool.place(&after);
        assert!(!next.relaid);
        assert_eq!(slot_of(&after, &next, 40), slot_of(&before, &first, 70), "node 3 stays in its slots");
        assert_eq!(slot_of(&after, &next, 0), slot_of(&before, &first, 0), "node 1 stays");
        assert_eq!(slot_of(&after, &next, 70), 40, "node 4 takes node 2's vacant run");
        assert_eq!(next.live(), vec![0..60, 70..100], "what node 4 leaves of that run is vacant");
    }

    #[test]
    fn a_node_that_fits_nowhere_grows_the_pool_and_a_mostly_vacant_pool_is_laid_out_anew() {
        let before = spans(&[(1, 40), (2, 40)]);
        let (mut pool, first) = SlotPool::laid_out(&before);
        let after = spans(&[(1, 40), (2, 40), (3, 30)]);
        let (capacity, tail) = (pool.capacity(), pool.capacity() - 80);
        assert!(tail < 30, "the vacant tail is too short for node 3");
        let grown = pool.place(&after);
        assert!(!grown.relaid, "the pool grows");
        assert_eq!(pool.capacity(), capacity + (30 - tail).max(capacity / 4), "by what node 3 lacks, or a quarter");
        assert_eq!(slot_of(&after, &grown, 40), slot_of(&before, &first, 40), "node 2 stays");
        assert_eq!(slot_of(&after, &grown, 80), 80, "node 3 starts in the vacant tail and runs into the new slots");
        let narrowed = pool.place(&spans(&[(3, 30)]));
        assert!(!narrowed.relaid, "nodes 1 and 2 stay resident: 110 splats held");
        assert_eq!(narrowed.resident, vec![0..40, 40..80]);
        // Both nodes come back with fewer splats: their old slots are free, 20 splats in 110 slots.
        let shrunk = pool.place(&spans(&[(1, 10), (2, 10)]));
        assert!(shrunk.relaid, "20 splats held in more than 60 slots: laid out anew");
        assert_eq!(pool.capacity(), (20.0 * HEADROOM).ceil() as u32);
        assert!(shrunk.resident.is_empty() && pool.residents() == 0, "laid out anew, nothing is kept");
    }

    #[test]
    fn a_dropped_node_stays_resident_and_comes_back_to_its_slots() {
        let first = spans(&[(1, 40), (2, 30), (3, 30)]);
        let (mut pool, placed) = SlotPool::laid_out(&first);
        let dropped = pool.place(&spans(&[(1, 40), (3, 30)]));
        assert!(!dropped.relaid);
        assert_eq!(dropped.resident, vec![40..70], "node 2's records stay in its slots");
        assert_eq!(dropped.live(), vec![0..40, 70..100], "and are not drawn");
        let back = pool.place(&first);
        assert_eq!(back.slots, placed.slots, "node 2 comes back to the slots it left");
        assert!(back.resident.is_empty());
        // Node 2 dropped again; node 4 fits in no vacant run: with room left, the pool grows rather than evict.
        let capacity = pool.capacity();
        let grown = pool.place(&spans(&[(1, 40), (3, 30), (4, 20)]));
        assert_eq!(grown.resident, vec![40..70], "node 2 stays resident");
        assert!(grown.slots[2].start >= 100 && pool.capacity() > capacity, "node 4 goes after the others");
    }

    #[test]
    fn the_pool_grows_for_residents_up_to_its_room_and_then_keeps_the_latest() {
        // Ten nodes of 10 splats; each selection drops its first node and adds the next.
        let window = |k: u32| spans(&(k..k + 10).map(|node| (node, 10)).collect::<Vec<_>>());
        let (mut pool, _) = SlotPool::laid_out(&window(0));
        let room = (100.0 * (HEADROOM + RESIDENT_ROOM)).ceil() as u32;
        for k in 1..=30 {
            let placed = pool.place(&window(k));
            assert!(!placed.relaid);
            assert!(pool.capacity() <= room, "selection {k}: {} slots, more than the room of {room}", pool.capacity());
        }
        assert_eq!(pool.capacity(), room, "grown to the room");
        assert_eq!(pool.residents(), ((room - 100) / 10) as usize, "every slot outside the selection holds a resident");
        let oldest_kept = 30 - pool.residents() as u32;
        assert!(pool.resident.keys().all(|&node| (oldest_kept..30).contains(&node)), "the latest dropped are kept");
    }

    #[test]
    fn the_least_recently_drawn_resident_is_evicted_first_and_only_when_no_vacant_run_fits() {
        // Slots: 1 at 0..50, 2 at 50..60, 3 at 60..70, 4 at 70..80, 5 at 80..100, vacant from 100 on.
        let (pool, _) = SlotPool::laid_out(&spans(&[(1, 50), (2, 10), (3, 10), (4, 10), (5, 20)]));
        // No room to grow for residents: the pool is as large as it gets.
        let mut pool = pool.with_resident_room(0.0);
        let capacity = pool.capacity();
        assert!(capacity < 120, "room for one more node of 10");
        pool.place(&spans(&[(1, 50), (3, 10), (4, 10), (5, 20)]));
        let older_dropped = pool.place(&spans(&[(1, 50), (3, 10), (5, 20)]));
        assert_eq!(older_dropped.resident, vec![50..60, 70..80], "nodes 2 and 4 resident, 2 dropped first");
        let after = spans(&[(1, 50), (3, 10), (5, 20), (6, 10), (7, 10)]);
        let next = pool.place(&after);
        assert!(!next.relaid);
        assert_eq!(next.slots[3], 100..110, "node 6 takes the vacant run");
        assert_eq!(next.slots[4], 50..60, "node 7 finds none: node 2, drawn least recently, is evicted");
        assert_eq!(next.resident, vec![70..80], "node 4 stays");
        assert_eq!(pool.capacity(), capacity, "nothing grew");
    }

    #[test]
    fn a_node_whose_splat_count_changed_is_placed_anew() {
        let (mut pool, _) = SlotPool::laid_out(&spans(&[(1, 20), (2, 40), (3, 40)]));
        let after = spans(&[(1, 21), (2, 40), (3, 40)]);
        let next = pool.place(&after);
        assert!(!next.relaid);
        assert_eq!(slot_of(&after, &next, 0), 100, "node 1 no longer fits its 20 slots: it goes after node 3");
        assert_eq!(slot_of(&after, &next, 21), 20, "node 2 stays");
        assert_eq!(next.live(), vec![20..121]);
    }
}
