//! A pick's answer: the layers the pixel's ray passes
//! ([`crate::reference::pick`]) with the attributes of each layer's
//! heaviest splat (intensity, classification and every other column the
//! file has), as JSON for scripts and as text for people.

use serde_json::{Value, json};

use crate::cloud::PointCloud;
use crate::reference::pick::PickedLayer;

/// The layers under one pixel, nearest first, with their attributes.
#[derive(Debug, Clone, PartialEq)]
pub struct PickReport {
    pub pixel: [u32; 2],
    pub layers: Vec<PickedLayer>,
    /// Per layer: each attribute of its heaviest splat, by name.
    pub attributes: Vec<Vec<(String, f64)>>,
    /// The units of the file's CRS, which positions are in, and its EPSG code.
    pub units: crate::cloud::crs_units::CrsUnits,
}

impl PickReport {
    /// Picks pixel `pixel` of a `size` image of `scene` ([`crate::reference::pick`]) and reads its attributes.
    pub fn of(
        scene: &crate::scene::Scene,
        camera: &crate::frame::Camera,
        options: &crate::reference::ReferenceOptions,
        size: (u32, u32),
        pixel: [u32; 2],
    ) -> Self {
        let flat = scene.flatten();
        let layers = crate::reference::pick::pick_in(scene, &flat, camera, options, size, (pixel[0], pixel[1]));
        PickReport::new(pixel, layers, &flat.cloud)
    }

    /// The report of `layers` picked at `pixel` in a scene whose flattened cloud is `cloud`.
    pub fn new(pixel: [u32; 2], layers: Vec<PickedLayer>, cloud: &PointCloud) -> Self {
        let attributes = layers
            .iter()
            .map(|layer| {
                let Some(&front) = layer.splats.first() else { return Vec::new() };
                let consistent = cloud.attributes.is_consistent(cloud.len());
                cloud
                    .attributes
                    .channels
                    .iter()
                    .filter(|_| consistent)
                    .map(|c| (c.name.clone(), c.values.get(front as usize)))
                    .collect()
            })
            .collect();
        PickReport { pixel, layers, attributes, units: cloud.units.clone() }
    }

    /// `{"pixel": [x, y], "epsg": code or null, "units": ..., "vertical_units":
    /// ..., "layers": [...]}`: the CRS's code and units ("units of the file"
    /// without one), then per layer its depth, position (where the ray meets
    /// it, f64 file coordinates), stored position (its heaviest splat's, as
    /// the file holds it), splats, normal, radius, colour, opacity and attributes.
    pub fn json(&self) -> Value {
        let layers: Vec<Value> = self
            .layers
            .iter()
            .zip(&self.attributes)
            .map(|(l, attributes)| {
                let attributes: serde_json::Map<String, Value> =
                    attributes.iter().map(|(name, v)| (name.clone(), json!(v))).collect();
                json!({
                    "depth": l.depth,
                    "position": l.position.to_array(),
                    "stored_position": l.stored.to_array(),
                    "splats": l.splats,
                    "normal": l.normal.to_array(),
                    "radius": l.radius,
                    "colour": l.colour,
                    "opacity": l.opacity,
                    "attributes": attributes,
                })
            })
            .collect();
        json!({
            "pixel": self.pixel,
            "epsg": self.units.epsg,
            "units": self.units.horizontal_name(),
            "vertical_units": self.units.vertical_name(),
            "layers": layers,
        })
    }

    /// The same for people: a line per layer, then its attributes.
    pub fn text(&self) -> String {
        let [x, y] = self.pixel;
        if self.layers.is_empty() {
            return format!("pixel ({x}, {y}): the ray meets nothing\n");
        }
        let mut out = format!("pixel ({x}, {y}): {} layer(s), nearest first\n", self.layers.len());
        for (k, (l, attributes)) in self.layers.iter().zip(&self.attributes).enumerate() {
            let [r, g, b] = l.colour;
            let [px, py, pz] = l.position.to_array();
            let [sx, sy, sz] = l.stored.to_array();
            let [nx, ny, nz] = l.normal.to_array();
            let shown: Vec<String> = l.splats.iter().take(5).map(u32::to_string).collect();
            let more = if l.splats.len() > 5 { ", ..." } else { "" };
            out.push_str(&format!(
                "layer {}: at ({px:.4}, {py:.4}, {pz:.4}), splat stored at ({sx}, {sy}, {sz}), depth {:.4}, normal ({nx:.3}, {ny:.3}, {nz:.3}), radius {:.4}, colour ({r}, {g}, {b}), opacity {:.3}, {} splat(s): {}{more}\n",
                k + 1,
                l.depth,
                l.radius,
                l.opacity,
                l.splats.len(),
                shown.join(", "),
            ));
            for (name, value) in attributes {
                let class = if name == crate::cloud::attributes::names::CLASSIFICATION {
                    format!(" ({})", crate::style::classes::name(*value as u8))
                } else {
                    String::new()
                };
                out.push_str(&format!("  {name}: {value}{class}\n"));
            }
        }
        out
    }
}
