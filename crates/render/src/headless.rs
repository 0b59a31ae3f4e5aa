//! Rendering to an image without a window (CLI `render`, tests, benchmarks).

use super::context::{GpuContext, GpuError};
use super::gpu_scene::GpuScene;
use super::plan::RenderPlan;
use super::readback;
use super::renderer::Renderer;
use crate::frame::Camera;
use crate::frame::settings::RenderSettings;
use crate::grouping::Grouping;
use crate::scene::Scene;

/// Format of headless output images.
pub const OUTPUT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// A GPU context, a renderer and an output texture.
pub struct HeadlessRenderer {
    pub ctx: GpuContext,
    pub renderer: Renderer,
    output: Option<wgpu::Texture>,
}

impl HeadlessRenderer {
    pub fn new() -> Result<Self, GpuError> {
        let ctx = GpuContext::headless()?;
        let renderer = Renderer::new(&ctx)?;
        Ok(Self { ctx, renderer, output: None })
    }

    /// Uploads `scene`, group by group when a grouping of it is given, with
    /// its environment map if it has one.
    pub fn upload(&self, scene: &Scene, grouping: Option<&Grouping>) -> GpuScene {
        self.upload_in(&scene.flattened(), scene.environment.as_deref(), grouping)
    }

    /// Uploads a scene's splats in world space, `cloud`, with the scene's environment map.
    pub fn upload_in(
        &self,
        cloud: &crate::cloud::PointCloud,
        environment: Option<&crate::scene::environment::EnvironmentMap>,
        grouping: Option<&Grouping>,
    ) -> GpuScene {
        let mut gpu = GpuScene::upload_cloud(&self.ctx.device, cloud, grouping);
        gpu.set_environment(&self.ctx.device, &self.ctx.queue, environment);
        gpu
    }

    /// Uploads a cloud already in world space (a scene's flattened splats).
    pub fn upload_cloud(&self, cloud: &crate::cloud::PointCloud, grouping: Option<&Grouping>) -> GpuScene {
        GpuScene::upload_cloud(&self.ctx.device, cloud, grouping)
    }

    /// Renders one frame and submits it, without reading it back.
    pub fn render(
        &mut self,
        scene: &mut GpuScene,
        camera: &Camera,
        settings: &RenderSettings,
        width: u32,
        height: u32,
    ) -> Result<RenderPlan, GpuError> {
        self.ctx.check_size(width, height)?;
        if self.output.as_ref().is_none_or(|t| (t.width(), t.height()) != (width, height)) {
            self.output = Some(self.ctx.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("Headless::output"),
                size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: OUTPUT_FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            }));
        }
        let view = self.output_texture()?.create_view(&Default::default());
        self.renderer.render(&self.ctx, scene, camera, settings, &view, OUTPUT_FORMAT, (width, height))
    }

    /// Renders one frame and reads it back.
    pub fn render_image(
        &mut self,
        scene: &mut GpuScene,
        camera: &Camera,
        settings: &RenderSettings,
        width: u32,
        height: u32,
    ) -> Result<(image::RgbaImage, RenderPlan), GpuError> {
        let mut plan = self.render(scene, camera, settings, width, height)?;
        let image = readback::read_rgba8(&self.ctx, self.output_texture()?)?;
        if let Some(tiles) = self.renderer.tile_engine().filter(|_| plan.compute_passes() > 0) {
            let overflowed = tiles.window_overflows(&self.ctx)?;
            plan.window_overflows = Some(overflowed);
            plan.notes.push(format!(
                "tile windows: {overflowed} pixels had more than {} hits waiting and were finished a layer at a time, exactly",
                super::tile_engine::WINDOW
            ));
        }
        Ok((image, plan))
    }

    /// [`Renderer::use_subgroups`] on this renderer's device.
    pub fn use_subgroups(&mut self, on: bool) -> bool {
        self.renderer.use_subgroups(&self.ctx, on)
    }

    fn output_texture(&self) -> Result<&wgpu::Texture, GpuError> {
        self.output.as_ref().ok_or_else(|| GpuError::Device("no output texture".into()))
    }
}
