//! `pointblend info FILE.copc.laz` (or a URL): the header, the octree and
//! the hierarchy read page by page, and the attributes of the root node's
//! points; the rest of the points are not decoded. The hierarchy's refused
//! entries are shown for the first few and counted; a root node that does
//! not decode says why.

use std::path::Path;

use anyhow::Result;
use pointblend::cloud::LoadOptions;
use pointblend::copc::{CopcStream, StreamOptions};
use pointblend::frame::Camera;
use pointblend::lod::{LodTree, SelectOptions};

pub fn run(file: &Path) -> Result<()> {
    let started = std::time::Instant::now();
    let name = file.to_string_lossy().to_string();
    let mut stream = CopcStream::open(&name, StreamOptions { progress: true, ..Default::default() })?;
    let header = &stream.header.las;
    println!("file:        {}", stream.name());
    println!(
        "encoding:    COPC, LAS {}, point format {}",
        header.version(),
        header.point_format().to_u8().unwrap_or(255)
    );
    println!("points:      {}", stream.points());
    let b = header.bounds();
    println!(
        "bounds:      [{:.6}, {:.6}, {:.6}] .. [{:.6}, {:.6}, {:.6}]",
        b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z
    );
    let i = stream.header.info.clone();
    println!(
        "octree:      centre ({:.3}, {:.3}, {:.3}), half-size {:.3}, root spacing {:.4}",
        i.center_x, i.center_y, i.center_z, i.halfsize, i.spacing
    );
    // Every node, wherever the camera: this reads every hierarchy page, and no point.
    let everything = SelectOptions { budget: usize::MAX, radius_scale: 1.0, cull: false, finest_px: 0.0 };
    let camera = Camera::default_for(&stream.bounds_cloud(), 1.0);
    let all = stream.select(&camera, (64, 64), everything);
    let mut levels: Vec<(usize, u64)> = Vec::new();
    for &n in &all.nodes {
        let node = &stream.tree.nodes[n as usize];
        let l = node.key.l as usize;
        if levels.len() <= l {
            levels.resize(l + 1, (0, 0));
        }
        levels[l].0 += 1;
        levels[l].1 += u64::from(node.points);
    }
    println!(
        "hierarchy:   {} nodes in {} pages, {} points listed",
        all.nodes.len(),
        stream.tree.pages_read,
        stream.tree.known_points()
    );
    for (l, (nodes, points)) in levels.iter().enumerate() {
        println!("  level {l:>2}: {nodes} nodes, {points} points, spacing {:.4}", i.spacing / f64::from(1u32 << l));
    }
    let refused = &stream.tree.refused;
    for line in &refused.first {
        println!("refused:     entry {line}");
    }
    if refused.total > refused.first.len() {
        println!(
            "refused:     ... and {} more entries ({} in all)",
            refused.total - refused.first.len(),
            refused.total
        );
    }
    // The root's points, for the attributes the file carries.
    let root = stream.tree.root().expect("checked on open");
    let only_root = pointblend::lod::Selection { nodes: vec![root], splats: stream.tree.count(root) };
    stream.load(&only_root);
    match stream.gather(&only_root, &LoadOptions::default(), None) {
        Ok(frame) => {
            println!("root node:   {} points decoded", frame.cloud.len());
            for line in &frame.report.format_details {
                println!("format:      {line}");
            }
            match &frame.report.crs {
                Some(crs) => println!("crs:         {}", crs.split_whitespace().collect::<Vec<_>>().join(" ")),
                None => println!("crs:         none declared"),
            }
            super::shared::print_units(&frame.cloud.units, frame.report.crs.is_some());
            super::shared::print_attributes(&frame.cloud.attributes);
        }
        Err(e) => println!("root node:   not decoded: {}", stream.failure(root).unwrap_or(&e.reason)),
    }
    let stats = stream.stats();
    println!(
        "read:        {:.1} KB in {} requests, {:.3} s; {} nodes failed",
        stats.bytes_read as f64 / 1e3,
        stats.requests,
        started.elapsed().as_secs_f64(),
        stats.failed
    );
    Ok(())
}
