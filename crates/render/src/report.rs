//! What a frame measured while it ran, returned with its image: the plan is
//! final when made (crate::plan), and everything counted or timed during
//! the frame goes here instead. `--explain` prints the plan, then this.

use std::fmt;

use super::plan::BufferDesc;
use crate::grouping::GroupingSpec;

/// The tile pipeline's lists in a frame of `tiled`.
#[derive(Debug, Clone, PartialEq)]
pub struct TileLists {
    /// (tile, splat) pairs counted over the discs' pixel boxes, and the
    /// room the entry buffer had for them.
    pub entries: u64,
    pub capacity: u64,
    /// Of the pairs counted, those kept: the discs that meet their tile.
    pub kept: u64,
    /// The longest tile list, in splats.
    pub longest: u32,
    /// Whether the lists passed the room the frame was first drawn with, so
    /// that it was drawn again with more (kept for later frames).
    pub retried: bool,
    /// Slots of the per-splat buffers (the scene's splats, or fewer).
    pub slots: u64,
    /// When the splats reaching the frame were packed into fewer slots
    /// than the scene has splats: how many reached it.
    pub packed: Option<u64>,
    /// The tile pipeline's buffers at the size this frame used.
    pub buffers: Vec<BufferDesc>,
}

/// A frame drawn in several sub-frames to bound its memory.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SubFrames {
    pub count: usize,
    /// Whether the frame (or a sub-frame) was cut because `tiled`'s splats
    /// or lists would pass the memory given to it.
    pub for_tiles: bool,
    /// The largest sub-frame's size (with its margin), whose plan the frame reports.
    pub largest: (u32, u32),
    pub margin: u32,
    /// The MiB one render may take.
    pub budget_mib: u64,
}

/// What one frame measured.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameReport {
    /// `tiled`: its lists (the largest sub-frame's, when drawn in sub-frames).
    pub tile_lists: Option<TileLists>,
    /// `tiled`: pixels whose window of waiting hits overflowed (finished a
    /// layer at a time, exactly), summed over the sub-frames drawn (their
    /// margins included).
    pub window_overflows: Option<u32>,
    /// Set when the frame was drawn in sub-frames.
    pub subframes: Option<SubFrames>,
    /// The nodes a point budget selected, and what that cost.
    pub budget: Option<BudgetStats>,
    /// The leaves and splats a frame with triangles drew, and what that cost.
    pub hybrid: Option<HybridStats>,
    /// Scene lights: what their shadows took, in lines, and the milliseconds
    /// and MiB of the translucent shadow map tables.
    pub shadows: Vec<String>,
    pub shadow_ms: Option<f64>,
    pub shadow_table_mib: Option<f64>,
    /// A moving scene: what advancing it to this frame cost.
    pub update: Option<FrameUpdate>,
    /// A streamed selection: the GPU pool its nodes sit in.
    pub pool: Option<PoolStats>,
}

/// The node pool a streamed frame drew from ([`crate::node_pool`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PoolStats {
    /// Splat slots in the pool, and the bytes of their records.
    pub slots: usize,
    pub bytes: u64,
    /// Nodes drawn, and nodes kept on the GPU undrawn (left by earlier views).
    pub drawn: usize,
    pub kept: usize,
}

impl PoolStats {
    /// One line for `--explain` and the viewer.
    pub fn describe(&self) -> String {
        format!(
            "node pool: {} nodes drawn, {} kept on the GPU from earlier views; {} slots, {:.1} MiB",
            self.drawn,
            self.kept,
            self.slots,
            self.bytes as f64 / (1 << 20) as f64
        )
    }
}

impl FrameReport {
    /// The report in lines, for `--explain` and the viewer.
    pub fn lines(&self) -> Vec<String> {
        let mut lines = Vec::new();
        if let Some(w) = &self.subframes {
            let why = if w.for_tiles { "the splats or tile lists of `tiled`" } else { "the whole frame's targets" };
            lines.push(format!(
                "drawn in {} sub-frames (the plan is the largest's, {}x{} with a {} px margin): {why} would pass the \
                 GPU's limits or the {} MiB a render may take",
                w.count, w.largest.0, w.largest.1, w.margin, w.budget_mib
            ));
        }
        if let Some(t) = &self.tile_lists {
            lines.push(format!(
                "tile lists: {} entries kept of {} counted over the discs' boxes (room for {}), the longest {} splats{}{}",
                t.kept,
                t.entries,
                t.capacity,
                t.longest,
                t.packed.map_or(String::new(), |p| format!(
                    "; {p} splats reached the part, packed into {} slots (the scene has more splats)",
                    t.slots
                )),
                if t.retried {
                    "; they passed the room the frame was first drawn with, so it was drawn again with more"
                } else {
                    ""
                }
            ));
        }
        if let Some(n) = self.window_overflows {
            lines.push(format!(
                "tile windows: {n} pixels had more than {} hits waiting and were finished a layer at a time, exactly",
                super::tile_engine::WINDOW
            ));
        }
        lines.extend(self.budget.as_ref().map(BudgetStats::describe));
        lines.extend(self.hybrid.as_ref().map(HybridStats::describe));
        lines.extend(self.pool.as_ref().map(PoolStats::describe));
        lines.extend(self.shadows.iter().cloned());
        lines
    }
}

