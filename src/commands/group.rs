//! `pointblend group FILE`: point grouping with MGC, WGC or hashing, and its quality.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Result, bail};
use clap::ValueEnum;
use pointblend::frame::Camera;
use pointblend::grouping::{self, Grouping, cache, extend, hash, metrics, mgc, wgc};
use pointblend::spatial::overlap::OverlapOptions;
use serde_json::json;

#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
pub enum Algo {
    Mgc,
    Wgc,
    Hash,
}

#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
pub enum CollisionArg {
    None,
    All,
    Near,
}

#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
pub enum ExtendArg {
    Dup,
    Radius,
}

#[derive(clap::Args, Debug)]
pub struct Args {
    /// PLY file.
    pub file: PathBuf,
    /// Grouping algorithm.
    #[arg(long, value_enum, default_value = "mgc")]
    pub algo: Algo,
    /// Number of groups (wgc, hash; for mgc: the largest c with at most K groups is searched).
    #[arg(long)]
    pub k: Option<usize>,
    /// Overlap relaxation c in 0..=1: edges join splats closer than c·(r_i + r_j)
    /// (0.4 is the paper's opaque setting, and `--group`'s default).
    #[arg(long, default_value_t = 0.4)]
    pub c: f32,
    /// Relaxation (2): no edge between splats whose normals point in opposite directions.
    #[arg(long)]
    pub relax_normals: bool,
    /// Relaxation (1): no edge between nearly coplanar splats of the same colour.
    #[arg(long)]
    pub relax_coplanar: bool,
    /// WGC weights without Eq. 7's (1 - n_i·n_j) factor.
    #[arg(long)]
    pub pure_area: bool,
    /// WGC's MinimizeOverlap picks the colour of least Eq. 7 weight instead of
    /// the paper's least overlap area.
    #[arg(long)]
    pub eq7: bool,
    /// Hash grouping collision handling; `near` resolves splats nearer the default camera than the median.
    #[arg(long, value_enum, default_value = "all")]
    pub collisions: CollisionArg,
    /// Extend each group to cover the surface, for transparency.
    #[arg(long, value_enum)]
    pub extend: Option<ExtendArg>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Neither read nor write the grouping cache.
    #[arg(long)]
    pub no_cache: bool,
}

