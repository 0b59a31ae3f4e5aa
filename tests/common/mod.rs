//! Helpers shared by the integration tests: data paths (shipped, and the
//! shared scans that skip a test when absent), tolerances, an
//! independent PLY reader for the test scans, a CPU silhouette rasteriser,
//! E57 and COPC files rewritten byte by byte (`e57bytes`, `copcbytes`), an
//! HTTP server that misbehaves (`bad_http`) and one GPU renderer per test
//! binary.
#![allow(dead_code)]

pub mod bad_http;
pub mod copcbytes;
pub mod corrupt;
pub mod e57bytes;
pub mod fuzz;
pub mod lidar;
pub mod nginx;
pub mod plywriter;
pub mod source;
pub mod tolerances;
pub mod viewer;

use std::path::PathBuf;
use std::sync::{Mutex, MutexGuard, OnceLock};

use glam::{DVec3, Mat4, Vec3};
use pointblend::frame::Camera;
use pointblend::render::GpuRenderer;

/// Data the repository ships for its tests (`tests/data`, see its README):
/// environment maps and a small volume, all from registry packages.
pub fn data(name: &str) -> PathBuf {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(name);
    assert!(path.exists(), "{} is missing from the repository (tests/data/README.md lists it)", path.display());
    path
}

/// The folder of the scans the repository may not ship (the Stanford bunny,
/// its merged range scans, the PCL table scan): `POINTBLEND_DATA` when set,
/// else `../shared/data` beside the repository.
pub fn shared_dir() -> PathBuf {
    std::env::var_os("POINTBLEND_DATA")
        .filter(|dir| !dir.is_empty())
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data"))
}

/// A scan of [`shared_dir`], or `None` when that folder is absent: the test
/// is then skipped, with one line on stderr and one in
/// `target/tmp/skipped-tests.txt`, which `scripts/test` counts. When the
/// folder is there, a missing file fails the test.
pub fn shared_data(name: &str) -> Option<PathBuf> {
    let dir = shared_dir();
    if !dir.is_dir() {
        skip(&format!("it needs {} from {}", name, dir.display()), " (set POINTBLEND_DATA to the folder of the scans)");
        return None;
    }
    let path = dir.join(name);
    assert!(path.exists(), "{} is missing: the folder of the scans is there but lacks it", path.display());
    Some(path)
}

/// Records that the running test is skipped because of `why`: one line on
/// stderr (with `hint` after it) and one in `target/tmp/skipped-tests.txt`,
/// which `scripts/test` counts.
pub fn skip(why: &str, hint: &str) {
    let test = std::thread::current().name().unwrap_or("a test").to_string();
    let line = format!("skipped {test}: {why}");
    eprintln!("{line}{hint}");
    let log = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("skipped-tests.txt");
    if let Ok(mut file) = std::fs::OpenOptions::new().create(true).append(true).open(log) {
        use std::io::Write;
        let _ = writeln!(file, "{line}");
    }
}

/// Runs the test on to its end only when a scan of [`shared_data`] is there:
/// `let bunny = require!(common::stanford_bunny());`.
#[macro_export]
macro_rules! require {
    ($data:expr) => {
        match $data {
            Some(path) => path,
            None => return,
        }
    };
}

/// The Stanford bunny as splats (34,834 splats with normals, radii and a
/// clay colour), made from the shared `bun_zipper.ply` by `pointblend
/// convert` once per test binary, into `target/tmp`: the model most tests
/// were calibrated on. `None` (the test is skipped) without the shared scans.
pub fn stanford_bunny() -> Option<PathBuf> {
    static BUNNY: OnceLock<PathBuf> = OnceLock::new();
    let zipper = shared_data("bun_zipper.ply")?;
    Some(
        BUNNY
            .get_or_init(|| {
                let tmp = PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
                let out = tmp.join(format!("stanford-bunny-{}.ply", std::process::id()));
                let status = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend"))
                    .arg("convert")
                    .arg(&zipper)
                    .arg(&out)
                    .stdout(std::process::Stdio::null())
                    .stderr(std::process::Stdio::null())
                    .status()
                    .expect("pointblend convert runs");
                assert!(status.success(), "pointblend convert {} failed", zipper.display());
                out
            })
            .clone(),
    )
}

