//! New splats shown in a slot ([`Slot`]): a moving scene's next frame, or a
//! subset's new choice (the nodes under a point budget, the splats beside a
//! hybrid frame's triangles; [`crate::frame::subset::Subset`]). What the
//! slot's frames prepared is carried over, not made anew: every grouping
//! kept is Zhang & Pajarola's hash grouping redone on a fixed lattice (in
//! milliseconds, only near what moved), and every GPU copy is rewritten in
//! place (reallocated when the count changed). Shadows are keyed by the
//! splats they are for, so the next frame computes its own.

use std::sync::Arc;

use super::{FrameError, PreparedScene, with_extension};
use crate::cloud::PointCloud;
use crate::frame::subset::{Choice, NodeSpans};
use crate::gpu_renderer::GpuRenderer;
use crate::gpu_scene::Arrangement;
use crate::grouping::regroup::{HashRegrouper, Lattice};
use crate::report::FrameUpdate;
use crate::scene_cache::{Keep, SceneGrouping, Slot};

/// The splats a slot draws, in world space, and the key that names them.
pub(super) struct Drawn {
    pub(super) key: u64,
    pub(super) cloud: Arc<PointCloud>,
    /// Whether some splat is less than opaque (asked every frame, so kept).
    pub(super) transparent: bool,
    /// The nodes the splats came in, when a tree of nodes chose them (a
    /// streamed selection's, or the nodes under a point budget).
    pub(super) spans: Option<Arc<NodeSpans>>,
}

impl Drawn {
    pub(super) fn new(key: u64, cloud: Arc<PointCloud>) -> Self {
        Self { key, transparent: cloud.has_transparency(), cloud, spans: None }
    }

    /// The same splats, which came in the nodes `spans`.
    pub(super) fn in_nodes(self, spans: Option<Arc<NodeSpans>>) -> Self {
        Self { spans, ..self }
    }
}

impl PreparedScene {
    /// The splats `slot` draws (a subset's, once it has chosen).
    pub(super) fn drawn(&self, slot: Slot) -> &Drawn {
        self.drawn[slot.index()].as_ref().expect("a subset's slot is drawn once it has chosen")
    }

    /// Shows a subset's `choice` in `slot`: nothing changes when it holds
    /// no new splats (its last ones again), else they are shown as the slot's next frame.
    pub(super) fn show_choice(
        &mut self,
        gpu: Option<&GpuRenderer>,
        slot: Slot,
        choice: Choice,
    ) -> Result<(), FrameError> {
        if choice.cloud.is_none() && self.drawn[slot.index()].is_some() {
            return Ok(());
        }
        // A subset's first choice always holds its splats.
        let cloud = Arc::new(choice.cloud.unwrap_or_default());
        self.show(gpu, slot, Drawn::new(choice.key, cloud).in_nodes(choice.spans)).map(|_| ())
    }