pub fn run(args: &Args) -> Result<()> {
    if !(0.0..=1.0).contains(&args.c) {
        bail!("--c must be in 0..=1, not {}", args.c);
    }
    if let Some(k) = args.k {
        if k == 0 || k > grouping::MAX_GROUPS {
            bail!("--k must be 1..={}, not {k}", grouping::MAX_GROUPS);
        }
    }
    let mut stages: Vec<(&str, f64)> = Vec::new();
    let t = Instant::now();
    let (cloud, _) = super::shared::load(&args.file)?;
    stages.push(("load", t.elapsed().as_secs_f64()));
    let overlap = OverlapOptions {
        c: args.c,
        skip_opposite_normals: args.relax_normals,
        skip_coplanar_same_colour: args.relax_coplanar,
    };
    let parameters = format!(
        "{:?}|{:?}|{:?}|{}|{}|{:?}|{:?}|v3",
        args.algo, args.k, overlap, args.pure_area, args.eq7, args.collisions, args.extend
    );
    let cache = cache::Cache::from_env();
    let cache_key = if args.no_cache { None } else { cache::key(&args.file, &parameters).ok() };

    let started = Instant::now();
    let mut degrees = None;
    let mut notes: Vec<String> = Vec::new();
    let cached = cache_key.and_then(|key| cache.load(key, cloud.len()));
    let from_cache = cached.is_some();
    let result: Grouping = match cached {
        Some(g) => {
            stages.push(("cache", started.elapsed().as_secs_f64()));
            g
        }
        None => {
            let t = Instant::now();
            let base = match args.algo {
                Algo::Mgc => {
                    let options = match args.k {
                        Some(k) => {
                            let c = mgc::c_for_groups(&cloud, k, &overlap);
                            notes.push(format!("c = {c:.4} is the largest relaxation with at most {k} groups"));
                            OverlapOptions { c, ..overlap }
                        }
                        None => overlap,
                    };
                    let (g, graph) = mgc::group(&cloud, &options)?;
                    degrees = Some((graph.max_degree(), graph.average_degree()));
                    stages.push(("graph + colouring", t.elapsed().as_secs_f64()));
                    g
                }
                Algo::Wgc => {
                    let options = wgc::WgcOptions {
                        k: args.k.unwrap_or(8),
                        pure_area: args.pure_area,
                        minimize_by_eq7: args.eq7,
                        overlap,
                        ..Default::default()
                    };
                    let (g, graph, report) = wgc::group(&cloud, &options)?;
                    degrees = Some((graph.max_degree(), graph.average_degree()));
                    let total = t.elapsed().as_secs_f64();
                    stages.push((
                        "graph",
                        total - report.seconds_weights - report.seconds_initialise - report.seconds_optimise,
                    ));
                    stages.push(("weights", report.seconds_weights));
                    stages.push(("initialise", report.seconds_initialise));
                    stages.push(("optimise", report.seconds_optimise));
                    notes.push(format!(
                        "cost (Eq. 6) {:.4e} after initialisation, {:.4e} after {} moves",
                        report.initial_cost, report.final_cost, report.moves
                    ));
                    g
                }
                Algo::Hash => {
                    let collisions = match args.collisions {
                        CollisionArg::None => hash::Collisions::None,
                        CollisionArg::All => hash::Collisions::All,
                        CollisionArg::Near => {
                            let camera = Camera::default_for(&cloud, 1.0);
                            hash::Collisions::Near { eye: camera.eye(), distance: camera.distance }
                        }
                    };
                    let (g, resolved) = hash::group(&cloud, &hash::HashOptions { k: args.k.unwrap_or(8), collisions })?;
                    stages.push(("hash grouping", t.elapsed().as_secs_f64()));
                    notes.push(format!("{resolved} collisions resolved"));
                    g
                }
            };
            let t = Instant::now();
            let extended = match args.extend {
                None => base,
                Some(ExtendArg::Dup) => {
                    let g = extend::duplicate(&cloud, &base);
                    stages.push(("extend: duplication", t.elapsed().as_secs_f64()));
                    g
                }
                Some(ExtendArg::Radius) => {
                    let (g, report) = extend::enlarge(&cloud, &base);
                    stages.push(("extend: radius", t.elapsed().as_secs_f64()));
                    let scales: Vec<String> = report.scales.iter().map(|s| format!("{s:.3}")).collect();
                    let stopped = report.converged.iter().filter(|c| !**c).count();
                    notes.push(format!(
                        "enlarged radii x [{}] ({} of {} groups stopped at a bound; hash-table estimate x{:.3})",
                        scales.join(", "),
                        stopped,
                        report.scales.len(),
                        report.hash_table_scale
                    ));
                    g
                }
            };
            if let Some(key) = cache_key {
                if let Err(e) = cache.store(key, &extended, cloud.len()) {
                    log::warn!("{e}");
                }
            }
            extended
        }
    };
    let grouping_seconds = started.elapsed().as_secs_f64();
    let t = Instant::now();
    let m = metrics::measure(&cloud, &result);
    stages.push(("metrics", t.elapsed().as_secs_f64()));
    let (max_degree, avg_degree) = degrees.unwrap_or((0, 0.0));
    if args.json {
        let stage_seconds: serde_json::Map<String, serde_json::Value> =
            stages.iter().map(|(s, t)| (s.to_string(), json!(t))).collect();
        let object = json!({
            "file": args.file.display().to_string(),
            "points": cloud.len(),
            "algo": format!("{:?}", args.algo).to_lowercase(),
            "c": args.c,
            "k": m.k,
            "group_sizes": m.group_sizes,
            "max_degree": max_degree,
            "avg_degree": avg_degree,
            "overlap_factor": m.overlap_factor,
            "violations": m.violations,
            "coverage": m.coverage,
            "mean_coverage": m.mean_coverage,
            "duplication_ratio": m.duplication_ratio,
            "radius_scale": result.radius_scale,
            "from_cache": from_cache,
            "seconds": grouping_seconds,
            "stage_seconds": stage_seconds,
            "notes": notes,
        });
        println!("{object}");
        return Ok(());
    }
    println!(
        "{}: {} splats, {:?}{}",
        args.file.display(),
        cloud.len(),
        args.algo,
        if from_cache { " (from the cache)" } else { "" }
    );
    println!("K:               {}", m.k);
    println!("group sizes:     {:?}", m.group_sizes);
    if degrees.is_some() {
        println!("degree:          max {max_degree}, average {avg_degree:.2}");
    }
    println!("overlap factor:  {:.4}", m.overlap_factor);
    println!("violations:      {} overlapping pairs within a group", m.violations);
    let coverage: Vec<String> = m.coverage.iter().map(|c| format!("{:.1}%", 100.0 * c)).collect();
    println!("coverage:        mean {:.1}%, per group [{}]", 100.0 * m.mean_coverage, coverage.join(", "));
    if m.duplication_ratio > 0.0 {
        println!("duplication:     +{:.1}% splats", 100.0 * m.duplication_ratio);
    }
    for note in &notes {
        println!("note:            {note}");
    }
    println!("time:            {grouping_seconds:.3} s grouping");
    for (stage, seconds) in &stages {
        println!("  {stage:<22} {seconds:.3} s");
    }
    if let Some(key) = cache_key {
        println!("cache:           {}", cache.path_for(key).display());
    }
    Ok(())
}
