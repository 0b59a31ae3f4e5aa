//! Benchmark rows and the files they are written to: `bench.json`, `bench.md`.

use std::path::Path;

use serde::Serialize;

/// Median and range of one pass's GPU time.
#[derive(Debug, Clone, Serialize)]
pub struct PassTime {
    pub pass: String,
    pub ms: f64,
    pub ms_min: f64,
    pub ms_max: f64,
}

/// What one view of a camera path (`--path`) cost to prepare, the same on
/// every row of that view: the nodes and bytes it read, and the points it
/// decoded, estimated, styled and grouped, with their seconds and the bytes
/// uploaded to the GPU for it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct ViewCosts {
    /// 0-based, in path order.
    pub view_index: usize,
    /// Nodes loaded for this view: a streamed file's; a file opened whole is
    /// one node, loaded for its first view.
    pub nodes_added: usize,
    /// Bytes read from the file or the server for this view.
    pub bytes_read: u64,
    /// Points prepared for this view: a streamed file's are those of the
    /// nodes it added, each decoded and estimated once, when it arrived; a
    /// file opened whole prepares all of its points for its first view.
    pub points_prepared: u64,
    /// Seconds of the view's preparation: decoding, estimating and (for a
    /// grouped mode) grouping the nodes it added, then building the
    /// selection (re-centring, merging copies) and styling it; a file opened
    /// whole is grouped whole.
    pub prepare_s: f64,
    /// Bytes of splat records uploaded to the GPU for this view (every
    /// variant's copy: a grouped variant draws its own).
    pub upload_bytes: u64,
}

/// One mode variant, seen from one view of one model.
#[derive(Debug, Clone, Serialize)]
pub struct BenchRow {
    pub model: String,
    /// The registry's mode name.
    pub mode: String,
    /// The mode with the settings that differ (`deferred:group=wgc-k8`), as `--modes` takes it.
    pub variant: String,
    /// What the error is measured against: the reference with every splat
    /// opaque (opaque modes) or with the scene's opacity (transparent modes).
    pub reference: String,
    /// Set when a transparent mode ran on a scene with nothing transparent:
    /// it then runs the opaque two-pass plan, and the row says so
    /// ("opaque scene: ran two-pass") rather than repeat two-pass's figures unexplained.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fallback: Option<String>,
    /// Whether this row is the reference itself: the ruler the other rows
    /// are measured against. Its ε (0) and PSNR (none) compare it with
    /// itself and say nothing; its time is the exact answer's cost.
    pub ruler: bool,
    pub view: String,
    /// The row's image, a file in the output folder (its difference image
    /// beside it as `…-diff.png`, except for the ruler's own rows).
    pub image: String,
    /// Wall time per frame, submission to `poll(wait)`, median over the timed frames.
    pub frame_ms: f64,
    pub frame_ms_min: f64,
    pub frame_ms_max: f64,
    /// Sum of the per-pass GPU timestamps (median), when the adapter has them.
    pub gpu_ms: Option<f64>,
    pub passes: Vec<PassTime>,
    /// ε of Zhang & Pajarola §6.3 against the reference, 0..255 units.
    pub eps: f64,
    /// ε split by the number of ε-layers each pixel's reference ray met
    /// (0: background; the last bucket counts that many or more): which
    /// pixels carry the error. Empty for the ruler's own rows.
    pub eps_by_layers: Vec<crate::reference::LayerError>,
    /// PSNR in dB; `null` for an image identical to the reference.
    pub psnr: Option<f64>,
    pub bad_pixel_share: f64,
    pub geometry_passes: usize,
    pub points: usize,
    pub width: u32,
    pub height: u32,
    /// Seconds to load the model (decode and estimation), once per model.
    pub load_s: f64,
    /// Groups K of a deferred variant (1 otherwise).
    pub k: usize,
    /// Seconds to group the splats (set-up of deferred variants; 0 when cached).
    pub group_s: Option<f64>,
    /// In a scene lit by scene lights: milliseconds to compute the shadow
    /// coefficients of every splat (a TSM build per light, or exact rays),
    /// done once per light position, not per frame.
    pub shadow_ms: Option<f64>,
    /// The TSM tables' memory at their largest, MiB (0 for exact rays).
    pub shadow_table_mib: Option<f64>,
    /// Timed frames behind the medians.
    pub frames: usize,
    /// With `--animate`: the animation frame (from 0) and its time in seconds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frame: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time: Option<f64>,
    /// With `--animate`: milliseconds to regroup the splats for this frame
    /// (the hash grouping this variant draws; none for a mode without groups).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub regroup_ms: Option<f64>,
    /// With `--animate`: milliseconds to write this frame's splats to the
    /// variant's GPU copy (none on frame 0, the first upload).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub upload_ms: Option<f64>,
    /// Under a point budget: milliseconds of the node selection in each
    /// timed frame (part of `frame_ms`); `points` is then the splats drawn.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub budget_select_ms: Option<f64>,
    /// In a frame that draws mesh triangles: the triangles drawn (`points`
    /// is then the splats drawn beside them, Guennebaud's hybrid rules).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub triangles: Option<u32>,
    /// `tiled`: the pixels of a frame from this view whose window of
    /// waiting hits overflowed, finished exactly a layer at a time (slower pixels).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub window_overflows: Option<u32>,
    /// `tiled`: bytes of its tile pipeline's buffers in the last timed frame
    /// (the largest part's, when drawn in parts): per-splat records, tile
    /// tables, the entries and the sort's scratch at their room.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tile_list_bytes: Option<u64>,
    /// `tiled`: whether the last timed frame's lists passed their room and
    /// it was drawn again with more.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tile_retried: Option<bool>,
    /// The parts of the screen the last timed frame was drawn in, when more
    /// than one (its targets, or `tiled`'s splats and lists, would pass the
    /// memory a render may take).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub parts: Option<usize>,
    /// With `--path`: what this row's view cost to prepare.
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub path: Option<ViewCosts>,
}

