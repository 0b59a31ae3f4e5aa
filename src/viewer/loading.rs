//! Opening a model in the background, and the same geometry again with
//! another opacity or environment map; the loaded model replaces the one on
//! screen (keeping the camera where the geometry is the same).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::app::ViewerApp;
use super::camera_input::SceneSphere;
use super::jobs::Job;
use super::model::Model;
use crate::frame::Camera;
use crate::scene::environment_map::EnvironmentMap;

impl ViewerApp {
    /// Starts loading `path` in the background; the current model stays until it succeeds.
    pub fn open(&mut self, ctx: &egui::Context, path: &Path) {
        self.cancel_load();
        self.generations += 1;
        let generation = self.generations;
        let path = path.to_path_buf();
        // The shown layers' looks, taken for this load (a streamed file's nodes keep the flags' looks).
        let looks = self.pending_looks.take();
        if self.drawn_by_nodes(&path) {
            return self.open_streamed(ctx, path, generation);
        }
        let label = format!("loading {}", path.file_name().map(|n| n.to_string_lossy()).unwrap_or_default());
        let materials = self.options.materials.clone();
        let environment = self.options.environment.clone();
        let cache = self.cache();
        self.load = Some(Job::spawn(label, ctx.clone(), move || {
            let mut model = Model::load(&path, generation, &materials)?;
            // The layers' opacities and colours, one per object.
            if let Some(looks) = looks {
                match model.with_looks(&looks, generation) {
                    Ok(looked) => model = looked,
                    Err(e) => log::warn!("the layers' looks were not applied: {e}"),
                }
            }
            let model = match environment {
                Some(env) => {
                    let map = EnvironmentMap::load(&env).map_err(|e| e.to_string())?;
                    model.with_environment(Some(Arc::new(map)), generation)
                }
                None => model,
            };
            Ok(model.with_hierarchy(&cache))
        }));
    }

    /// Gives every object of the model on screen `opacity`, in the
    /// background: the same geometry as a new model (new upload; the grouping
    /// comes back from the cache, keyed by geometry), with the camera kept.
    pub fn set_opacity(&mut self, ctx: &egui::Context, opacity: f32) {
        for look in self.layers.iter_mut().filter_map(|l| l.look.as_mut()) {
            look.opacity = opacity;
        }
        let cache = self.cache();
        self.remake(ctx, format!("opacity {opacity:.2}"), move |model, generation| {
            Ok(model.with_opacity(opacity, generation).with_hierarchy(&cache))
        });
    }

    /// Colours the model on screen and sets its opacity by its attributes
    /// (`None`: as loaded), in the background from the file's own values: a
    /// new upload, with the camera kept; a style the file cannot take is shown
    /// as the load error and the model kept.
    pub fn set_style(&mut self, ctx: &egui::Context, style: Option<crate::style::Style>) {
        let label = match &style {
            Some(s) => format!("colour by {}", s.color_by.as_ref().map_or("rgb".into(), |c| c.text())),
            None => "colours as loaded".into(),
        };
        let cache = self.cache();
        self.remake(ctx, label, move |model, generation| {
            Ok(model.with_style(style.map(Arc::new), generation)?.with_hierarchy(&cache))
        });
    }

    /// Sets the model on screen in the environment map at `path` (loaded in
    /// the background; an unreadable map is shown as the load error and the
    /// model kept), or in none: a new upload of the same geometry.
    pub fn set_environment(&mut self, ctx: &egui::Context, path: Option<PathBuf>) {
        let label = match &path {
            Some(p) => format!("environment {}", p.file_name().map(|n| n.to_string_lossy()).unwrap_or_default()),
            None => "no environment".into(),
        };
        self.remake(ctx, label, move |model, generation| {
            let map = match path {
                Some(p) => Some(Arc::new(EnvironmentMap::load(&p).map_err(|e| e.to_string())?)),
                None => None,
            };
            // The same splats: the same hierarchy.
            let hierarchy = model.hierarchy.clone();
            Ok(Model { hierarchy, ..model.with_environment(map, generation) })
        });
    }

    /// Remakes the model on screen in the background by `remake` (given it
    /// and its new generation), in place of any load under way; the camera
    /// is kept, and an error is shown as the load error with the model kept.
    pub(super) fn remake(
        &mut self,
        ctx: &egui::Context,
        label: String,
        remake: impl FnOnce(Arc<Model>, u64) -> Result<Model, String> + Send + 'static,
    ) {
        let Some(model) = self.model.clone() else { return };
        self.cancel_load();
        self.generations += 1;
        let generation = self.generations;
        self.load = Some(Job::spawn(label, ctx.clone(), move || remake(model, generation)));
    }

