//! Which splat goes in which instance slot of a [`crate::gpu_scene::GpuScene`],
//! at what radius scale: a cloud in its own order, group by group (each of
//! Zhang & Pajarola's groups one contiguous run, §4.3, with the opaque
//! splats of a mixed scene once more after them, Fig. 18/19), or as a node
//! pool placed a streamed selection's nodes, vacant slots included.

use std::ops::Range;

use crate::cloud::PointCloud;
use crate::frame::subset::NodeSpans;
use crate::gpu_data::SplatInstance;
use crate::grouping::Grouping;
use crate::node_pool::{Placement, VACANT};

/// Which splat goes in which instance slot, at what radius scale.
pub(crate) struct InstanceLayout {
    /// The cloud index of each slot.
    pub order: Vec<u32>,
    pub scale_of: Vec<f32>,
    pub groups: Vec<Range<u32>>,
    pub transparent_groups: Vec<Range<u32>>,
    pub opaque: Range<u32>,
    /// Where the instance ranges the passes draw lie in the slots, when not
    /// where they say: runs `(first instance drawn, slots)`, in draw
    /// order (a node pool's; see [`Self::pooled`]).
    pub draw_map: Option<Vec<(u32, Range<u32>)>>,
    /// Slots whose records a rewrite leaves as they are: a node pool's
    /// resident nodes, not drawn (sorted by start; see [`crate::node_pool`]).
    pub keep: Vec<Range<u32>>,
}

impl InstanceLayout {
    /// The instance records of slots `range`.
    pub fn instances(&self, cloud: &PointCloud, range: std::ops::Range<usize>) -> Vec<SplatInstance> {
        range
            .map(|slot| {
                if self.order[slot] == VACANT {
                    return SplatInstance::VACANT;
                }
                let i = self.order[slot] as usize;
                let [r, g, b] = cloud.colours[i];
                // A two-sided splat carries a negative radius (see `SplatInstance`).
                let side = if cloud.is_two_sided(i) { -1.0 } else { 1.0 };
                SplatInstance {
                    position: cloud.positions[i].to_array(),
                    radius: side * cloud.radii[i] * self.scale_of[slot],
                    normal: cloud.normals[i].to_array(),
                    colour: [r, g, b, 255],
                    opacity: cloud.opacity[i].clamp(0.0, 1.0),
                }
            })
            .collect()
    }

    /// Whether each slot of `range` is one a rewrite leaves as it is ([`Self::keep`]).
    pub fn kept_in(&self, range: Range<usize>) -> Vec<bool> {
        let mut kept = vec![false; range.len()];
        let first = self.keep.partition_point(|r| (r.end as usize) <= range.start);
        for run in self.keep[first..].iter().take_while(|r| (r.start as usize) < range.end) {
            let (from, to) = ((run.start as usize).max(range.start), (run.end as usize).min(range.end));
            kept[from - range.start..to - range.start].fill(true);
        }
        kept
    }

    /// A bit per slot, 32 to a word: set where a slot holds a splat drawn
    /// (not a node pool's vacant or resident slots). What `tiled` projects.
    pub fn live_bits(&self) -> Vec<u32> {
        let mut bits = vec![0u32; self.order.len().div_ceil(32).max(1)];
        if self.draw_map.is_none() {
            // Packed (every slot a splat): no pass over the slots, as a moving model rewrites every frame.
            bits.fill(u32::MAX);
            return bits;
        }
        for (slot, &splat) in self.order.iter().enumerate() {
            if splat != VACANT {
                bits[slot / 32] |= 1 << (slot % 32);
            }
        }
        bits
    }

