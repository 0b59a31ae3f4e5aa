//! Meshes in scenes (`mesh =` and `hybrid =`): triangles drawn by the
//! modes that draw them, against the reference's exact ray-triangle
//! intersections; Guennebaud's hybrid rules (triangles where splats would
//! be large, splats elsewhere) without cracks; and bad mesh files.

mod common;

use std::path::Path;
use std::sync::Arc;

use common::tolerances::{BOUNDARY_RIM_PIXELS, MAX_HYBRID_EPS_RATIO, MAX_MESH_EPS};
use pointblend::frame::Camera;
use pointblend::reference::{self, ReferenceOptions};
use pointblend::render::report::HybridStats;
use pointblend::render::{PreparedScene, RenderMode, RenderSettings};
use pointblend::scene::{self, Scene};

const SIZE: u32 = 192;

/// A cube of side 1 centred at the origin, each face a grid of n×n quads
/// with its own vertices (crisp edges: the faces do not share vertices, as
/// in most exported meshes), coloured by position; plus `extra` face lines.
fn cube_ply(n: usize, extra: &[&str]) -> String {
    cube_faces_ply(n, 6, extra)
}

/// The first `count` faces of [`cube_ply`]'s cube (the first: x = -0.5, facing -x).
fn cube_faces_ply(n: usize, count: usize, extra: &[&str]) -> String {
    let mut vertices = Vec::new();
    let mut faces = Vec::new();
    for (axis, side) in (0..3).flat_map(|axis| [(axis, -0.5f32), (axis, 0.5)]).take(count) {
        let base = vertices.len();
        for i in 0..=n {
            for j in 0..=n {
                let (u, v) = (i as f32 / n as f32 - 0.5, j as f32 / n as f32 - 0.5);
                let mut p = [0.0f32; 3];
                p[axis] = side;
                p[(axis + 1) % 3] = u;
                p[(axis + 2) % 3] = v;
                vertices.push(p);
            }
        }
        for i in 0..n {
            for j in 0..n {
                let a = base + i * (n + 1) + j;
                let (b, c, d) = (a + n + 1, a + n + 2, a + 1);
                // Outward winding on both sides.
                let quad = if side > 0.0 { [a, b, c, d] } else { [a, d, c, b] };
                faces.push(format!("4 {} {} {} {}", quad[0], quad[1], quad[2], quad[3]));
            }
        }
    }
    let mut text = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
         property uchar red\nproperty uchar green\nproperty uchar blue\nelement face {}\n\
         property list uchar int vertex_indices\nend_header\n",
        vertices.len(),
        faces.len() + extra.len()
    );
    for p in &vertices {
        let c = p.map(|x| (60.0 + 180.0 * (x + 0.5)) as u8);
        text += &format!("{} {} {} {} {} {}\n", p[0], p[1], p[2], c[0], c[1], 200 - c[2] / 2);
    }
    for f in faces.iter().map(String::as_str).chain(extra.iter().copied()) {
        text += f;
        text += "\n";
    }
    text
}

/// A scene file in `dir` with one object `key = "cube.ply"` and its `extra` lines.
fn cube_scene(dir: &Path, key: &str, object: &str) -> std::path::PathBuf {
    std::fs::write(dir.join("cube.ply"), cube_ply(20, &[])).unwrap();
    let path = dir.join(format!("{key}.toml"));
    std::fs::write(&path, format!("[[object]]\n{key} = \"cube.ply\"\n{object}\n")).unwrap();
    path
}

fn open(path: &Path) -> Arc<Scene> {
    let (scene, warnings) = scene::open(path, &Default::default()).expect("the scene opens");
    assert!(warnings.is_empty(), "{warnings:?}");
    Arc::new(scene)
}