/// Writes `rows` as a JSON array, atomically.
pub fn write_json(rows: &[BenchRow], path: &Path) -> std::io::Result<()> {
    let text = serde_json::to_string_pretty(rows).map_err(std::io::Error::other)?;
    crate::output::write_atomically(path, text.as_bytes())
}

/// What a row of `--no-reference` is measured against.
pub const NO_REFERENCE: &str = "nothing (--no-reference)";

/// The rows as a Markdown table (of throughput, when nothing measured their error).
pub fn markdown(rows: &[BenchRow]) -> String {
    if !rows.is_empty() && rows.iter().all(|r| r.reference == NO_REFERENCE) {
        return throughput_markdown(rows);
    }
    let mut out = String::from(
        "| model | view | variant | K | points | size | geometry passes | frame ms median (min-max) | GPU ms | ε | PSNR dB | bad pixels | measured against |\n|---|---|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---|\n",
    );
    for r in rows {
        if r.ruler {
            out.push_str(&format!(
                "| {} | {} | {} (the ruler) | {} | {} | {}x{} | {} | {:.1} | - | ruler | ruler | ruler | itself: the other rows are measured against it |\n",
                r.model, r.view, r.variant, r.k, r.points, r.width, r.height, r.geometry_passes, r.frame_ms
            ));
            continue;
        }
        let mut variant = match &r.fallback {
            Some(note) => format!("{} ({note})", r.variant),
            None => r.variant.clone(),
        };
        if let Some(n) = r.window_overflows {
            variant.push_str(&format!(" ({n} window overflows)"));
        }
        out.push_str(&format!(
            "| {} | {} | {} | {} | {} | {}x{} | {} | {:.1} ({:.1}-{:.1}) | {} | {:.3} | {} | {:.2}% | {} |\n",
            r.model,
            r.view,
            variant,
            r.k,
            match r.triangles {
                Some(t) => format!("{} + {t} triangles", r.points),
                None => r.points.to_string(),
            },
            r.width,
            r.height,
            r.geometry_passes,
            r.frame_ms,
            r.frame_ms_min,
            r.frame_ms_max,
            r.gpu_ms.map_or("-".into(), |g| format!("{g:.1}")),
            r.eps,
            r.psnr.map_or("∞".into(), |p| format!("{p:.2}")),
            100.0 * r.bad_pixel_share,
            r.reference
        ));
    }
    if rows.iter().any(|r| r.frame.is_some()) {
        out.push_str(&animation_markdown(rows));
    }
    if rows.iter().any(|r| r.shadow_ms.is_some()) {
        out.push_str("\nShadow coefficients (once per light position, not per frame):\n\n| model | variant | shadows ms | TSM tables MiB |\n|---|---|---:|---:|\n");
        let mut seen = std::collections::HashSet::new();
        for r in rows.iter().filter(|r| r.shadow_ms.is_some()) {
            if seen.insert((&r.model, &r.variant)) {
                out.push_str(&format!(
                    "| {} | {} | {:.1} | {:.1} |\n",
                    r.model,
                    r.variant,
                    r.shadow_ms.unwrap_or(0.0),
                    r.shadow_table_mib.unwrap_or(0.0)
                ));
            }
        }
    }
    out
}

