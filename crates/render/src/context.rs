//! The wgpu device: adapter choice, real limits, error capture.
//!
//! Vulkan is preferred (lavapipe on machines without a GPU); `WGPU_BACKEND`
//! overrides. The device asks for the adapter's own limits, because wgpu's
//! defaults allow too few colour bytes per sample for the accumulation
//! targets, and installs an error handler so that a GPU error becomes a log
//! line and a failed render instead of a panic.

use std::sync::Arc;

/// Errors from the GPU side.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error(
        "no GPU adapter found ({0}); install Mesa's Vulkan drivers (apt-get install mesa-vulkan-drivers libvulkan1) or set WGPU_BACKEND"
    )]
    NoAdapter(String),
    #[error("could not open the GPU device: {0}")]
    Device(String),
    #[error("GPU validation error in {stage}: {message}")]
    Validation { stage: String, message: String },
    #[error("reading the image back from the GPU failed: {0}")]
    Readback(String),
    #[error("the image size {width}x{height} is not supported (1..={max} per side)")]
    Size { width: u32, height: u32, max: u32 },
    #[error("{0}")]
    TooLarge(String),
    /// A `tiled` frame (or part of one) whose splats or tile lists would
    /// pass the memory given to it, `over` times over: drawn in smaller
    /// parts (gpu_renderer.rs), an error only when a part cannot shrink.
    #[error("{message}")]
    TilesDoNotFit { message: String, over: f64 },
    #[error("the GPU ran out of memory {stage}: {message}")]
    OutOfMemory { stage: String, message: String },
}

/// Target memory a frame may use on a GPU whose free memory is unknown:
/// 4 GiB, within any current discrete GPU's memory.
pub const DEFAULT_GPU_TARGET_BUDGET: u64 = 4 << 30;

/// An open GPU device with its queue.
pub struct GpuContext {
    pub instance: wgpu::Instance,
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
}

impl GpuContext {
    /// Opens a device with no surface (headless rendering, tests, benchmarks).
    pub fn headless() -> Result<Self, GpuError> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        if wgpu::Backends::from_env().is_none() {
            desc.backends = wgpu::Backends::VULKAN;
        }
        let instance = wgpu::Instance::new(desc);
        let options = wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        };
        let adapter = match pollster::block_on(instance.request_adapter(&options)) {
            Ok(adapter) => adapter,
            Err(vulkan_error) if wgpu::Backends::from_env().is_none() => {
                // No Vulkan: try every other backend before giving up.
                let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
                desc.backends = wgpu::Backends::all();
                let instance = wgpu::Instance::new(desc);
                let adapter = pollster::block_on(instance.request_adapter(&options))
                    .map_err(|e| GpuError::NoAdapter(format!("Vulkan: {vulkan_error}; others: {e}")))?;
                return Self::open(instance, adapter);
            }
            Err(e) => return Err(GpuError::NoAdapter(e.to_string())),
        };
        Self::open(instance, adapter)
    }

    /// Opens the device of `adapter` with its full limits.
    pub fn open(instance: wgpu::Instance, adapter: wgpu::Adapter) -> Result<Self, GpuError> {
        let desc = Self::device_descriptor(&adapter);
        let (device, queue) =
            pollster::block_on(adapter.request_device(&desc)).map_err(|e| GpuError::Device(e.to_string()))?;
        device.on_uncaptured_error(Arc::new(|error: wgpu::Error| {
            log::error!("uncaptured GPU error: {error}");
        }));
        Ok(Self { instance, adapter, device, queue })
    }

    /// What the renderer needs of a device: the adapter's own limits, timestamps,
    /// float32 blending and subgroup operations where the adapter has them.
    pub fn device_descriptor(adapter: &wgpu::Adapter) -> wgpu::DeviceDescriptor<'static> {
        let wanted = wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::FLOAT32_BLENDABLE | wgpu::Features::SUBGROUP;
        wgpu::DeviceDescriptor {
            label: Some("GpuContext::device"),
            required_features: adapter.features() & wanted,
            required_limits: adapter.limits(),
            ..Default::default()
        }
    }

    /// One line naming the adapter and its driver.
    pub fn describe(&self) -> String {
        let info = self.adapter.get_info();
        format!("{} ({:?}, {} {})", info.name, info.backend, info.driver, info.driver_info)
    }

    /// Bytes of render targets a frame may allocate: `$POINTBLEND_GPU_MEMORY_MB`
    /// if set; on a software adapter (lavapipe, whose textures live in system
    /// memory) three quarters of the memory available now; on a GPU, whose
    /// free memory wgpu cannot tell, [`DEFAULT_GPU_TARGET_BUDGET`].
    pub fn target_budget(&self) -> u64 {
        if let Some(mb) = std::env::var("POINTBLEND_GPU_MEMORY_MB").ok().and_then(|v| v.parse::<u64>().ok()) {
            return mb.saturating_mul(1 << 20);
        }
        match self.adapter.get_info().device_type {
            wgpu::DeviceType::Cpu => crate::memory::available_bytes().map_or(DEFAULT_GPU_TARGET_BUDGET, |b| b / 4 * 3),
            _ => DEFAULT_GPU_TARGET_BUDGET,
        }
    }

    /// Runs `allocate` inside an out-of-memory error scope, so that running
    /// out gives one error instead of a cascade.
    pub fn allocating<T>(&self, stage: &str, allocate: impl FnOnce() -> T) -> Result<T, GpuError> {
        // Views of a texture that could not be allocated are invalid too: a
        // validation scope around the allocation keeps those consequences
        // from being reported one by one, after the one line that says why.
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let memory = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let value = allocate();
        let out_of_memory = pollster::block_on(memory.pop());
        let invalid = pollster::block_on(validation.pop());
        match (out_of_memory, invalid) {
            (Some(error), _) => Err(GpuError::OutOfMemory { stage: stage.to_string(), message: error.to_string() }),
            (None, Some(error)) => Err(GpuError::Validation {
                stage: stage.to_string(),
                message: error.to_string().split_whitespace().collect::<Vec<_>>().join(" "),
            }),
            (None, None) => Ok(value),
        }
    }

    /// Runs `work` inside a validation error scope and reports what it caught.
    pub fn checked<T>(&self, stage: &str, work: impl FnOnce() -> T) -> Result<T, GpuError> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let value = work();
        match pollster::block_on(scope.pop()) {
            None => Ok(value),
            Some(error) => Err(GpuError::Validation {
                stage: stage.to_string(),
                message: error.to_string().split_whitespace().collect::<Vec<_>>().join(" "),
            }),
        }
    }

    /// Blocks until the GPU has finished all submitted work.
    pub fn wait_idle(&self) -> Result<(), GpuError> {
        self.device.poll(wgpu::PollType::wait_indefinitely()).map(|_| ()).map_err(|e| GpuError::Device(e.to_string()))
    }

    /// Checks that an image of `width` x `height` can be rendered.
    pub fn check_size(&self, width: u32, height: u32) -> Result<(), GpuError> {
        let max = self.device.limits().max_texture_dimension_2d;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(GpuError::Size { width, height, max });
        }
        Ok(())
    }
}
