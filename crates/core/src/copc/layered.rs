//! Several streamed files (COPC files, URLs) drawn as layers under one
//! point budget: `render A.copc.laz B.copc.laz`, or a `.vpc` of COPC tiles.
//!
//! The layers' octrees are selected as one: a forest whose own root (no
//! points, always refined) has every file's root as a child, and whose
//! nodes are the files' nodes numbered one file after another. The
//! selection ([`crate::lod::select_in`], additive refinement) then takes
//! the node of largest projected spacing next, whichever file it is in,
//! while the points of all the files together fit the budget: a near tile
//! gets fine nodes and a far one its top levels, as one file of them all
//! would. Every file's root in view is drawn whatever the budget, as one
//! file's root is: a budget below the roots' points together would
//! otherwise leave whole files out, holes in the view. Each file's spheres are moved into the first file's frame (its
//! origin: file = frame + origin), in which the camera is given. Each
//! file's chosen nodes are then loaded, estimated and gathered by its own
//! [`StreamSubset`], as a file alone is, into a cloud with its own origin,
//! and the seams where two files' clouds meet are estimated again
//! ([`LayeredStreams::mend_seams`]), as layers held whole are.

use glam::{DVec3, Vec3};

use super::hierarchy::CopcTree;
use super::subset::StreamSubset;
use super::{CopcError, CopcStream, StreamBudget, StreamOptions};
use crate::cloud::estimate::EstimateOptions;
use crate::cloud::{LoadOptions, PointCloud, Provenance};
use crate::frame::Camera;
use crate::frame::subset::{Choice, Choosing};
use crate::lod::{LodTree, Refinement, Selection, select_in};
use crate::scene::Scene;
use crate::scene::layer_seams::{self, Layer};
use crate::scene::layers::SharedCrs;

/// The forest root's coarseness: larger than any node's, so that it is always refined.
const ROOT_COARSENESS: f32 = 1e30;

/// Streamed files drawn together under one budget.
pub struct LayeredStreams {
    /// Each file, with its node cache and its last choice.
    pub layers: Vec<StreamSubset>,
    pub budget: StreamBudget,
    /// Each file's last cloud: what a choice of the same nodes gives again.
    last: Vec<Option<PointCloud>>,
}

/// The layers' octrees as one tree (see the module doc).
struct Forest<'a> {
    /// Each file's tree and its origin's offset from the first file's.
    trees: Vec<(&'a CopcTree, Vec3)>,
    /// The forest's number of each file's first node.
    bases: Vec<u32>,
    /// The forest's own root: the number after every file's nodes.
    root: u32,
    /// A sphere around the files' roots (centre, reach).
    around: (Vec3, f32),
}

impl<'a> Forest<'a> {
    fn new(trees: Vec<(&'a CopcTree, Vec3)>) -> Self {
        let mut bases = Vec::with_capacity(trees.len());
        let mut total = 0u32;
        for (tree, _) in &trees {
            bases.push(total);
            total += tree.nodes.len() as u32;
        }
        let spheres: Vec<(Vec3, f32)> = trees
            .iter()
            .filter_map(|(tree, offset)| {
                let (centre, reach, _) = tree.sphere(tree.root()?);
                Some((centre + *offset, reach))
            })
            .collect();
        let centre = spheres.iter().map(|s| s.0).sum::<Vec3>() / spheres.len().max(1) as f32;
        let reach = spheres.iter().map(|(c, r)| c.distance(centre) + r).fold(0.0, f32::max);
        Forest { trees, bases, root: total, around: (centre, reach) }
    }

    /// The file a forest node is in, and its number there.
    fn local(&self, node: u32) -> (usize, u32) {
        let file = self.bases.partition_point(|&b| b <= node) - 1;
        (file, node - self.bases[file])
    }

    /// The forest's selection as each file's, in the order chosen (the forest's root left out).
    fn split(&self, selection: &Selection) -> Vec<Selection> {
        let mut each: Vec<Selection> = self.trees.iter().map(|_| Selection { nodes: Vec::new(), splats: 0 }).collect();
        for &node in selection.nodes.iter().filter(|&&n| n != self.root) {
            let (file, local) = self.local(node);
            each[file].nodes.push(local);
            each[file].splats += self.trees[file].0.count(local);
        }
        each
    }
}

impl LodTree for Forest<'_> {
    fn refinement(&self) -> Refinement {
        Refinement::Add
    }
    fn root(&self) -> Option<u32> {
        self.trees.iter().any(|(tree, _)| tree.root().is_some()).then_some(self.root)
    }
    fn count(&self, node: u32) -> usize {
        if node == self.root {
            return 0;
        }
        let (file, local) = self.local(node);
        self.trees[file].0.count(local)
    }
    fn sphere(&self, node: u32) -> (Vec3, f32, f32) {
        if node == self.root {
            return (self.around.0, self.around.1, ROOT_COARSENESS);
        }
        let (file, local) = self.local(node);
        let (tree, offset) = self.trees[file];
        let (centre, reach, spacing) = tree.sphere(local);
        (centre + offset, reach, spacing)
    }
    fn always_drawn(&self, node: u32) -> bool {
        if node == self.root {
            return false;
        }
        let (file, local) = self.local(node);
        self.trees[file].0.root() == Some(local)
    }
    fn children(&self, node: u32, out: &mut Vec<u32>) {
        if node == self.root {
            let roots = self.trees.iter().zip(&self.bases).filter_map(|((tree, _), base)| Some(base + tree.root()?));
            out.extend(roots);
            return;
        }
        let (file, local) = self.local(node);
        let start = out.len();
        self.trees[file].0.children(local, out);
        for child in &mut out[start..] {
            *child += self.bases[file];
        }
    }
}

