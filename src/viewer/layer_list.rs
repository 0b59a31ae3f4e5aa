//! The viewer's layers: the point files the user opened, drawn together as
//! one scene; the panel lists them (`layers_panel.rs`), shown or hidden, or removed.
//!
//! Open…, a dropped file, or a URL adds a layer to the files on screen,
//! and a `.vpc` adds each of its files; a scene file, or anything opened over
//! the bundled model, replaces what is shown. The shown layers are opened as
//! the command line's `view A B` opens them: a `.vpc` of their files
//! ([`crate::scene::vpc::write`]) in a folder of the window's own, read by
//! [`crate::scene::open`] as layers ([`crate::scene::layers`]: one object per
//! file, each with its f64 origin, one CRS, their seams mended). One shown
//! layer is opened as the file itself. The camera stays where it was, moved
//! by the difference of the frames' origins when the first layer changes.
//! A layer's opacity, colour and cut ([`Look`]) are its object's material
//! and box ([`crate::scene::Scene::set_looks`]): set on the model on screen, and
//! again on each model the shown layers open as; a screenshot's sidecar
//! records them for `render --camera`.

use std::path::{Path, PathBuf};

use super::app::ViewerApp;
use super::state::Layer;
use crate::scene::{Look, vpc};

/// The files a path opens as layers: a `.vpc`'s files, else the path; none
/// for a scene file or the bundled model, which are not layers.
pub fn layers_of(path: &Path) -> Vec<PathBuf> {
    let is_scene = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml"));
    if is_scene || crate::assets::path(crate::assets::BUNDLED_MODEL).is_ok_and(|b| b == path) {
        return Vec::new();
    }
    if vpc::is_vpc(path) {
        if let Ok(files) = vpc::read(path) {
            return files.into_iter().map(|f| f.path).collect();
        }
    }
    vec![path.to_path_buf()]
}

impl ViewerApp {
    /// Opens the file the window starts with; it is the first layer (a `.vpc`'s files are the layers).
    pub(super) fn open_first(&mut self, ctx: &egui::Context, file: &Path) {
        self.layers = layers_of(file).into_iter().map(|path| Layer { path, shown: true, look: None }).collect();
        self.open(ctx, file);
    }

    /// The files of the shown layers, when there are several (a screenshot's sidecar names them).
    pub(super) fn shown_layer_files(&self) -> Vec<String> {
        let shown: Vec<String> = self.layers.iter().filter(|l| l.shown).map(|l| href(&l.path)).collect();
        if shown.len() < 2 { Vec::new() } else { shown }
    }

    /// The layers, as the panel lists them.
    pub fn layers(&self) -> &[Layer] {
        &self.layers
    }

    /// Opens `path` as Open… and a drop do: added to the layers on screen,
    /// or in place of what is shown (a scene file, or over the bundled model).
    pub(super) fn open_or_add(&mut self, ctx: &egui::Context, path: &Path) {
        let added = layers_of(path);
        if self.layers.is_empty() || added.is_empty() {
            self.layers = added.into_iter().map(|path| Layer { path, shown: true, look: None }).collect();
            self.layers_before = None;
            return self.open(ctx, path);
        }
        self.layers_before = Some(self.layers.clone());
        self.layers.extend(added.into_iter().map(|path| Layer { path, shown: true, look: None }));
        self.open_shown_layers(ctx);
    }

    /// Shows or hides layer `k`.
    pub(super) fn show_layer(&mut self, ctx: &egui::Context, k: usize, shown: bool) {
        if self.layers.get(k).is_some_and(|l| l.shown != shown) {
            self.layers_before = Some(self.layers.clone());
            self.layers[k].shown = shown;
            self.open_shown_layers(ctx);
        }
    }

    /// Removes layer `k`.
    pub(super) fn remove_layer(&mut self, ctx: &egui::Context, k: usize) {
        if k < self.layers.len() {
            self.layers_before = Some(self.layers.clone());
            self.layers.remove(k);
            self.open_shown_layers(ctx);
        }
    }

