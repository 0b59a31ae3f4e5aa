//! Timing of the back-to-front orders (`bench --orders`): for each model and
//! view, the BSP traversal, Gunjee's bucket sort and the full sort, each
//! median over timed runs after warm-up runs (CPU wall time; the BSP tree is
//! built once per model and its build time reported apart).

use std::time::Instant;

use serde::Serialize;

use super::views::NamedView;
use crate::cloud::PointCloud;
use crate::spatial::order::{OrderKind, Orderer};

/// One order from one view of one model.
#[derive(Debug, Clone, Serialize)]
pub struct OrderRow {
    pub model: String,
    pub view: String,
    pub order: String,
    pub points: usize,
    /// Per view, median over the timed runs.
    pub ms: f64,
    pub ms_min: f64,
    pub ms_max: f64,
    /// Slab thickness, as a share of the model's bounding radius.
    pub slab: f64,
    /// Once per model: building the BSP tree (0 for the others).
    pub build_ms: f64,
}

/// Times every order on `cloud` from each of `views`.
pub fn time_orders(model: &str, cloud: &PointCloud, views: &[NamedView], runs: usize, warm_up: usize) -> Vec<OrderRow> {
    let radius = cloud.bounds().map_or(1.0, |b| b.radius()).max(f32::MIN_POSITIVE) as f64;
    let mut rows = Vec::new();
    let mut out = Vec::with_capacity(cloud.len());
    for kind in OrderKind::ALL {
        let built = Instant::now();
        let mut orderer = Orderer::new(kind, &cloud.positions, &cloud.radii);
        let build_ms = if kind == OrderKind::Bsp { built.elapsed().as_secs_f64() * 1e3 } else { 0.0 };
        for view in views {
            let ray = view.camera.view_ray();
            let mut times = Vec::with_capacity(runs);
            let mut slab = 0.0;
            for run in 0..warm_up + runs.max(1) {
                let t = Instant::now();
                slab = orderer.back_to_front(&cloud.positions, ray, &mut out);
                if run >= warm_up {
                    times.push(t.elapsed().as_secs_f64() * 1e3);
                }
            }
            times.sort_by(f64::total_cmp);
            rows.push(OrderRow {
                model: model.to_string(),
                view: view.name.to_string(),
                order: kind.name().to_string(),
                points: cloud.len(),
                ms: times[times.len() / 2],
                ms_min: times[0],
                ms_max: times[times.len() - 1],
                slab: slab as f64 / radius,
                build_ms,
            });
        }
    }
    rows
}

/// The rows as a Markdown table.
pub fn markdown(rows: &[OrderRow]) -> String {
    let mut out = String::from(
        "| model | points | view | order | ms median (min-max) | slab / radius | build ms |\n|---|---:|---|---|---:|---:|---:|\n",
    );
    for r in rows {
        out.push_str(&format!(
            "| {} | {} | {} | {} | {:.2} ({:.2}-{:.2}) | {:.5} | {} |\n",
            r.model,
            r.points,
            r.view,
            r.order,
            r.ms,
            r.ms_min,
            r.ms_max,
            r.slab,
            if r.build_ms > 0.0 { format!("{:.0}", r.build_ms) } else { "-".into() }
        ));
    }
    out
}