/// The real scans the tests read whole: the bundled lion and the CGAL
/// building (shipped), then the Stanford bunny mesh, its merged range scans
/// and the PCL table scan where the shared scans are there (without them the
/// test is counted as skipped in part).
pub fn real_scans() -> Vec<PathBuf> {
    let mut scans = vec![bundled_model(), data("building.ply")];
    for name in ["bun_zipper.ply", "bunny_range_scans_merged.ply", "table_scene_mug_stereo_textured.ply"] {
        scans.extend(shared_data(name));
    }
    scans
}

/// Every `step`-th splat of the bundled lion, radii × √step so that they
/// still cover the surface: a real scan small enough for the tests that
/// render many plans or variants of one frame.
pub fn thinned_lion(step: usize) -> pointblend::cloud::PointCloud {
    fn every<T: Copy>(values: &[T], step: usize) -> Vec<T> {
        values.iter().step_by(step).copied().collect()
    }
    let (lion, _) = pointblend::cloud::load(&bundled_model()).expect("the bundled lion loads");
    let thinned = pointblend::cloud::PointCloud {
        positions: every(&lion.positions, step),
        normals: every(&lion.normals, step),
        radii: every(&lion.radii, step).into_iter().map(|r| r * (step as f32).sqrt()).collect(),
        colours: every(&lion.colours, step),
        opacity: every(&lion.opacity, step),
        two_sided: every(&lion.two_sided, step),
        ..lion
    };
    assert!(thinned.is_consistent());
    thinned
}

/// A file of `assets/`.
pub fn asset(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets").join(name)
}

/// The mesh pointblend ships (`assets/knot.ply`, a torus knot it makes).
pub fn bundled_mesh() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/knot.ply")
}

/// The model pointblend ships (`assets/lion.ply`, see assets/README.md).
pub fn bundled_model() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/lion.ply")
}

/// Looks down -z at the origin from z = 5 with a 30° field.
pub fn looking_down_z() -> Camera {
    Camera {
        target: Vec3::ZERO,
        distance: 5.0,
        azimuth_deg: 0.0,
        elevation_deg: 0.0,
        fov_y_deg: 30.0,
        up: pointblend::frame::UpAxis::PosY,
        scene_radius: 3.0,
        projection: Default::default(),
    }
}

/// Runs `pointblend render ARGS --out OUT`: its exit status and stderr.
pub fn render_cli<S: AsRef<std::ffi::OsStr>>(args: &[S], out: &std::path::Path) -> (bool, String) {
    let result = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .arg("render")
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .expect("pointblend runs");
    (result.status.success(), String::from_utf8_lossy(&result.stderr).into_owned())
}

/// Runs `pointblend bench ARGS --out OUT`, which must succeed: the rows of its `bench.json`.
#[allow(dead_code)]
pub fn bench_rows<S: AsRef<std::ffi::OsStr>>(args: &[S], out: &std::path::Path) -> Vec<serde_json::Value> {
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .arg("bench")
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .expect("pointblend runs");
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    serde_json::from_slice(&std::fs::read(out.join("bench.json")).expect("bench wrote bench.json")).unwrap()
}

/// [`render_cli`] that must fail with exactly one `error:` line and write
/// nothing (`what` names the case in messages); returns that line.
pub fn refused_in_one_line<S: AsRef<std::ffi::OsStr>>(args: &[S], out: &std::path::Path, what: &str) -> String {
    let (ok, stderr) = render_cli(args, out);
    assert!(!ok, "{what} was accepted");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "{what}: {stderr}");
    assert!(!out.exists(), "{what} wrote an output");
    errors[0].to_string()
}

/// One renderer for the whole test binary; tests that render take turns.
pub fn renderer() -> MutexGuard<'static, GpuRenderer> {
    static RENDERER: OnceLock<Mutex<GpuRenderer>> = OnceLock::new();
    RENDERER
        .get_or_init(|| Mutex::new(GpuRenderer::new().expect("a Vulkan adapter (lavapipe) is needed for render tests")))
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Vertices and triangles of an ASCII PLY mesh, read without the library
/// (an independent check of the loader on real data).
pub struct AsciiMesh {
    pub vertices: Vec<DVec3>,
    pub triangles: Vec<[usize; 3]>,
}