/// Looking at a corner of the cube from close by: its near faces' splats
/// are several times larger on screen than its far faces'.
fn corner_camera(scene: &Scene) -> Camera {
    let mut camera = Camera::default_for(&scene.flattened(), 1.0);
    camera.azimuth_deg = 35.0;
    camera.elevation_deg = 25.0;
    camera.distance = 2.4;
    camera
}

/// A frame's image, its plan's notes and the leaves it drew as triangles, if any.
fn render(
    frames: &mut PreparedScene,
    camera: &Camera,
    settings: &RenderSettings,
) -> (image::RgbaImage, Vec<String>, Option<HybridStats>) {
    let mut renderer = common::renderer();
    let frame = frames.render(Some(&mut *renderer), camera, settings, (SIZE, SIZE), false).expect("render");
    let notes = frame.plan.notes.into_iter().chain(frame.report.lines()).collect();
    (frame.image, notes, frame.report.hybrid)
}

#[test]
fn a_hybrid_cube_matches_the_reference_on_its_triangles_without_cracks_between_triangles_and_splats() {
    let dir = tempfile::tempdir().unwrap();
    let scene = open(&cube_scene(dir.path(), "hybrid", ""));
    let camera = corner_camera(&scene);
    let mut frames = PreparedScene::of(Arc::clone(&scene));
    for mode in [RenderMode::TwoPass, RenderMode::Deferred, RenderMode::Tiled] {
        // Leaves whose splats would be wider than 9 px are triangles: the near faces here.
        let hybrid = RenderSettings { mode, hybrid_pixels: 9.0, ..Default::default() };
        let exact = reference::render(&scene, &camera, &ReferenceOptions::matching(&hybrid, &scene), SIZE, SIZE);
        let (image, notes, stats) = render(&mut frames, &camera, &hybrid);
        let stats = stats.expect("a hybrid frame");
        assert!(stats.triangle_leaves > 0 && stats.splat_leaves > 0, "{mode}: not a mix of both: {notes:?}");
        let splats_only = RenderSettings { hybrid_pixels: f32::INFINITY, ..hybrid };
        let (splats, _, splat_stats) = render(&mut frames, &camera, &splats_only);
        assert_eq!(splat_stats.unwrap().triangles, 0);
        let eps = reference::compare(&image, &exact).unwrap().eps;
        let splat_eps = reference::compare(&splats, &exact).unwrap().eps;
        println!(
            "{mode}: hybrid ε {eps:.3} ({} triangles of {} leaves, {} splats), splats alone ε {splat_eps:.3}",
            stats.triangles, stats.triangle_leaves, stats.splats
        );
        assert!(eps <= MAX_HYBRID_EPS_RATIO * splat_eps, "{mode}: hybrid ε {eps} against splats alone {splat_eps}");
        // No crack: inside the reference's silhouette (eroded by the rim) no background shows.
        let bg = common::background_rgb();
        let inside = common::morph(&common::foreground(&exact, bg), SIZE, SIZE, -BOUNDARY_RIM_PIXELS);
        let cracks = inside.iter().zip(common::foreground(&image, bg)).filter(|(i, f)| **i && !*f).count();
        assert_eq!(cracks, 0, "{mode}: {cracks} background pixels inside the cube");
    }
}