impl LayeredStreams {
    /// `streams` under `budget` together, each loaded as `load` says.
    pub fn new(streams: Vec<CopcStream>, budget: StreamBudget, load: LoadOptions) -> Self {
        let layers: Vec<StreamSubset> =
            streams.into_iter().map(|s| StreamSubset::new(s, budget, load.clone())).collect();
        let last = vec![None; layers.len()];
        LayeredStreams { layers, budget, last }
    }

    /// Opens `files` (COPC files or URLs) as layers under `budget`, each
    /// admitted to the layers' one CRS (`crs`), each file's node cache an
    /// equal share of `options.cache_bytes`.
    pub fn open(
        files: &[&std::path::Path],
        mut options: StreamOptions,
        (budget, load): (StreamBudget, LoadOptions),
        crs: &mut SharedCrs,
    ) -> Result<Self, CopcError> {
        options.cache_bytes /= files.len().max(1);
        let mut streams = Vec::with_capacity(files.len());
        for &path in files {
            let stream = super::open_nodes(path, options.clone())?;
            let (epsg, text) = stream.crs();
            crs.admit(stream.name(), epsg, text.as_deref()).map_err(|why| CopcError::new(stream.name(), why))?;
            streams.push(stream);
        }
        Ok(Self::new(streams, budget, load))
    }

    /// Selects under `budget` from now on, all the files' points within it.
    pub fn set_budget(&mut self, budget: StreamBudget) {
        self.budget = budget;
        self.layers.iter_mut().for_each(|l| l.budget = budget);
    }

    /// The origin of the frame the camera is given in: the first file's.
    pub fn origin(&self) -> DVec3 {
        self.layers.first().map_or(DVec3::ZERO, |l| l.stream.tree.origin)
    }

    /// Each file's nodes that `camera` (in the frame of [`Self::origin`])
    /// selects at `size`, all the files' points within the one budget;
    /// reads the hierarchy pages the traversal reaches.
    pub fn select(
        &mut self,
        camera: &Camera,
        size: (u32, u32),
        choosing: Choosing,
    ) -> Result<Vec<Selection>, CopcError> {
        if self.budget == StreamBudget::All {
            for layer in &self.layers {
                layer.stream.check_fits(self.budget)?;
            }
        }
        let options = self.budget.select_options(choosing);
        let origin = self.origin();
        loop {
            let each = {
                let trees = self.layers.iter().map(|l| (&l.stream.tree, (l.stream.tree.origin - origin).as_vec3()));
                let forest = Forest::new(trees.collect());
                forest.split(&select_in(&forest, camera, size, options))
            };
            let mut pending = false;
            for (layer, selection) in self.layers.iter_mut().zip(&each) {
                let waiting: Vec<u32> = layer.stream.tree.pending(&selection.nodes).collect();
                pending |= !waiting.is_empty();
                for node in waiting {
                    layer.stream.read_page(node);
                }
            }
            if !pending {
                return Ok(each);
            }
        }
    }

