//! Which instance slots of a [`crate::gpu_scene::GpuScene`] hold a splat
//! drawn: a bit per slot, 32 to a word, on the GPU for `tiled`'s projection
//! (which reads every slot) and on the CPU to write only the words that
//! changed. A node pool keeps the records of nodes no longer drawn in their
//! slots ([`crate::node_pool`]); the raster passes skip them by drawing only
//! the placed runs, `tiled` by this mask. No paper of ours covers it.

/// The mask on the GPU and the copy it was last written from.
pub struct LiveMask {
    buffer: wgpu::Buffer,
    bits: Vec<u32>,
}

impl LiveMask {
    /// Uploads `bits`.
    pub fn new(device: &wgpu::Device, bits: Vec<u32>) -> Self {
        Self { buffer: buffer(device, &bits), bits }
    }

    /// The mask on the GPU.
    pub fn buffer(&self) -> &wgpu::Buffer {
        &self.buffer
    }

    /// Writes `bits` where they differ from the last ones (the span from the
    /// first word that differs to the last), in a new buffer when the words
    /// changed in number. Returns the bytes written.
    pub fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, bits: Vec<u32>) -> u64 {
        let written = if bits.len() != self.bits.len() {
            self.buffer = buffer(device, &bits);
            bits.len() * 4
        } else {
            let differ = |(a, b): (&u32, &u32)| a != b;
            let first = bits.iter().zip(&self.bits).position(differ);
            let last = bits.iter().zip(&self.bits).rposition(differ);
            match (first, last) {
                (Some(first), Some(last)) => {
                    queue.write_buffer(&self.buffer, first as u64 * 4, bytemuck::cast_slice(&bits[first..=last]));
                    (last + 1 - first) * 4
                }
                _ => 0,
            }
        };
        self.bits = bits;
        written as u64
    }
}

fn buffer(device: &wgpu::Device, bits: &[u32]) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("GpuScene::live"),
        contents: bytemuck::cast_slice(bits),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
    })
}