#[test]
fn meshes_opaque_and_transparent_are_their_triangles_and_modes_without_triangles_say_so() {
    let dir = tempfile::tempdir().unwrap();
    for (opacity, modes) in [
        ("", &[RenderMode::TwoPass, RenderMode::Deferred, RenderMode::Tiled][..]),
        ("opacity = 0.5", &[RenderMode::DepthPeel, RenderMode::Tiled][..]),
    ] {
        // The same file as a mesh, and as a hybrid object drawn as splats alone.
        let mesh = open(&cube_scene(dir.path(), "mesh", opacity));
        let hybrid = open(&cube_scene(dir.path(), "hybrid", opacity));
        let camera = corner_camera(&mesh);
        let mut mesh_frames = PreparedScene::of(Arc::clone(&mesh));
        let mut splat_frames = PreparedScene::of(Arc::clone(&hybrid));
        for &mode in modes {
            let settings = RenderSettings { mode, ..Default::default() };
            let exact = reference::render(&mesh, &camera, &ReferenceOptions::matching(&settings, &mesh), SIZE, SIZE);
            let (image, notes, stats) = render(&mut mesh_frames, &camera, &settings);
            let stats = stats.expect("a frame with triangles");
            assert_eq!((stats.splats, stats.splat_leaves), (0, 0), "{mode}: a mesh is triangles only: {notes:?}");
            let splats_only = RenderSettings { hybrid_pixels: f32::INFINITY, ..settings };
            let (splats, _, _) = render(&mut splat_frames, &camera, &splats_only);
            let eps = reference::compare(&image, &exact).unwrap().eps;
            let splat_eps = reference::compare(&splats, &exact).unwrap().eps;
            println!("{mode} {opacity}: ε {eps:.4} ({} triangles), as splats alone {splat_eps:.3}", stats.triangles);
            assert!(eps <= MAX_HYBRID_EPS_RATIO * splat_eps, "{mode} {opacity}: ε {eps} against {splat_eps}");
            if opacity.is_empty() {
                assert!(eps <= MAX_MESH_EPS, "{mode}: ε {eps}");
            }
        }
        // A mode that cannot draw triangles draws the vertices' splats, and says so in the plan;
        // given an opaque scene it runs the two-pass plan, which draws them.
        let settings = RenderSettings { mode: RenderMode::Alg2, ..Default::default() };
        let (_, notes, _) = render(&mut mesh_frames, &camera, &settings);
        let said = |what: &str| notes.iter().any(|n| n.contains(what));
        match opacity.is_empty() {
            true => assert!(said("meshes: 4800 triangles") && !said("cannot draw"), "{notes:?}"),
            false => assert!(said("alg2 cannot draw triangles"), "{notes:?}"),
        }
    }
}

