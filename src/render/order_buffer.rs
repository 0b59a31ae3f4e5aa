//! The back-to-front order of a scene's splats as a GPU buffer of indices,
//! recomputed and uploaded only when the view changed.
//!
//! Transparent passes that blend in order (Zhang & Pajarola §5.2.1) draw the
//! splats through this buffer. The order comes from a CPU [`Orderer`] (a BSP
//! traversal or Gunjee's bucket sort, O(n), see `spatial::order`), the fast
//! path on lavapipe. A frame whose eye and view direction are bit for bit
//! those of the last upload reuses the buffer: an orbiting viewer re-sorts
//! while the camera moves, and a settled one (or `bench`'s timed frames of
//! one view) uploads nothing.

use crate::spatial::order::{OrderKind, Orderer, ViewRay};

/// The eye and view direction an order was made for, as bits (so that
/// "changed" means any change, and NaN cannot compare equal to itself).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct ViewKey([u32; 6]);

impl ViewKey {
    fn of(view: ViewRay) -> Self {
        let [a, b, c] = view.eye.to_array().map(f32::to_bits);
        let [d, e, f] = view.forward.to_array().map(f32::to_bits);
        Self([a, b, c, d, e, f])
    }
}

/// One order's index buffer and the view it holds.
pub struct OrderBuffer {
    orderer: Orderer,
    order: Vec<u32>,
    buffer: wgpu::Buffer,
    view: Option<ViewKey>,
    slab: f32,
    uploads: u64,
}

impl OrderBuffer {
    /// Prepares `kind` over `points` (world space) with `radii`, and a buffer
    /// of one index per splat (usable as index and storage buffer).
    pub fn new(device: &wgpu::Device, kind: OrderKind, points: &[glam::Vec3], radii: &[f32]) -> Self {
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("OrderBuffer::indices"),
            size: (points.len().max(1) * std::mem::size_of::<u32>()) as u64,
            usage: wgpu::BufferUsages::INDEX
                | wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        Self {
            orderer: Orderer::new(kind, points, radii),
            order: Vec::with_capacity(points.len()),
            buffer,
            view: None,
            slab: 0.0,
            uploads: 0,
        }
    }

    /// The buffer, back to front for `view`: ordered and written only if the
    /// view differs from the last one.
    pub fn for_view(&mut self, queue: &wgpu::Queue, points: &[glam::Vec3], view: ViewRay) -> &wgpu::Buffer {
        let key = ViewKey::of(view);
        if self.view != Some(key) {
            self.slab = self.orderer.back_to_front(points, view, &mut self.order);
            if !self.order.is_empty() {
                queue.write_buffer(&self.buffer, 0, bytemuck::cast_slice(&self.order));
            }
            self.view = Some(key);
            self.uploads += 1;
        }
        &self.buffer
    }

    /// The order last uploaded (CPU copy).
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// The slab thickness of the order last uploaded.
    pub fn slab(&self) -> f32 {
        self.slab
    }

    /// How many times an order was computed and uploaded.
    pub fn uploads(&self) -> u64 {
        self.uploads
    }

    pub fn kind(&self) -> OrderKind {
        self.orderer.kind()
    }
}