    /// Each file's points for `camera` (see [`Self::select`]), its chosen
    /// nodes loaded and gathered by its own subset: `None` for a file with
    /// no node in view, else its choice (always with its cloud: a file
    /// that draws the same nodes as last time gives its last cloud again)
    /// or why it gave no point.
    pub fn choose(
        &mut self,
        camera: &Camera,
        size: (u32, u32),
        choosing: Choosing,
    ) -> Result<Vec<Option<Result<Choice, CopcError>>>, CopcError> {
        let each = self.select(camera, size, choosing)?;
        let chosen = self.layers.iter_mut().zip(&mut self.last).zip(&each).map(|((layer, last), selection)| {
            if selection.nodes.is_empty() {
                return None;
            }
            layer.load_selected(selection, u64::MAX);
            Some(layer.gather_selected(selection, choosing, u64::MAX).map(|mut choice| {
                match &choice.cloud {
                    Some(cloud) => *last = Some(cloud.clone()),
                    None => choice.cloud = last.clone(),
                }
                choice
            }))
        });
        Ok(chosen.collect())
    }

    /// Whether layer `k`'s file gives its normals and its radii, or its stream estimated them.
    fn provenance(&self, k: usize) -> (Provenance, Provenance) {
        let gives = |name: &str| self.layers[k].stream.header.fields.iter().any(|f| f.name == name);
        let of = |given: bool| if given { Provenance::FromFile } else { Provenance::Estimated };
        (of(["nx", "ny", "nz"].into_iter().all(gives)), of(gives("radius")))
    }

    /// Mends the seams where the chosen clouds of two layers (layer
    /// number, cloud) meet, as layers held whole are mended
    /// ([`layer_seams::mend`]): each node was estimated with its own file's
    /// points only. Returns how many points were estimated again.
    pub fn mend_seams(&self, clouds: &mut Vec<(usize, PointCloud)>, options: &EstimateOptions) -> usize {
        if clouds.len() < 2 {
            return 0;
        }
        let order: Vec<usize> = clouds.iter().map(|(k, _)| *k).collect();
        let mut layers: Vec<Layer> = clouds
            .drain(..)
            .map(|(k, cloud)| {
                let (normals, radii) = self.provenance(k);
                Layer { cloud, normals, radii }
            })
            .collect();
        let options = EstimateOptions { orient_up: true, ..options.clone() };
        let mended = layer_seams::mend(&mut layers, &options);
        clouds.extend(order.into_iter().zip(layers.into_iter().map(|l| l.cloud)));
        mended
    }

    /// The scene of what `camera` chooses ([`Self::choose`]): one object
    /// per file that gives points, named after it, in its own frame, the
    /// seams where two meet mended ([`Self::mend_seams`]); and the points
    /// drawn. Each file's share is logged, and a file that gives no point
    /// is logged and left out.
    pub fn scene(
        &mut self,
        camera: &Camera,
        size: (u32, u32),
        choosing: Choosing,
    ) -> Result<(Scene, usize), CopcError> {
        let chosen = self.choose(camera, size, choosing)?;
        let (mut clouds, mut keys) = (Vec::new(), Vec::new());
        for (k, choice) in chosen.into_iter().enumerate() {
            match choice {
                Some(Ok(Choice { cloud: Some(cloud), key, .. })) => {
                    let layer = &self.layers[k];
                    log::info!("{}: {} points of {} nodes drawn", layer.stream.name(), cloud.len(), layer.last.drawn);
                    clouds.push((k, cloud));
                    keys.push(key);
                }
                Some(Err(why)) => log::warn!("{why}"),
                _ => {}
            }
        }
        let estimate = self.layers.first().map(|l| l.load.estimate.clone()).unwrap_or_default();
        let mended = self.mend_seams(&mut clouds, &estimate);
        if mended > 0 {
            log::info!("{mended} points where the streamed layers meet estimated again with their neighbours across");
        }
        let drawn = clouds.iter().map(|(_, c)| c.len()).sum();
        let mut scene = Scene::default();
        for ((k, cloud), key) in clouds.into_iter().zip(keys) {
            scene.objects.extend(Scene::single(self.layers[k].stream.file_name(), cloud, key).objects);
        }
        Ok((scene, drawn))
    }
}