#[test]
fn one_sided_triangles_seen_from_behind_are_culled_and_a_mesh_after_a_cloud_keeps_its_place() {
    let dir = tempfile::tempdir().unwrap();
    // One face of the cube, seen from behind: culled when one-sided, drawn when two-sided.
    std::fs::write(dir.path().join("quad.ply"), cube_faces_ply(8, 1, &[])).unwrap();
    let bg = common::background_rgb();
    for (sides, drawn) in [("", false), ("two_sided = true", true)] {
        let path = dir.path().join("quad.toml");
        std::fs::write(&path, format!("[[object]]\nmesh = \"quad.ply\"\n{sides}\n")).unwrap();
        let scene = open(&path);
        let mut camera = Camera::default_for(&scene.flattened(), 1.0);
        camera.look_from_direction(glam::Vec3::X); // the face at x = -0.5 faces -x: seen from behind
        let mut frames = PreparedScene::of(Arc::clone(&scene));
        for mode in [RenderMode::TwoPass, RenderMode::Deferred, RenderMode::Tiled, RenderMode::Reference] {
            let settings = RenderSettings { mode, ..Default::default() };
            let (image, notes, _) = render(&mut frames, &camera, &settings);
            let shown = common::foreground(&image, bg).iter().filter(|&&f| f).count();
            assert_eq!(shown > 0, drawn, "{mode} {sides}: {shown} pixels of the quad shown: {notes:?}");
        }
    }
    // The same face with normals of its own that face +x, against its winding:
    // its triangles are turned to face as the normals do (and said), so from +x it shows.
    let with_normals: String = cube_faces_ply(8, 1, &[])
        .replace("property float z\n", "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n")
        .lines()
        .map(|l| match l.split(' ').count() {
            6 if !l.starts_with("4 ") => {
                let (xyz, rgb) = l.split_at(l.match_indices(' ').nth(2).unwrap().0);
                format!("{xyz} 1 0 0{rgb}\n")
            }
            _ => format!("{l}\n"),
        })
        .collect();
    std::fs::write(dir.path().join("quad.ply"), with_normals).unwrap();
    std::fs::write(dir.path().join("quad.toml"), "[[object]]\nmesh = \"quad.ply\"\n").unwrap();
    let (scene, warnings) = scene::open(&dir.path().join("quad.toml"), &Default::default()).unwrap();
    assert!(warnings.iter().any(|w| w.contains("128 triangles were wound against")), "{warnings:?}");
    let mut camera = Camera::default_for(&scene.flattened(), 1.0);
    camera.look_from_direction(glam::Vec3::X);
    let mut frames = PreparedScene::of(Arc::new(scene));
    let (image, _, _) = render(&mut frames, &camera, &RenderSettings::default());
    assert!(common::foreground(&image, bg).iter().any(|&f| f), "the turned face is culled");

    // A cloud first, then a mesh: the mesh's triangles index its own splats, after the cloud's.
    std::fs::write(dir.path().join("cube.ply"), cube_ply(20, &[])).unwrap();
    let path = dir.path().join("both.toml");
    std::fs::write(
        &path,
        "[[object]]\nsphere = { splats = 4000, radius = 0.3, centre = [1.2, 0.0, 0.0] }\n\n[[object]]\nmesh = \"cube.ply\"\n",
    )
    .unwrap();
    let scene = open(&path);
    let camera = corner_camera(&scene);
    let mut frames = PreparedScene::of(Arc::clone(&scene));
    for mode in [RenderMode::TwoPass, RenderMode::Tiled] {
        let settings = RenderSettings { mode, ..Default::default() };
        let exact = reference::render(&scene, &camera, &ReferenceOptions::matching(&settings, &scene), SIZE, SIZE);
        let (image, _, stats) = render(&mut frames, &camera, &settings);
        let stats = stats.unwrap();
        assert_eq!(stats.splats, 4000, "{mode}: the sphere's splats, and none of the cube's");
        let eps = reference::compare(&image, &exact).unwrap().eps;
        println!("{mode}, a sphere of splats and a cube mesh: ε {eps:.4}");
        assert!(eps <= MAX_MESH_EPS, "{mode}: ε {eps}");
    }
}

#[test]
fn bad_mesh_faces_are_counted_in_one_line_and_a_mesh_without_faces_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    std::fs::write(&scene, "[[object]]\nmesh = \"cube.ply\"\n").unwrap();
    let out = dir.path().join("out.png");
    // A face naming a vertex the file lacks, and two degenerate triangles (a repeated vertex, zero area).
    std::fs::write(dir.path().join("cube.ply"), cube_ply(4, &["3 0 1 99999", "3 0 0 1", "3 0 1 2"])).unwrap();
    let (ok, stderr) = common::render_cli(&[scene.as_os_str(), "--size".as_ref(), "64x64".as_ref()], &out);
    assert!(ok, "{stderr}");
    assert!(out.exists());
    let lines = |what: &str| stderr.lines().filter(|l| l.contains(what)).count();
    assert_eq!(lines("1 faces that refer to vertices the file does not have"), 1, "{stderr}");
    assert_eq!(lines("2 triangles with zero area"), 1, "{stderr}");
    // Points without faces: one line naming the file, and nothing written.
    let points: String = cube_ply(2, &[])
        .replace("element face 24", "element face 0")
        .lines()
        .filter(|l| !l.starts_with("4 "))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(dir.path().join("points.ply"), points).unwrap();
    std::fs::write(&scene, "[[object]]\nmesh = \"points.ply\"\n").unwrap();
    std::fs::remove_file(&out).unwrap();
    let error = common::refused_in_one_line(&[&scene], &out, "a mesh without faces");
    assert!(error.contains("points.ply") && error.contains("no faces"), "{error}");
}