pub fn read_ascii_mesh(path: &std::path::Path) -> AsciiMesh {
    let text = std::fs::read_to_string(path).expect("readable ASCII PLY");
    let mut lines = text.lines();
    let (mut vertex_count, mut face_count) = (0usize, 0usize);
    for line in lines.by_ref() {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["element", "vertex", n] => vertex_count = n.parse().expect("count"),
            ["element", "face", n] => face_count = n.parse().expect("count"),
            ["end_header"] => break,
            _ => {}
        }
    }
    let vertices = lines
        .by_ref()
        .take(vertex_count)
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().take(3).map(|w| w.parse().expect("number")).collect();
            DVec3::new(v[0], v[1], v[2])
        })
        .collect();
    let triangles = lines
        .take(face_count)
        .map(|l| {
            let v: Vec<usize> = l.split_whitespace().skip(1).take(3).map(|w| w.parse().expect("index")).collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    AsciiMesh { vertices, triangles }
}

/// Rasterises triangles (world coordinates, already re-centred) into a
/// coverage mask with the camera's matrices: pixel centres inside any triangle.
pub fn silhouette(triangles: &[[Vec3; 3]], camera: &Camera, width: u32, height: u32) -> Vec<bool> {
    let clip_from_world: Mat4 = camera.projection(width as f32 / height as f32) * camera.view_matrix();
    let mut mask = vec![false; (width * height) as usize];
    for tri in triangles {
        let p = tri.map(|v| {
            let c = clip_from_world * v.extend(1.0);
            let ndc = c.truncate() / c.w;
            glam::Vec2::new((ndc.x * 0.5 + 0.5) * width as f32, (0.5 - ndc.y * 0.5) * height as f32)
        });
        let lo = p[0].min(p[1]).min(p[2]).floor().max(glam::Vec2::ZERO);
        let hi = p[0].max(p[1]).max(p[2]).ceil().min(glam::Vec2::new(width as f32 - 1.0, height as f32 - 1.0));
        let edge = |a: glam::Vec2, b: glam::Vec2, q: glam::Vec2| (b - a).perp_dot(q - a);
        let area = edge(p[0], p[1], p[2]);
        if area.abs() < 1e-12 {
            continue;
        }
        for y in lo.y as u32..=hi.y.max(0.0) as u32 {
            for x in lo.x as u32..=hi.x.max(0.0) as u32 {
                let q = glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let w = [edge(p[1], p[2], q), edge(p[2], p[0], q), edge(p[0], p[1], q)];
                if w.iter().all(|&e| e * area >= 0.0) {
                    mask[(y * width + x) as usize] = true;
                }
            }
        }
    }
    mask
}

/// Pixels that differ from the background colour.
pub fn foreground(image: &image::RgbaImage, background: [u8; 3]) -> Vec<bool> {
    image.pixels().map(|p| p.0[..3] != background).collect()
}

/// The background colour as the renderer writes it.
pub fn background_rgb() -> [u8; 3] {
    let b = pointblend::frame::Shading::default().background;
    [b.x, b.y, b.z].map(|c| (c * 255.0).round() as u8)
}

/// Erodes (`grow` < 0) or dilates (`grow` > 0) a mask by |grow| pixels (square neighbourhood).
pub fn morph(mask: &[bool], width: u32, height: u32, grow: i32) -> Vec<bool> {
    let (w, h) = (width as i32, height as i32);
    let r = grow.abs();
    let dilate = grow > 0;
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let mut any = false;
            let mut all = true;
            for dy in -r..=r {
                for dx in -r..=r {
                    let (nx, ny) = (x + dx, y + dy);
                    let v = nx >= 0 && ny >= 0 && nx < w && ny < h && mask[(ny * w + nx) as usize];
                    any |= v;
                    all &= v;
                }
            }
            if dilate { any } else { all }
        })
        .collect()
}

/// A floor of splats (y = 0, 2 x 2 units, a checkerboard of two colours) and
/// a camera 0.5 mm above it looking 10° down, so that the splats under and
/// just ahead of the eye cross the near plane (near ≈ 2e-5).
pub fn floor_crossing_the_near_plane() -> (pointblend::cloud::PointCloud, Camera) {
    let n = 200;
    let mut cloud = pointblend::cloud::PointCloud::default();
    for i in 0..n {
        for j in 0..n {
            let (x, z) = (-1.0 + 2.0 * (i as f32 + 0.5) / n as f32, -1.0 + 2.0 * (j as f32 + 0.5) / n as f32);
            cloud.positions.push(Vec3::new(x, 0.0, z));
            cloud.normals.push(Vec3::Y);
            cloud.radii.push(0.012);
            cloud.colours.push(if (i / 10 + j / 10) % 2 == 0 { [200, 80, 80] } else { [80, 200, 80] });
            cloud.opacity.push(1.0);
        }
    }
    let (height, down) = (0.0005f32, 10f32.to_radians());
    let camera = Camera {
        target: Vec3::new(0.0, height - 0.5 * down.sin(), -0.5 * down.cos()),
        distance: 0.5,
        azimuth_deg: 0.0,
        elevation_deg: 10.0,
        fov_y_deg: 60.0,
        up: pointblend::frame::UpAxis::PosY,
        scene_radius: 1.5,
        projection: Default::default(),
    };
    (cloud, camera)
}