    /// The splats of the nodes `spans` as a node pool placed them
    /// ([`crate::node_pool`]), vacant slots between them, each node's in
    /// group order when `grouping` (one group per splat) is given. The
    /// instance ranges a pass draws (the groups) are then in a draw order of
    /// their own, group by group and node by node within one, and
    /// [`Self::draw_map`] says where in the slots each run of it lies.
    /// Ungrouped, the draw order is the slots' (one group of every splat; vacant slots are skipped).
    pub fn pooled(placement: &Placement, spans: &NodeSpans, grouping: Option<&Grouping>) -> Self {
        let capacity = placement.capacity;
        let mut order = vec![VACANT; capacity as usize];
        let mut scale_of = vec![1.0; capacity as usize];
        let nodes = spans.0.iter().map(|(_, splats)| splats).zip(&placement.slots);
        let Some(grouping) = grouping else {
            for (splats, slots) in nodes {
                for (slot, splat) in slots.clone().zip(splats.clone()) {
                    order[slot as usize] = splat;
                }
            }
            let mut drawn = 0u32;
            let mut draw_map = Vec::new();
            for run in placement.live() {
                draw_map.push((drawn, run.clone()));
                drawn += run.len() as u32;
            }
            return Self {
                order,
                scale_of,
                groups: std::iter::once(0..drawn).collect(),
                transparent_groups: std::iter::once(0..drawn).collect(),
                opaque: drawn..drawn,
                draw_map: Some(draw_map),
                keep: placement.resident.clone(),
            };
        };
        let k = grouping.ranges.len().max(1);
        let mut group_of = vec![0u32; spans.splats() as usize];
        for (g, range) in grouping.ranges.iter().enumerate() {
            for &splat in &grouping.order[range.start as usize..range.end as usize] {
                group_of[splat as usize] = g as u32;
            }
        }
        // Each group's runs of slots, node by node.
        let mut runs: Vec<Vec<Range<u32>>> = vec![Vec::new(); k];
        for (splats, slots) in nodes {
            let mut counts = vec![0u32; k];
            splats.clone().for_each(|s| counts[group_of[s as usize] as usize] += 1);
            let mut starts = Vec::with_capacity(k);
            let mut at = slots.start;
            for (g, &count) in counts.iter().enumerate() {
                starts.push(at);
                if count > 0 {
                    runs[g].push(at..at + count);
                    let scale = grouping.radius_scale.get(g).copied().unwrap_or(1.0);
                    scale_of[at as usize..(at + count) as usize].fill(scale);
                }
                at += count;
            }
            for splat in splats.clone() {
                let next = &mut starts[group_of[splat as usize] as usize];
                order[*next as usize] = splat;
                *next += 1;
            }
        }
        let (mut groups, mut draw_map, mut drawn) = (Vec::with_capacity(k), Vec::new(), 0u32);
        for group_runs in runs {
            let start = drawn;
            for run in group_runs {
                draw_map.push((drawn, run.clone()));
                drawn += run.len() as u32;
            }
            groups.push(start..drawn);
        }
        Self {
            order,
            scale_of,
            transparent_groups: groups.clone(),
            groups,
            opaque: drawn..drawn,
            draw_map: Some(draw_map),
            keep: placement.resident.clone(),
        }
    }

    /// The cloud in its own order, one group of everything.
    pub fn plain(cloud: &PointCloud) -> Self {
        let n = cloud.len() as u32;
        Self {
            order: (0..n).collect(),
            scale_of: vec![1.0; n as usize],
            groups: std::iter::once(0..n).collect(),
            transparent_groups: std::iter::once(0..n).collect(),
            opaque: n..n,
            draw_map: None,
            keep: Vec::new(),
        }
    }

    /// Group by group (`order`'s runs `ranges`, radii times `scales[k]`). When
    /// the cloud has both transparent and opaque splats, each group's
    /// transparent splats come first, and every opaque splat follows the
    /// groups once more at its own radius.
    pub fn grouped(cloud: &PointCloud, order: &[u32], scales: &[f32], ranges: &[Range<u32>]) -> Self {
        let opaque_splat = |i: u32| cloud.opacity[i as usize] >= 1.0;
        let mixed = cloud.has_transparency() && cloud.opacity.iter().any(|&a| a >= 1.0);
        let mut out = Self {
            order: Vec::with_capacity(order.len()),
            scale_of: Vec::with_capacity(order.len()),
            groups: Vec::with_capacity(ranges.len()),
            transparent_groups: Vec::with_capacity(ranges.len()),
            opaque: 0..0,
            draw_map: None,
            keep: Vec::new(),
        };
        for (k, range) in ranges.iter().enumerate() {
            let run = &order[range.start as usize..range.end as usize];
            let scale = scales.get(k).copied().unwrap_or(1.0);
            let start = out.order.len() as u32;
            if mixed {
                out.order.extend(run.iter().copied().filter(|&i| !opaque_splat(i)));
                let transparent_end = out.order.len() as u32;
                out.order.extend(run.iter().copied().filter(|&i| opaque_splat(i)));
                out.transparent_groups.push(start..transparent_end);
            } else {
                out.order.extend_from_slice(run);
                out.transparent_groups.push(start..start + run.len() as u32);
            }
            out.scale_of.resize(out.order.len(), scale);
            out.groups.push(start..out.order.len() as u32);
        }
        let end = out.order.len() as u32;
        if mixed {
            out.order.extend((0..cloud.len() as u32).filter(|&i| opaque_splat(i)));
            out.scale_of.resize(out.order.len(), 1.0);
        }
        out.opaque = end..out.order.len() as u32;
        out
    }
}
