//! A point cloud on the GPU: splat instances in vertex buffers.
//!
//! Splats live in instance (vertex) buffers rather than storage buffers,
//! because lavapipe caps a storage binding at 128 MiB. Buffers are split into
//! chunks of at most [`MAX_CHUNK_BYTES`] so that no single allocation nears a
//! driver's buffer-size limit; a 2.3M-point cloud takes three 32 MiB chunks.

use wgpu::util::DeviceExt;

use super::gpu_data::SplatInstance;
use crate::cloud::PointCloud;

/// Largest vertex buffer made for one chunk of splats.
pub const MAX_CHUNK_BYTES: usize = 32 << 20;

/// The splats of one cloud, uploaded.
pub struct GpuCloud {
    pub chunks: Vec<(wgpu::Buffer, u32)>,
    pub len: usize,
    pub mean_radius: f32,
}

impl GpuCloud {
    pub fn upload(device: &wgpu::Device, cloud: &PointCloud) -> Self {
        let per_chunk = (MAX_CHUNK_BYTES / std::mem::size_of::<SplatInstance>())
            .min(device.limits().max_buffer_size as usize / std::mem::size_of::<SplatInstance>())
            .max(1);
        let mut chunks = Vec::new();
        let mut start = 0;
        while start < cloud.len() {
            let end = (start + per_chunk).min(cloud.len());
            let instances: Vec<SplatInstance> = (start..end)
                .map(|i| {
                    let [r, g, b] = cloud.colors[i];
                    SplatInstance {
                        position: cloud.positions[i].to_array(),
                        radius: cloud.radii[i],
                        normal: cloud.normals[i].to_array(),
                        color: [r, g, b, (cloud.opacity[i].clamp(0.0, 1.0) * 255.0).round() as u8],
                    }
                })
                .collect();
            let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("GpuCloud::splats"),
                contents: bytemuck::cast_slice(&instances),
                usage: wgpu::BufferUsages::VERTEX,
            });
            chunks.push((buffer, (end - start) as u32));
            start = end;
        }
        Self { chunks, len: cloud.len(), mean_radius: cloud.mean_radius() }
    }

    /// Draws every splat as a 4-vertex strip instance; the pipeline must be set.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        for (buffer, count) in &self.chunks {
            pass.set_vertex_buffer(0, buffer.slice(..));
            pass.draw(0..4, 0..*count);
        }
    }
}