/// How many splats of `cloud` cross the near plane of `camera`: their disc
/// reaches both sides of it.
pub fn splats_crossing_the_near_plane(cloud: &pointblend::cloud::PointCloud, camera: &Camera) -> usize {
    let (near, _) = camera.near_far();
    let view = camera.view_matrix();
    (0..cloud.len())
        .filter(|&i| {
            let depth = -view.transform_point3(cloud.positions[i]).z;
            let normal = view.transform_vector3(cloud.normals[i]);
            // The disc's depth extent: r · sqrt(1 - n_z²).
            let reach = cloud.radii[i] * (1.0 - normal.z * normal.z).max(0.0).sqrt();
            depth - reach < near && depth + reach > near
        })
        .count()
}

/// `count` two-sided splats at the origin facing +z (the camera of a
/// default view), of radius 0.1, each of `opacity` and `colour`.
pub fn coincident(count: usize, opacity: f32, colour: [u8; 3]) -> pointblend::scene::Scene {
    let mut cloud = pointblend::cloud::PointCloud::default();
    for _ in 0..count {
        cloud.positions.push(Vec3::ZERO);
        cloud.normals.push(Vec3::Z);
        cloud.radii.push(0.1);
        cloud.colours.push(colour);
        cloud.opacity.push(opacity);
    }
    let mut scene = pointblend::scene::Scene::from(cloud);
    scene.objects[0].material.two_sided = true;
    scene
}

/// A scene file of `tests/common/scenes` on the Stanford bunny, the way the
/// scenes in `assets/` were before the bundled model became the lion (the
/// scenes docs/BENCHMARKS.md's bunny figures were measured on): written once per test
/// binary into `target/tmp` with the converted bunny, the shared mesh and
/// the bundled environment map in place of its relative paths. `None` (the
/// test is skipped) without the shared scans.
pub fn stanford_scene(name: &str) -> Option<PathBuf> {
    let bunny = stanford_bunny()?;
    let zipper = shared_data("bun_zipper.ply")?;
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("tests/common/scenes").join(name)).expect("a test scene");
    let text = text
        .replace("\"bunny.ply\"", &format!("{:?}", bunny.display().to_string()))
        .replace("\"../tests/data/bun_zipper.ply\"", &format!("{:?}", zipper.display().to_string()))
        .replace("\"venice.exr\"", &format!("{:?}", root.join("assets/venice.exr").display().to_string()));
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("{}-{name}", std::process::id()));
    std::fs::write(&path, text).expect("target/tmp is writable");
    Some(path)
}

/// `scene` in `settings.mode` (grouped as the mode needs), from
/// [`looking_down_z`], at `size`²: a GPU frame, or the CPU reference.
pub fn render_mode(
    scene: &pointblend::scene::Scene,
    settings: &pointblend::frame::RenderSettings,
    size: u32,
) -> image::RgbaImage {
    use pointblend::reference::{self, ReferenceOptions};
    let camera = looking_down_z();
    if !settings.mode.is_gpu() {
        return reference::render(scene, &camera, &ReferenceOptions::matching(settings, scene), size, size);
    }
    let cloud = scene.flattened();
    let grouping = settings.mode.needs_grouping().then(|| settings.grouping_for_mode().compute(&cloud).unwrap());
    let mut renderer = renderer();
    let mut gpu = renderer.upload(scene, grouping.as_ref());
    renderer.render_image(&mut gpu, &camera, settings, size, size).expect("render").0
}

/// Mean |ΔR| + |ΔG| + |ΔB| per pixel, in 0-255 steps.
pub fn mean_difference(a: &image::RgbaImage, b: &image::RgbaImage) -> f64 {
    assert_eq!(a.dimensions(), b.dimensions());
    let sum: u64 =
        a.pixels().zip(b.pixels()).map(|(p, q)| (0..3).map(|c| u64::from(p[c].abs_diff(q[c]))).sum::<u64>()).sum();
    sum as f64 / f64::from(a.width() * a.height())
}
