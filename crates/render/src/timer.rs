//! GPU timestamps around each plan pass, when the adapter supports them.
//!
//! Each plan pass writes a timestamp at the start of its first render pass
//! and at the end of its last one (the K render passes of the group images
//! are one plan pass); the renderer resolves them into a buffer in the same
//! submission, and [`PassTimer::read`] maps it after the frame to give
//! milliseconds per pass. The timer is sized from the plan: the renderer
//! makes a larger one when a plan has more passes.

use super::context::{GpuContext, GpuError};

pub struct PassTimer {
    /// Plan passes it can time.
    passes: u32,
    query_set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    period_ns: f64,
}

impl PassTimer {
    /// A timer for `passes` plan passes, or `None` when the device has no timestamp queries.
    pub fn new(ctx: &GpuContext, passes: usize) -> Option<Self> {
        if !ctx.device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
            return None;
        }
        let passes = u32::try_from(passes.max(1)).ok()?;
        let count = 2 * passes;
        let bytes = count as u64 * 8;
        let query_set = ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("PassTimer::queries"),
            ty: wgpu::QueryType::Timestamp,
            count,
        });
        let buffer = |label, usage| {
            ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage,
                mapped_at_creation: false,
            })
        };
        Some(Self {
            passes,
            query_set,
            resolve: buffer("PassTimer::resolve", wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC),
            readback: buffer("PassTimer::readback", wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ),
            period_ns: ctx.queue.get_timestamp_period() as f64,
        })
    }

    /// Plan passes it can time.
    pub fn capacity(&self) -> usize {
        self.passes as usize
    }

    /// The timestamp writes for pass `index`, if it can be timed.
    pub fn writes(&self, index: usize) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let i = u32::try_from(index).ok().filter(|&i| i < self.passes)?;
        Some(wgpu::RenderPassTimestampWrites {
            query_set: &self.query_set,
            beginning_of_pass_write_index: Some(2 * i),
            end_of_pass_write_index: Some(2 * i + 1),
        })
    }

    /// Timestamp writes for pass `index` when it spans several render passes:
    /// the first writes the start, the last the end.
    pub fn writes_span(&self, index: usize, first: bool, last: bool) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let w = self.writes(index)?;
        if !first && !last {
            return None;
        }
        Some(wgpu::RenderPassTimestampWrites {
            beginning_of_pass_write_index: if first { w.beginning_of_pass_write_index } else { None },
            end_of_pass_write_index: if last { w.end_of_pass_write_index } else { None },
            ..w
        })
    }

    /// Resolves the timestamps of `passes` passes into the readback buffer.
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder, passes: usize) {
        let count = (2 * passes as u32).min(2 * self.passes);
        if count == 0 {
            return;
        }
        encoder.resolve_query_set(&self.query_set, 0..count, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.readback, 0, count as u64 * 8);
    }

    /// Milliseconds spent in each of the first `passes` passes of the last frame.
    pub fn read(&self, ctx: &GpuContext, passes: usize) -> Result<Vec<f64>, GpuError> {
        let passes = passes.min(self.passes as usize);
        if passes == 0 {
            return Ok(Vec::new());
        }
        let bytes = passes as u64 * 16;
        let (sender, receiver) = std::sync::mpsc::channel();
        self.readback.map_async(wgpu::MapMode::Read, ..bytes, move |r| {
            let _ = sender.send(r);
        });
        ctx.wait_idle()?;
        receiver
            .recv()
            .map_err(|e| GpuError::Readback(e.to_string()))?
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        let times = {
            let mapped = self.readback.get_mapped_range(..bytes).map_err(|e| GpuError::Readback(e.to_string()))?;
            let stamps: Vec<u64> =
                mapped.chunks_exact(8).map(|c| u64::from_le_bytes(c.try_into().unwrap_or([0; 8]))).collect();
            stamps.chunks_exact(2).map(|p| p[1].saturating_sub(p[0]) as f64 * self.period_ns / 1e6).collect()
        };
        self.readback.unmap();
        Ok(times)
    }
}
