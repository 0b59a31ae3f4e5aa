//! `pointblend group FILE`: point grouping with MGC, WGC or hashing, and its quality.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Result, bail};
use pointblend::cloud::PointCloud;
use pointblend::frame::Camera;
use pointblend::grouping::{self, Grouping, GroupingAlgo, GroupingReport, GroupingSpec, Tuning, cache, metrics};
use serde_json::json;

#[derive(clap::Args, Debug)]
pub struct Args {
    #[arg(help = super::formats_help::grouped_file())]
    pub file: PathBuf,
    /// The grouping, written as `render --group` and bench's `group=` write it.
    #[arg(long, default_value = "mgc-c0.4", value_name = "SPEC", help = format!(
        "The grouping, written as `render --group` and bench's `group=` write it: {}",
        grouping::spec::GRAMMAR
    ))]
    pub group: GroupingSpec,
    /// MGC: search the largest c (to 1/64) that needs at most K groups, in place of the spec's c.
    #[arg(long, value_name = "K")]
    pub max_groups: Option<usize>,
    /// WGC: the overlap graph's relaxation c in 0..=1, edges between splats closer than c·(r_i + r_j) [default: 1].
    #[arg(long, value_name = "C")]
    pub graph_c: Option<f32>,
    /// WGC: weights are the plain overlap area, without Eq. 7's (1 - n_i·n_j) factor.
    #[arg(long)]
    pub pure_area: bool,
    /// Hashing that resolves collisions: only for splats nearer the default camera than the median.
    #[arg(long)]
    pub near_only: bool,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Neither read nor write the grouping cache.
    #[arg(long)]
    pub no_cache: bool,
}

impl Args {
    /// The knobs a spec's name does not hold, checked against the spec's algorithm.
    fn tuning(&self, cloud: &PointCloud) -> Result<Tuning> {
        let spec = self.group;
        let (mgc, wgc) = (matches!(spec.algo, GroupingAlgo::Mgc { .. }), matches!(spec.algo, GroupingAlgo::Wgc { .. }));
        let resolving = matches!(spec.algo, GroupingAlgo::Hash { resolve_collisions: true, .. });
        if self.max_groups.is_some() && !mgc {
            bail!("--max-groups searches MGC's c; {spec} is not an MGC grouping");
        }
        if (self.graph_c.is_some() || self.pure_area) && !wgc {
            bail!("--graph-c and --pure-area tune WGC; {spec} is not a WGC grouping");
        }
        if self.near_only && !resolving {
            bail!("--near-only tunes hashing that resolves collisions; {spec} is not one (hash-kK without -kept)");
        }
        if let Some(k) = self.max_groups.filter(|k| *k == 0 || *k > grouping::MAX_GROUPS) {
            bail!("--max-groups must be 1..={}, not {k}", grouping::MAX_GROUPS);
        }
        if let Some(c) = self.graph_c.filter(|c| !(0.0..=1.0).contains(c)) {
            bail!("--graph-c must be in 0..=1, not {c}");
        }
        let near = self.near_only.then(|| {
            let camera = Camera::default_for(cloud, 1.0);
            (camera.eye(), camera.distance)
        });
        Ok(Tuning { max_groups: self.max_groups, wgc_c: self.graph_c, pure_area: self.pure_area, near })
    }
}

pub fn run(args: &Args) -> Result<()> {
    let mut stages: Vec<(&str, f64)> = Vec::new();
    let t = Instant::now();
    let (cloud, _) = super::shared::load(&args.file)?;
    stages.push(("load", t.elapsed().as_secs_f64()));
    let (spec, tuning) = (args.group, args.tuning(&cloud)?);
    let cache = cache::Cache::from_env();
    let file_hash = if args.no_cache { None } else { pointblend::hash::file_hash(&args.file).ok() };

    let started = Instant::now();
    let (result, report) = match file_hash {
        Some(hash) => spec.compute_tuned_cached(&cache, hash, &cloud, &tuning)?,
        None => {
            let (g, report) = spec.compute_tuned(&cloud, &tuning)?;
            (g, Some(report))
        }
    };
    let from_cache = report.is_none();
    match &report {
        Some(report) => stages.extend(report.stages.iter().copied()),
        None => stages.push(("cache", started.elapsed().as_secs_f64())),
    }
    let grouping_seconds = started.elapsed().as_secs_f64();
    let notes = report.as_ref().map(|r| notes(args, r)).unwrap_or_default();
    let t = Instant::now();
    let m = metrics::measure(&cloud, &result);
    stages.push(("metrics", t.elapsed().as_secs_f64()));
    let degrees = report.as_ref().and_then(|r| r.degrees);
    let outcome = Outcome {
        cloud: &cloud,
        grouping: &result,
        metrics: &m,
        from_cache,
        seconds: grouping_seconds,
        stages: &stages,
        degrees,
        notes: &notes,
        cache_path: file_hash.map(|hash| cache.path_for(spec.cache_key(hash, &tuning))),
    };
    if args.json {
        print_json(args, &outcome);
    } else {
        print_text(args, &outcome);
    }
    Ok(())
}