    /// Where groupings and hierarchies are cached.
    pub(super) fn cache(&self) -> crate::grouping::cache::Cache {
        self.options.cache.clone().unwrap_or_else(crate::grouping::cache::Cache::from_env)
    }

    /// Cancels the load job under way, if any, with the steps it had not shown.
    pub(super) fn cancel_load(&mut self) {
        if let Some(job) = self.load.take() {
            job.cancel();
        }
        self.interim = Default::default();
    }

    /// Takes the model the load job returned, if it has finished, else the
    /// newest step of a streamed view it is refining.
    pub(super) fn poll_load(&mut self) {
        if let Some(result) = self.load.as_ref().and_then(|j| j.poll()) {
            self.load = None;
            self.interim = Default::default();
            match result.and_then(|r| r) {
                Ok(model) => {
                    self.layers_before = None;
                    self.adopt(model)
                }
                Err(e) => {
                    // A layer that could not be opened is not listed.
                    if let Some(before) = self.layers_before.take() {
                        self.layers = before;
                    }
                    self.keep_view = false;
                    self.load_error = Some(e)
                }
            }
        } else if self.load.is_some() {
            if let Some(model) = self.take_interim() {
                self.adopt(model);
            }
        }
    }

    /// Puts `model` on screen, with its camera and background.
    fn adopt(&mut self, model: Model) {
        let aspect = self.view_size.0 as f32 / self.view_size.1.max(1) as f32;
        // The command line's camera over the scene file's, else the default view.
        let asked = self.options.camera.over(model.scene.camera.unwrap_or_default());
        let fresh = match &model.streamed {
            Some(source) => source.home_camera(&asked, aspect),
            None => asked.camera(&model.cloud, aspect).unwrap_or_else(|_| Camera::default_for(&model.cloud, aspect)),
        };
        self.scene = SceneSphere { centre: fresh.target, radius: fresh.scene_radius };
        self.home = fresh;
        // The same file with other materials (the opacity slider) keeps the view.
        let same_geometry = self.model.as_ref().is_some_and(|m| {
            // Another selection of the same streamed file is the same geometry too, and so
            // are the same file's points filtered otherwise (in the same frame: the camera means the same).
            let same_frame = m.scene.frame_placement() == model.scene.frame_placement();
            m.path == model.path
                && (m.hash == model.hash || (m.streamed.is_some() && model.streamed.is_some()) || same_frame)
        });
        let placement = model.scene.frame_placement();
        let kept = std::mem::take(&mut self.keep_view).then_some(self.placement_shown).flatten();
        self.placement_shown = Some(placement);
        self.ui.camera = match &self.options.view {
            _ if same_geometry => self.ui.camera,
            // Another set of layers: the same place, in the new frame.
            _ if kept.is_some_and(|(_, unit)| unit == placement.1) => {
                let (origin, unit) = kept.expect("checked");
                let mut camera = self.ui.camera;
                let moved = camera.target + ((origin - placement.0) / unit).as_vec3();
                self.scene.retarget(&mut camera, moved);
                camera
            }
            // The starting view of a sidecar applies to the first model only.
            Some(view) if self.model.is_none() => view.camera(),
            _ => fresh,
        };
        self.load_error = None;
        self.grouped = None;
        self.measurement = None;
        // The scene's background, unless the command line or a sidecar set one.
        let background_given = self.options.parameters.iter().any(|(p, _)| *p == crate::frame::Parameter::Background);
        if self.options.view.is_none() && !background_given {
            if let Some(bg) = model.scene.background {
                self.ui.settings.shading.background = bg;
            }
        }
        // The scene file's lights and `--light`s, moved into the scene's frame (a
        // new model only: the same geometry again keeps the lights as they were moved).
        // Another model's lights sit in its coordinates: a new model starts from its own (or none).
        if !same_geometry {
            // A screenshot's sidecar brings the lights it was lit by, for the first model.
            let shot = self.options.view.as_ref().filter(|_| self.model.is_none()).map(|v| v.lights());
            let given: Vec<crate::frame::Light> = match shot {
                Some(Ok(lights)) => lights,
                _ => model.scene.lights.iter().chain(&self.options.lights).copied().collect(),
            };
            let lights: Vec<_> = given.iter().map(|l| model.scene.light_in_frame(l)).collect();
            self.ui.settings.lights = crate::frame::Lights::new(&lights).unwrap_or_else(|e| {
                self.load_error = Some(format!("{}: lights: {e}", crate::copc::shown(&model.path.to_string_lossy())));
                Default::default()
            });
        }
        for warning in &model.warnings {
            log::warn!("{}: {warning}", crate::copc::shown(&model.path.to_string_lossy()));
        }
        self.model = Some(Arc::new(model));
    }
}