    /// Each layer's look as drawn: a shown layer's object's material, a
    /// hidden one's as set (else the flags' opacity and colour).
    pub(super) fn layer_looks(&self) -> Vec<Look> {
        let drawn = self.model.as_ref().map(|m| m.scene.looks()).unwrap_or_default();
        let shown = self.layers.iter().filter(|l| l.shown).count();
        let mut at = 0;
        let default = self.flags_look();
        self.layers
            .iter()
            .map(|layer| {
                let drawn_look = layer.shown.then(|| drawn.get(at).filter(|_| drawn.len() == shown)).flatten();
                at += usize::from(layer.shown);
                drawn_look.copied().or(layer.look).unwrap_or(default)
            })
            .collect()
    }

    /// The look the command line's `--opacity` and `--color` give an object.
    fn flags_look(&self) -> Look {
        let materials = &self.options.materials;
        Look { opacity: materials.opacity.unwrap_or(1.0), colour: materials.colour, clip: None }
    }

    /// Draws layer `k` in `look`; a shown layer's object now, a hidden one's when it is shown.
    pub(super) fn set_layer_look(&mut self, ctx: &egui::Context, k: usize, look: Look) {
        let mut drawn = self.layer_looks();
        let Some(layer) = self.layers.get_mut(k) else { return };
        layer.look = Some(look);
        if !layer.shown {
            return;
        }
        drawn[k] = look;
        let shown: Vec<Look> = self.layers.iter().zip(drawn).filter(|(l, _)| l.shown).map(|(_, d)| d).collect();
        let cache = self.cache();
        self.remake(ctx, format!("layer {} look", k + 1), move |model, generation| {
            Ok(model.with_looks(&shown, generation)?.with_hierarchy(&cache))
        });
    }

    /// The looks the shown layers open in, when one was set.
    fn shown_looks(&self) -> Option<Vec<Look>> {
        let shown = self.layers.iter().filter(|l| l.shown);
        let set = shown.clone().any(|l| l.look.is_some());
        set.then(|| shown.map(|l| l.look.unwrap_or(self.flags_look())).collect())
    }

    /// Opens the shown layers as one model, keeping the view; none shown clears the view.
    fn open_shown_layers(&mut self, ctx: &egui::Context) {
        self.pending_looks = self.shown_looks();
        let shown: Vec<&Layer> = self.layers.iter().filter(|l| l.shown).collect();
        self.keep_view = true;
        match shown.as_slice() {
            [] => {
                self.cancel_load();
                self.model = None;
                self.shown = None;
            }
            [one] => {
                let path = one.path.clone();
                self.open(ctx, &path);
            }
            many => {
                let hrefs: Vec<String> = many.iter().map(|l| href(&l.path)).collect();
                match self.write_layers_file(&hrefs) {
                    Ok(path) => self.open(ctx, &path),
                    Err(e) => self.load_error = Some(format!("writing the layers' .vpc: {e}")),
                }
            }
        }
    }

    /// A `.vpc` of `hrefs` in the window's own folder, named for this generation.
    fn write_layers_file(&mut self, hrefs: &[String]) -> std::io::Result<PathBuf> {
        if self.layers_folder.is_none() {
            self.layers_folder = Some(tempfile::Builder::new().prefix("pointblend-layers-").tempdir()?);
        }
        let folder = self.layers_folder.as_ref().expect("made above").path();
        let path = folder.join(format!("layers-{}.vpc", self.generations + 1));
        vpc::write(hrefs, &path)?;
        Ok(path)
    }
}

/// A layer's file as a `.vpc` names it ([`vpc::href`]); one that cannot be
/// found as it is, so that opening it names it in the error.
fn href(path: &Path) -> String {
    vpc::href(path).unwrap_or_else(|_| path.to_string_lossy().into_owned())
}