/// The notes of a computed grouping: the c MGC found, WGC's costs, the
/// collisions hashing resolved, the radius enlargement.
fn notes(args: &Args, report: &GroupingReport) -> Vec<String> {
    let mut notes = Vec::new();
    if let (Some(c), Some(k)) = (report.c, args.max_groups) {
        notes.push(format!("c = {c:.4} is the largest relaxation with at most {k} groups"));
    }
    if let Some(wgc) = &report.wgc {
        notes.push(format!(
            "cost (Eq. 6) {:.4e} after initialisation, {:.4e} after {} moves",
            wgc.initial_cost, wgc.final_cost, wgc.moves
        ));
    }
    if let Some(resolved) = report.resolved {
        notes.push(format!("{resolved} collisions resolved"));
    }
    if let Some(enlarged) = &report.enlarged {
        let scales: Vec<String> = enlarged.scales.iter().map(|s| format!("{s:.3}")).collect();
        let stopped = enlarged.converged.iter().filter(|c| !**c).count();
        notes.push(format!(
            "enlarged radii x [{}] ({} of {} groups stopped at a bound; hash-table estimate x{:.3})",
            scales.join(", "),
            stopped,
            enlarged.scales.len(),
            enlarged.hash_table_scale
        ));
    }
    notes
}

/// What `group` prints, as JSON or as text.
struct Outcome<'a> {
    cloud: &'a PointCloud,
    grouping: &'a Grouping,
    metrics: &'a metrics::GroupingMetrics,
    from_cache: bool,
    /// Grouping (or reading the cache), without loading and metrics.
    seconds: f64,
    stages: &'a [(&'a str, f64)],
    /// The overlap graph's largest and average degree, when one was built.
    degrees: Option<(usize, f64)>,
    notes: &'a [String],
    /// The cache entry, unless the cache is off.
    cache_path: Option<PathBuf>,
}

fn print_json(args: &Args, o: &Outcome<'_>) {
    let m = o.metrics;
    let (max_degree, avg_degree) = o.degrees.unwrap_or((0, 0.0));
    let stage_seconds: serde_json::Map<String, serde_json::Value> =
        o.stages.iter().map(|(s, t)| (s.to_string(), json!(t))).collect();
    let object = json!({
        "file": args.file.display().to_string(),
        "points": o.cloud.len(),
        "grouping": args.group.to_string(),
        "k": m.k,
        "group_sizes": m.group_sizes,
        "max_degree": max_degree,
        "avg_degree": avg_degree,
        "overlap_factor": m.overlap_factor,
        "violations": m.violations,
        "coverage": m.coverage,
        "mean_coverage": m.mean_coverage,
        "duplication_ratio": m.duplication_ratio,
        "radius_scale": o.grouping.radius_scale,
        "from_cache": o.from_cache,
        "seconds": o.seconds,
        "stage_seconds": stage_seconds,
        "notes": o.notes,
    });
    println!("{object}");
}

fn print_text(args: &Args, o: &Outcome<'_>) {
    let m = o.metrics;
    println!(
        "{}: {} splats, {}{}",
        args.file.display(),
        o.cloud.len(),
        args.group,
        if o.from_cache { " (from the cache)" } else { "" }
    );
    println!("K:               {}", m.k);
    println!("group sizes:     {:?}", m.group_sizes);
    if let Some((max_degree, avg_degree)) = o.degrees {
        println!("degree:          max {max_degree}, average {avg_degree:.2}");
    }
    println!("overlap factor:  {:.4}", m.overlap_factor);
    println!("violations:      {} overlapping pairs within a group", m.violations);
    let coverage: Vec<String> = m.coverage.iter().map(|c| format!("{:.1}%", 100.0 * c)).collect();
    println!("coverage:        mean {:.1}%, per group [{}]", 100.0 * m.mean_coverage, coverage.join(", "));
    if m.duplication_ratio > 0.0 {
        println!("duplication:     +{:.1}% splats", 100.0 * m.duplication_ratio);
    }
    for note in o.notes {
        println!("note:            {note}");
    }
    println!("time:            {:.3} s grouping", o.seconds);
    for (stage, seconds) in o.stages {
        println!("  {stage:<22} {seconds:.3} s");
    }
    if let Some(path) = &o.cache_path {
        println!("cache:           {}", path.display());
    }
}