impl fmt::Display for FrameReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let lines = self.lines();
        if lines.is_empty() {
            return Ok(());
        }
        writeln!(f, "measured while drawing:")?;
        for line in lines {
            writeln!(f, "  {line}")?;
        }
        Ok(())
    }
}

/// What a budgeted frame's selection drew and cost.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BudgetStats {
    pub budget: u32,
    /// Nodes and splats drawn.
    pub nodes: usize,
    pub splats: usize,
    /// Node selection, in milliseconds.
    pub select_ms: f64,
    /// Gathering the selected splats, regrouping and rewriting the GPU copies
    /// (only when the selection changed), in milliseconds.
    pub update_ms: f64,
    /// Whether the selection changed.
    pub changed: bool,
    /// The hierarchy: its build seconds (0 when it came from the cache), nodes and bytes.
    pub build_s: f64,
    pub hierarchy_nodes: usize,
    pub hierarchy_bytes: usize,
}

impl BudgetStats {
    /// One line for the plan's notes and `--explain`.
    pub fn describe(&self) -> String {
        format!(
            "point budget {}: {} splats of {} nodes drawn; selection {:.2} ms, update {:.1} ms{}; hierarchy {} nodes, {:.1} MiB, {}",
            self.budget,
            self.splats,
            self.nodes,
            self.select_ms,
            self.update_ms,
            if self.changed { "" } else { " (unchanged)" },
            self.hierarchy_nodes,
            self.hierarchy_bytes as f64 / (1 << 20) as f64,
            if self.build_s > 0.0 { format!("built in {:.2} s", self.build_s) } else { "from the cache".into() },
        )
    }
}

/// What a frame with triangles drew and cost.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct HybridStats {
    /// Leaves are drawn as triangles where their splats would pass this radius in pixels.
    pub pixels: f32,
    pub triangles: u32,
    pub splats: usize,
    pub triangle_leaves: usize,
    pub splat_leaves: usize,
    pub transition_splats: usize,
    /// Choosing the leaves, in milliseconds.
    pub select_ms: f64,
    /// Gathering the splats and rewriting their GPU copy (when they changed), in milliseconds.
    pub update_ms: f64,
    pub changed: bool,
}

impl HybridStats {
    /// One line for the plan's notes and `--explain`.
    pub fn describe(&self) -> String {
        let pixels = self.pixels;
        format!(
            "meshes: {} triangles of {} leaves and {} splats ({} leaves as splats, {} transition splats) drawn; \
             leaves as triangles where splats exceed {pixels} px; selection {:.2} ms, update {:.1} ms{}",
            self.triangles,
            self.triangle_leaves,
            self.splats,
            self.splat_leaves,
            self.transition_splats,
            self.select_ms,
            self.update_ms,
            if self.changed { "" } else { " (unchanged)" },
        )
    }
}

/// What moving a scene to its next frame cost.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameUpdate {
    /// Hash regrouping of every grouping drawn, in milliseconds.
    pub regroup_ms: f64,
    /// Writing the splats to the GPU (the records built and the buffers written), in milliseconds.
    pub upload_ms: f64,
    /// Splats whose group was computed (all of them unless the change was local).
    pub regrouped: usize,
    pub uploaded_bytes: u64,
    /// Per grouping kept: the milliseconds of its regroup (shared by specs of one algorithm).
    pub regroup_ms_of: Vec<(GroupingSpec, f64)>,
    /// Per GPU copy (by the grouping it draws): milliseconds of its rewrite and bytes written.
    pub upload_of: Vec<(Option<GroupingSpec>, f64, u64)>,
}

impl FrameUpdate {
    /// The regroup milliseconds of grouping `spec` (0 for none, or one not kept).
    pub fn regroup_ms_for(&self, spec: Option<GroupingSpec>) -> f64 {
        self.regroup_ms_of.iter().find(|(s, _)| Some(*s) == spec).map_or(0.0, |(_, ms)| *ms)
    }

    /// The upload milliseconds and bytes of the GPU copy drawing `spec`.
    pub fn upload_for(&self, spec: Option<GroupingSpec>) -> (f64, u64) {
        self.upload_of.iter().find(|(s, _, _)| *s == spec).map_or((0.0, 0), |(_, ms, bytes)| (*ms, *bytes))
    }
}
