//! An object cut to a box: the viewer's layer list keeps only a layer's
//! points inside the clip box (or outside it, when the box hides its
//! inside), so that one layer is clipped while the others stay whole.
//!
//! The scene's clip ([`crate::frame::clip`]) cuts every object per pixel,
//! in every renderer. A cut is the per-object counterpart, made once on
//! the object's points instead: [`SceneObject::set_cut`] keeps the points
//! whose file position (f64, [`PointCloud::file_position`]) the box keeps,
//! with every attribute, and holds the whole cloud to undo it. So each
//! mode, the exact reference, exports, profiles and measures see the same
//! points, as they do for a style's filters; a splat on the box's face is
//! kept or dropped whole. A styled object is cut as loaded, then styled
//! again, so colour ranges and filters see the cut points. The object's
//! content hash changes with the box, so the caches keyed by it (grouping,
//! hierarchy) are kept apart.

use std::sync::Arc;

use super::SceneObject;
use crate::cloud::PointCloud;
use crate::frame::ClipRegion;
use crate::frame::clip::ClipBox;
use crate::hash::fnv1a;

/// What an object was before it was cut to `clip_box`.
#[derive(Debug, Clone)]
pub struct Cut {
    pub clip_box: ClipBox,
    /// The object's cloud (as loaded, before any style) and its content hash.
    pub whole: Arc<PointCloud>,
    pub whole_hash: u64,
}

/// The points of `cloud` whose file positions `clip_box` keeps, with their attributes.
pub fn cut_cloud(cloud: &PointCloud, clip_box: ClipBox) -> PointCloud {
    let region = ClipRegion { clip_box: Some(clip_box), planes: Vec::new() };
    let kept: Vec<u32> =
        (0..cloud.len()).filter(|&i| region.keeps_file_point(cloud.file_position(i))).map(|i| i as u32).collect();
    PointCloud {
        attributes: cloud.attributes.gather(&kept),
        scanner_position: cloud.scanner_position,
        ..cloud.select(&kept)
    }
}

impl SceneObject {
    /// The box this object is cut to, if it is.
    pub fn clip_box(&self) -> Option<ClipBox> {
        self.cut.as_ref().map(|c| c.clip_box)
    }

    /// Cuts this object to `clip_box` (none: whole again), styled as it
    /// was; an error names what its file lacks for the style.
    pub fn set_cut(&mut self, clip_box: Option<ClipBox>) -> Result<(), String> {
        if self.clip_box() == clip_box {
            return Ok(());
        }
        let style = self.styled.take().map(|styled| {
            self.cloud = styled.source;
            self.content_hash = styled.source_hash;
            styled.style
        });
        if let Some(cut) = self.cut.take() {
            self.cloud = cut.whole.clone();
            self.content_hash = cut.whole_hash;
        }
        if let Some(clip_box) = clip_box {
            let kept = Arc::new(cut_cloud(&self.cloud, clip_box));
            let whole = std::mem::replace(&mut self.cloud, kept);
            let whole_hash = self.content_hash;
            self.content_hash = fnv1a(whole_hash, format!("cut {clip_box:?}").as_bytes());
            self.cut = Some(Arc::new(Cut { clip_box, whole, whole_hash }));
        }
        match style {
            Some(style) => self.restyle(&style),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::frame::clip::Hidden;
    use crate::scene::Scene;

    /// Ten points along x at file x = 1000 + i, each with its index as intensity.
    fn row() -> PointCloud {
        let n = 10;
        let mut cloud = PointCloud {
            positions: (0..n).map(|i| Vec3::new(i as f32, 0.0, 0.0)).collect(),
            normals: vec![Vec3::Z; n],
            radii: vec![0.4; n],
            colours: vec![[200, 200, 200]; n],
            opacity: vec![1.0; n],
            origin: [1000.0, 0.0, 0.0],
            ..Default::default()
        };
        let values = (0..n).map(|i| i as f64).collect();
        cloud.attributes.push("intensity", crate::cloud::Values::F64(values));
        cloud
    }

    fn intensities(object: &SceneObject) -> Vec<f64> {
        let values = object.cloud.attributes.get("intensity").unwrap();
        (0..values.len()).map(|i| values.get(i)).collect()
    }

    #[test]
    fn a_cut_keeps_the_points_its_box_keeps_with_their_attributes_and_is_undone() {
        let mut scene = Scene::single("row", row(), 7);
        let object = &mut scene.objects[0];
        let inside = ClipBox { min: [1002.5, -1.0, -1.0], max: [1005.5, 1.0, 1.0], hide: Hidden::Outside };
        object.set_cut(Some(inside)).unwrap();
        assert_eq!(intensities(object), [3.0, 4.0, 5.0], "the points inside the box, by file x");
        assert_eq!(object.clip_box(), Some(inside));
        assert_ne!(object.content_hash, 7, "a cut object is cached apart");

        let hole = ClipBox { hide: Hidden::Inside, ..inside };
        object.set_cut(Some(hole)).unwrap();
        assert_eq!(intensities(object), [0.0, 1.0, 2.0, 6.0, 7.0, 8.0, 9.0], "a box hiding its inside, from the whole");
        object.set_cut(None).unwrap();
        assert_eq!(object.cloud.len(), 10);
        assert_eq!(object.content_hash, 7, "whole again, as loaded");
    }

    #[test]
    fn a_styled_object_is_cut_as_loaded_and_styled_again() {
        let mut scene = Scene::single("row", row(), 7);
        let style = crate::style::Style {
            filters: vec![crate::style::Filter {
                name: "intensity".into(),
                test: crate::style::filter::Test::Range(4.0, 100.0),
            }],
            ..Default::default()
        };
        scene.apply_style(&style).unwrap();
        let object = &mut scene.objects[0];
        let left = ClipBox { min: [999.0, -1.0, -1.0], max: [1006.5, 1.0, 1.0], hide: Hidden::Outside };
        object.set_cut(Some(left)).unwrap();
        assert_eq!(intensities(object), [4.0, 5.0, 6.0], "cut, then filtered");
        assert_eq!(object.styled.as_ref().unwrap().source.len(), 7, "the style's source is the cut cloud");
        object.set_cut(None).unwrap();
        assert_eq!(intensities(object), [4.0, 5.0, 6.0, 7.0, 8.0, 9.0], "whole again, still filtered");
    }
}
