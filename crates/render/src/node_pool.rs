//! Where a streamed selection's nodes sit in the GPU's instance buffers:
//! each node drawn keeps the slots it was first written to for as long as
//! it stays drawn, so a new selection writes only the nodes it adds and
//! marks vacant the slots of those it drops (a node pool, as Potree and
//! Schütz et al.'s streaming renderers keep one; no paper of ours covers
//! it). The records themselves are written by [`crate::gpu_scene::GpuScene`],
//! which compares each slot with what it last wrote.
//!
//! A pool is laid out with [`HEADROOM`] times the splats of its first
//! selection. A node that arrives takes the first run of vacant slots it
//! fits in (first fit, in slot order); a node whose splat count changed
//! (copies merged across a border it shares) is placed anew. A node that
//! fits nowhere grows the pool at its end by a quarter at least (new
//! buffers, the old ones kept as they are). When the selection holds less
//! than [`SHRINK`] of the slots (it shrank, or vacant runs piled up), the
//! pool is laid out anew: every node packed in selection order, every
//! record written again. Vacant slots hold a record the splat shaders cull
//! (see `SplatInstance::VACANT`), and a raster pass draws only the runs of
//! drawn slots ([`Placement::live`]).

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

/// A pool whose selection holds less than this fraction of its slots is laid out anew, smaller.
pub const SHRINK: f64 = 0.5;

/// Each drawn node's slots.
#[derive(Debug, Clone, Default)]
pub struct SlotPool {
    placed: HashMap<u32, Range<u32>>,
    capacity: u32,
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
        let mut pool = SlotPool { placed: HashMap::new(), capacity };
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

    /// Places the nodes of `spans`: those drawn before, with as many
    /// splats, keep their slots; the others take the first vacant run they
    /// fit in, or grow the pool. Laid out anew when the pool is mostly vacant.
    pub fn place(&mut self, spans: &NodeSpans) -> Placement {
        if (spans.splats() as f64) < SHRINK * self.capacity as f64 {
            return self.relaid(spans);
        }
        let kept: HashMap<u32, Range<u32>> = spans
            .0
            .iter()
            .filter_map(|(node, splats)| {
                let slots = self.placed.get(node).filter(|s| s.len() == splats.len())?;
                Some((*node, slots.clone()))
            })
            .collect();
        let mut taken: Vec<Range<u32>> = kept.values().cloned().collect();
        taken.sort_by_key(|r| r.start);
        let mut vacant = vacant_runs(&taken, self.capacity);
        let mut placed = kept.clone();
        for (node, splats) in spans.0.iter().filter(|(node, _)| !kept.contains_key(node)) {
            let need = splats.len() as u32;
            if !vacant.iter().any(|r| r.len() as u32 >= need) {
                let tail = vacant.last().filter(|r| r.end == self.capacity).map_or(0, |r| r.len() as u32);
                let grown = self.capacity + (need - tail).max(self.capacity / 4);
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

    fn relaid(&mut self, spans: &NodeSpans) -> Placement {
        let (pool, placement) = Self::laid_out(spans);
        *self = pool;
        placement
    }

    /// The slots of `spans`'s nodes as placed.
    fn placement(&self, spans: &NodeSpans, relaid: bool) -> Placement {
        let slots = spans.0.iter().map(|(node, _)| self.placed[node].clone()).collect();
        Placement { slots, capacity: self.capacity, relaid }
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
        let (mut pool, first) = SlotPool::laid_out(&before);
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
        let shrunk = pool.place(&spans(&[(3, 30)]));
        assert!(shrunk.relaid, "30 splats in more than 60 slots: laid out anew");
        assert_eq!(pool.capacity(), (30.0 * HEADROOM).ceil() as u32);
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