/// Per animation frame and variant, the means over views: frame time, regroup
/// and upload, their share of the frame, and ε against that frame's reference.
pub fn animation_markdown(rows: &[BenchRow]) -> String {
    let mut out = String::from(
        "\nPer animation frame (means over the views; the regroup and upload are once per frame):\n\n| model | frame | time s | variant | frame ms | regroup ms | upload ms | (regroup + upload) / frame | ε |\n|---|---:|---:|---|---:|---:|---:|---:|---:|\n",
    );
    let mut keys: Vec<(String, usize, String)> = Vec::new();
    for r in rows.iter().filter(|r| r.frame.is_some() && !r.ruler) {
        let key = (r.model.clone(), r.frame.unwrap_or(0), r.variant.clone());
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    for (model, frame, variant) in keys {
        let of: Vec<&BenchRow> =
            rows.iter().filter(|r| r.model == model && r.frame == Some(frame) && r.variant == variant).collect();
        let mean = |f: &dyn Fn(&BenchRow) -> f64| of.iter().map(|r| f(r)).sum::<f64>() / of.len().max(1) as f64;
        let frame_ms = mean(&|r| r.frame_ms);
        let regroup = of[0].regroup_ms;
        let upload = of[0].upload_ms;
        let share = match (regroup, upload) {
            (Some(g), Some(u)) => format!("{:.0}%", 100.0 * (g + u) / frame_ms.max(1e-9)),
            _ => "-".into(),
        };
        let ms = |v: Option<f64>| v.map_or("-".into(), |v| format!("{v:.1}"));
        out.push_str(&format!(
            "| {model} | {frame} | {:.3} | {variant} | {frame_ms:.1} | {} | {} | {share} | {:.3} |\n",
            of[0].time.unwrap_or(0.0),
            ms(regroup),
            ms(upload),
            mean(&|r| r.eps)
        ));
    }
    out
}

/// `--no-reference` rows: frame and GPU time, and millions of splats drawn
/// per second of each.
fn throughput_markdown(rows: &[BenchRow]) -> String {
    let mut out = String::from(
        "| model | view | variant | points | size | frame ms median (min-max) | GPU ms | M splats/s (frame) | M splats/s (GPU) | parts |\n|---|---|---|---:|---|---:|---:|---:|---:|---:|\n",
    );
    let rate = |ms: f64, points: usize| points as f64 / (ms * 1e-3) / 1e6;
    for r in rows {
        out.push_str(&format!(
            "| {} | {} | {} | {} | {}x{} | {:.1} ({:.1}-{:.1}) | {} | {:.1} | {} | {} |\n",
            r.model,
            r.view,
            r.variant,
            r.points,
            r.width,
            r.height,
            r.frame_ms,
            r.frame_ms_min,
            r.frame_ms_max,
            r.gpu_ms.map_or("-".into(), |g| format!("{g:.1}")),
            rate(r.frame_ms, r.points),
            r.gpu_ms.map_or("-".into(), |g| format!("{:.1}", rate(g, r.points))),
            r.parts.map_or("1".into(), |n| n.to_string()),
        ));
    }
    out
}
