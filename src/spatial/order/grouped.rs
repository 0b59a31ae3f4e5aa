//! One back-to-front order split into one back-to-front sequence per group:
//! a stable partition in O(n), as Zhang & Pajarola's transparent passes draw
//! each group S_k back to front into its own image (§5.2.1).
//!
//! Groups are the ranges of a [`Grouping`]'s `order` (the splat buffer is
//! uploaded in that order; a splat extended into several groups appears once
//! per group). The result holds positions in that buffer: group k's run is
//! `ranges[k]`, and within it the splats follow the global order.

use crate::grouping::Grouping;

/// Where each splat sits in the grouped buffer (CSR: a splat may sit in several groups).
#[derive(Debug, Clone)]
pub struct GroupedOrder {
    /// `slots[first[i]..first[i + 1]]`: (group, position in the grouped buffer) of splat i.
    first: Vec<u32>,
    slots: Vec<(u32, u32)>,
    /// Each group's start in the grouped buffer.
    starts: Vec<u32>,
}

impl GroupedOrder {
    /// The slots of `grouping` over `splats` splats.
    pub fn new(grouping: &Grouping, splats: usize) -> Self {
        let mut first = vec![0u32; splats + 1];
        for &i in &grouping.order {
            if (i as usize) < splats {
                first[i as usize + 1] += 1;
            }
        }
        for i in 0..splats {
            first[i + 1] += first[i];
        }
        let mut fill = first.clone();
        let mut slots = vec![(0, 0); first[splats] as usize];
        for (g, range) in grouping.ranges.iter().enumerate() {
            for position in range.clone() {
                let i = grouping.order[position as usize] as usize;
                if i < splats {
                    slots[fill[i] as usize] = (g as u32, position);
                    fill[i] += 1;
                }
            }
        }
        Self { first, slots, starts: grouping.ranges.iter().map(|r| r.start).collect() }
    }

    /// Partitions `order` (splat indices, back to front) by group into `out`
    /// (positions in the grouped buffer), keeping the order within each group.
    pub fn partition(&self, order: &[u32], out: &mut Vec<u32>) {
        out.clear();
        out.resize(self.slots.len(), 0);
        let mut fill = self.starts.clone();
        for &i in order {
            let i = i as usize;
            if i + 1 >= self.first.len() {
                continue;
            }
            for &(g, position) in &self.slots[self.first[i] as usize..self.first[i + 1] as usize] {
                out[fill[g as usize] as usize] = position;
                fill[g as usize] += 1;
            }
        }
    }
}
