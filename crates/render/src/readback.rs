//! Copying a rendered texture back: the frame into an `image::RgbaImage`,
//! a depth target into its f32 values.
//!
//! Buffer copies need rows padded to 256 bytes; the padding is stripped here.

use super::context::{GpuContext, GpuError};

/// Reads an `Rgba8Unorm` (or `Rgba8UnormSrgb`) texture into an image.
pub fn read_rgba8(ctx: &GpuContext, texture: &wgpu::Texture) -> Result<image::RgbaImage, GpuError> {
    let pixels = read_texels(ctx, texture, wgpu::TextureAspect::All, 4)?;
    let (width, height) = (texture.width(), texture.height());
    image::RgbaImage::from_raw(width, height, pixels).ok_or_else(|| GpuError::Readback("size mismatch".into()))
}

/// Reads a `Depth32Float` texture's values, row by row from the top.
pub fn read_depth32(ctx: &GpuContext, texture: &wgpu::Texture) -> Result<Vec<f32>, GpuError> {
    let bytes = read_texels(ctx, texture, wgpu::TextureAspect::DepthOnly, 4)?;
    Ok(bytes.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect())
}

/// The bytes of a texture's first layer (`texel` bytes each), rows unpadded.
fn read_texels(
    ctx: &GpuContext,
    texture: &wgpu::Texture,
    aspect: wgpu::TextureAspect,
    texel: usize,
) -> Result<Vec<u8>, GpuError> {
    let (width, height) = (texture.width(), texture.height());
    let row = width as usize * texel;
    let padded =
        row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT as usize) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT as usize;
    let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("Readback::staging"),
        size: (padded * height as usize) as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder =
        ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("Readback::encoder") });
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo { texture, mip_level: 0, origin: wgpu::Origin3d::ZERO, aspect },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded as u32),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
    );
    ctx.queue.submit([encoder.finish()]);
    let (sender, receiver) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |result| {
        let _ = sender.send(result);
    });
    ctx.wait_idle()?;
    receiver.recv().map_err(|e| GpuError::Readback(e.to_string()))?.map_err(|e| GpuError::Readback(e.to_string()))?;
    let mapped = buffer.get_mapped_range(..).map_err(|e| GpuError::Readback(e.to_string()))?;
    let mut bytes = Vec::with_capacity(row * height as usize);
    for r in 0..height as usize {
        bytes.extend_from_slice(&mapped[r * padded..r * padded + row]);
    }
    drop(mapped);
    buffer.unmap();
    Ok(bytes)
}
