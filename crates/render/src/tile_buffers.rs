//! The buffers the tile pipeline of `tiled` makes and reads
//! ([`crate::tile_engine`] owns them): their usages, the passes' `Tiles`
//! uniform (shaders/tiled_common.wgsl), dispatch sizes within the
//! per-dimension limit, and the map that reads a buffer back.

use wgpu::util::DeviceExt;

use super::context::{GpuContext, GpuError};

/// Invocations per workgroup of the per-splat and per-tile passes (`GROUP`).
pub(crate) const GROUP: u32 = 256;
/// Workgroups per dispatch dimension that every device allows.
pub(crate) const MAX_WORKGROUPS: u32 = 65535;

pub(crate) fn buffer(
    device: &wgpu::Device,
    label: &'static str,
    bytes: u64,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(16),
        usage,
        mapped_at_creation: false,
    })
}

pub(crate) const STORAGE: wgpu::BufferUsages =
    wgpu::BufferUsages::STORAGE.union(wgpu::BufferUsages::COPY_DST).union(wgpu::BufferUsages::COPY_SRC);
pub(crate) const READBACK: wgpu::BufferUsages = wgpu::BufferUsages::MAP_READ.union(wgpu::BufferUsages::COPY_DST);
pub(crate) const INDIRECT: wgpu::BufferUsages = STORAGE.union(wgpu::BufferUsages::INDIRECT);

/// A pass's `Tiles` uniform (shaders/tiled_common.wgsl): the grid, the
/// items `first..first + count` it handles, and the per-splat slots.
pub(crate) fn grid_uniform(
    device: &wgpu::Device,
    (columns, rows): (u32, u32),
    (first, count): (u32, u32),
    room: [u32; 4],
) -> wgpu::Buffer {
    let words = [columns, rows, first, count, room[0], room[1], room[2], room[3]];
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("Tiles::grid"),
        contents: bytemuck::cast_slice(&words),
        usage: wgpu::BufferUsages::UNIFORM,
    })
}

/// Workgroups for `items` items of one invocation each, as a 2D dispatch.
pub(crate) fn dispatch(items: u64, per_group: u32) -> (u32, u32) {
    let groups = items.div_ceil(per_group as u64).max(1);
    let x = groups.min(MAX_WORKGROUPS as u64) as u32;
    (x, groups.div_ceil(x as u64) as u32)
}

pub(crate) fn mib(bytes: u64) -> f64 {
    bytes as f64 / (1u64 << 20) as f64
}

/// Maps `buffer` and reads it as `T`s (waits for the GPU).
pub(crate) fn read<T: bytemuck::Pod>(ctx: &GpuContext, buffer: &wgpu::Buffer) -> Result<Vec<T>, GpuError> {
    let (sender, receiver) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |r| {
        let _ = sender.send(r);
    });
    ctx.wait_idle()?;
    receiver.recv().map_err(|e| GpuError::Readback(e.to_string()))?.map_err(|e| GpuError::Readback(e.to_string()))?;
    let values = {
        let mapped = buffer.get_mapped_range(..).map_err(|e| GpuError::Readback(e.to_string()))?;
        bytemuck::pod_collect_to_vec::<u8, T>(&mapped)
    };
    buffer.unmap();
    Ok(values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dispatches_cover_every_item_within_the_per_dimension_limit() {
        for items in [1u64, 255, 256, 257, 65535 * 256, 65535 * 256 + 1, 40_000_000] {
            let (x, y) = dispatch(items, GROUP);
            assert!(x <= MAX_WORKGROUPS && y <= MAX_WORKGROUPS, "{items}: {x}x{y}");
            assert!(x as u64 * y as u64 * GROUP as u64 >= items, "{items}: {x}x{y} too few");
        }
    }
}