    /// Shows `drawn` in `slot`: the slot's groupings are regrouped, its GPU
    /// copies rewritten (on `gpu`; dropped without one). Returns what that took.
    pub(super) fn show(
        &mut self,
        gpu: Option<&GpuRenderer>,
        slot: Slot,
        drawn: Drawn,
    ) -> Result<FrameUpdate, FrameError> {
        let key = drawn.key;
        self.drawn[slot.index()] = Some(drawn);
        let mut update = FrameUpdate::default();
        let specs: Vec<_> = self.prepared.groupings.keys().filter(|(s, _)| *s == slot).map(|(_, g)| g).collect();
        let mut fresh: Vec<SceneGrouping> = Vec::with_capacity(specs.len());
        for spec in specs {
            // A spec whose algorithm was regrouped this frame takes those groups.
            let shared = fresh.iter().find(|g| g.spec.algo == spec.algo).map(|g| (Arc::clone(&g.grouping), g.seconds));
            let node_labels =
                (shared.is_none() && slot == Slot::Whole && self.streamed).then(|| self.node_grouping(spec)).flatten();
            let grouping = match (shared, node_labels) {
                (Some((grouping, seconds)), _) => SceneGrouping {
                    spec,
                    grouping: Arc::new(with_extension(grouping.as_ref().clone(), spec)),
                    seconds,
                    cached: false,
                },
                // A streamed selection's groups are its nodes' labels, made when each arrived.
                (None, Some(node_labels)) => node_labels,
                (None, None) => {
                    let (grouping, labelled) = self.regroup(slot, spec)?;
                    update.regrouped += labelled;
                    update.regroup_ms += grouping.seconds * 1e3;
                    grouping
                }
            };
            update.regroup_ms_of.push((spec, grouping.seconds * 1e3));
            fresh.push(grouping);
        }
        for grouping in fresh {
            self.prepared.groupings.insert((slot, grouping.spec), Keep { drawn: key, value: grouping });
        }
        let Some(gpu) = gpu else {
            self.prepared.uploads.retain(|(s, _)| *s != slot);
            return Ok(update);
        };
        let cloud = Arc::clone(&self.drawn(slot).cloud);
        let uploads: Vec<_> = self.prepared.uploads.keys().filter(|(s, _)| *s == slot).collect();
        for upload_key in uploads {
            let grouping = upload_key.1.and_then(|spec| self.prepared.groupings.get(&(slot, spec)));
            let grouping = grouping.map(|kept| Arc::clone(&kept.value.grouping));
            let spans = self.pooled_nodes(slot, grouping.is_some());
            let upload = self.prepared.uploads.get(&upload_key).expect("listed above");
            let started = std::time::Instant::now();
            let arrangement = Arrangement::of(spans.as_deref(), grouping.as_deref());
            let bytes = upload.value.rewrite(&gpu.ctx.device, &gpu.ctx.queue, &cloud, arrangement);
            upload.drawn = key;
            let ms = started.elapsed().as_secs_f64() * 1e3;
            update.upload_of.push((upload_key.1, ms, bytes));
            update.upload_ms += ms;
            update.uploaded_bytes += bytes;
        }
        self.uploaded_bytes += update.uploaded_bytes;
        Ok(update)
    }

    /// Hash grouping `spec` of the splats `slot` draws by the slot's
    /// regrouper (made on first use); returns it and the splats labelled.
    pub(super) fn regroup(
        &mut self,
        slot: Slot,
        spec: crate::grouping::GroupingSpec,
    ) -> Result<(SceneGrouping, usize), FrameError> {
        let Some(options) = spec.algo.hash_options() else { return Err(FrameError::NoGrouping(spec)) };
        let key = (slot, spec.algo);
        if !self.prepared.regroupers.contains(&key) {
            let lattice = self.lattice_of(slot);
            let regrouper =
                HashRegrouper::new(lattice, options).map_err(|source| FrameError::Grouping { spec, source })?;
            self.prepared.regroupers.insert(key, regrouper);
        }
        let cloud = Arc::clone(&self.drawn(slot).cloud);
        let regrouper = self.prepared.regroupers.get(&key).expect("made above");
        let started = std::time::Instant::now();
        let grouping = with_extension(regrouper.regroup(&cloud), spec);
        let seconds = started.elapsed().as_secs_f64();
        let labelled = regrouper.stats().labelled;
        Ok((SceneGrouping { spec, grouping: Arc::new(grouping), seconds, cached: false }, labelled))
    }

    /// The lattice `slot`'s hash groups are counted on: a moving scene's
    /// rest pose (else its first frame shown), and the whole scene's for a
    /// subset, whatever it chose.
    fn lattice_of(&mut self, slot: Slot) -> Lattice {
        match slot {
            Slot::Whole => self.lattice.unwrap_or_else(|| Lattice::of(self.cloud())),
            Slot::Budget | Slot::Hybrid => {
                let whole = Arc::clone(self.cloud());
                *self.subset_lattice.get_or_insert_with(|| Lattice::of(&whole))
            }
        }
    }
}
