//! Each group's splats back to front for the view, in the scene's own
//! instance buffers: what the transparent passes that blend in order draw
//! (Zhang & Pajarola §5.2.1: every group S_k back to front into its image).
//!
//! The order is made on the CPU, the fast path on lavapipe: Gunjee's bucket
//! sort of the instances (`spatial::order`, O(n); exact along every pixel ray
//! up to one slab, where the BSP traversal lets overlapping discs stray), then
//! a stable partition by group, so each group keeps the global back-to-front
//! order. The instance records are then gathered in that order and written
//! over the scene's vertex buffers. The splats stay instance vertex buffers
//! (no storage binding, see `gpu_scene`), so the order is applied to the
//! records themselves rather than through an index buffer. Nothing is sorted
//! or written when the eye and view direction are bit for bit those of the
//! last frame: a settled viewer, or `bench`'s timed frames of one view,
//! upload nothing.

use std::ops::Range;

use glam::Vec3;

use super::gpu_data::{SplatInstance, SplatLight};
use crate::spatial::order::{OrderKind, Orderer, ViewRay};

/// The eye and view direction an order was made for, as bits (so any change
/// counts, and NaN never equals itself as a float would not), and the order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct ViewKey([u32; 6], OrderKind);

impl ViewKey {
    fn of(view: ViewRay, kind: OrderKind) -> Self {
        let [a, b, c] = view.eye.to_array().map(f32::to_bits);
        let [d, e, f] = view.forward.to_array().map(f32::to_bits);
        Self([a, b, c, d, e, f], kind)
    }
}

/// The group of an instance that is drawn in no order.
const UNORDERED: u32 = u32::MAX;

/// The instances of a grouped scene and the view their buffers are sorted for.
pub struct InstanceOrder {
    /// As uploaded: group by group, each group's run `groups[k]`.
    uploaded: Vec<SplatInstance>,
    groups: Vec<Range<u32>>,
    /// The group of each uploaded instance ([`UNORDERED`] for instances in no
    /// group, such as the opaque run drawn apart, which stay where they are).
    group_of: Vec<u32>,
    /// Each order, prepared on the first frame that asks for it (the BSP tree costs a build).
    orderers: Vec<Orderer>,
    positions: Vec<Vec3>,
    order: Vec<u32>,
    /// What the buffers hold now.
    current: Vec<SplatInstance>,
    /// The uploaded index of each current record.
    source: Vec<u32>,
    /// Each uploaded instance's shadow coefficients, in a frame lit by
    /// scene lights (empty otherwise): they follow their splat's record.
    lights: Vec<SplatLight>,
    view: Option<ViewKey>,
    uploads: u64,
    slab: f32,
}

impl InstanceOrder {
    /// The order of `instances`, uploaded group by group in `groups`.
    pub fn new(instances: Vec<SplatInstance>, groups: Vec<Range<u32>>) -> Self {
        let positions = instances.iter().map(|s| Vec3::from_array(s.position)).collect();
        let mut group_of = vec![UNORDERED; instances.len()];
        for (g, range) in groups.iter().enumerate() {
            group_of[range.start as usize..range.end as usize].fill(g as u32);
        }
        Self {
            group_of,
            source: (0..instances.len() as u32).collect(),
            lights: Vec::new(),
            current: instances.clone(),
            uploaded: instances,
            groups,
            orderers: Vec::new(),
            positions,
            order: Vec::new(),
            view: None,
            uploads: 0,
            slab: 0.0,
        }
    }

    /// Sorts each group back to front for `view` in the order `kind` and
    /// writes the records over `chunks` (the scene's instance buffers, in
    /// order); returns whether it did (false when the view and order are the
    /// last one's).
    pub fn apply(
        &mut self,
        queue: &wgpu::Queue,
        chunks: &[(wgpu::Buffer, u32)],
        light_chunks: Option<&[wgpu::Buffer]>,
        view: ViewRay,
        kind: OrderKind,
    ) -> bool {
        let key = ViewKey::of(view, kind);
        if self.view == Some(key) || self.uploaded.is_empty() {
            return false;
        }
        let at = match self.orderers.iter().position(|o| o.kind() == kind) {
            Some(at) => at,
            None => {
                let radii: Vec<f32> = self.uploaded.iter().map(|s| s.radius.abs()).collect();
                self.orderers.push(Orderer::new(kind, &self.positions, &radii));
                self.orderers.len() - 1
            }
        };
        let orderer = &mut self.orderers[at];
        self.slab = orderer.back_to_front(&self.positions, view, &mut self.order);
        // A stable partition of the one order into the groups' runs.
        let mut fill: Vec<u32> = self.groups.iter().map(|r| r.start).collect();
        for &i in &self.order {
            let g = self.group_of[i as usize];
            if g == UNORDERED {
                continue;
            }
            let g = g as usize;
            self.current[fill[g] as usize] = self.uploaded[i as usize];
            self.source[fill[g] as usize] = i;
            fill[g] += 1;
        }
        let mut start = 0usize;
        for (buffer, count) in chunks {
            let end = start + *count as usize;
            queue.write_buffer(buffer, 0, bytemuck::cast_slice(&self.current[start..end]));
            start = end;
        }
        if let Some(light_chunks) = light_chunks {
            self.write_lights(queue, chunks, light_chunks);
        }
        self.view = Some(key);
        self.uploads += 1;
        true
    }

    /// Takes each uploaded instance's shadow coefficients and writes them,
    /// in the current order, over `light_chunks` (beside `chunks`).
    pub fn set_lights(
        &mut self,
        queue: &wgpu::Queue,
        lights: Vec<SplatLight>,
        chunks: &[(wgpu::Buffer, u32)],
        light_chunks: &[wgpu::Buffer],
    ) {
        self.lights = lights;
        self.write_lights(queue, chunks, light_chunks);
    }

    fn write_lights(&self, queue: &wgpu::Queue, chunks: &[(wgpu::Buffer, u32)], light_chunks: &[wgpu::Buffer]) {
        if self.lights.len() != self.uploaded.len() {
            return;
        }
        let mut start = 0usize;
        for ((_, count), buffer) in chunks.iter().zip(light_chunks) {
            let end = start + *count as usize;
            let run: Vec<SplatLight> = self.source[start..end].iter().map(|&i| self.lights[i as usize]).collect();
            queue.write_buffer(buffer, 0, bytemuck::cast_slice(&run));
            start = end;
        }
    }

    /// The records the buffers hold now.
    pub fn current(&self) -> &[SplatInstance] {
        &self.current
    }

    /// How many times the buffers were sorted and written.
    pub fn uploads(&self) -> u64 {
        self.uploads
    }

    /// The slab thickness of the last order: within a group, an earlier
    /// splat's depth is at least a later one's minus this.
    pub fn slab(&self) -> f32 {
        self.slab
    }
}
