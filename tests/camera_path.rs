//! `render --path views.json --path-frames N`: a flight through bookmarked
//! views, written as a numbered PNG sequence and an animated GIF; its first
//! and last frames are the first and last views, and a bad views file is
//! refused in one line with nothing written.

mod common;

use pointblend::frame::{Camera, RenderSettings, UpAxis, ViewPath};
use pointblend::scene::Scene;

fn view(azimuth: f32, distance: f32) -> Camera {
    Camera {
        target: glam::Vec3::new(0.0, 2.2, 0.0),
        distance,
        azimuth_deg: azimuth,
        elevation_deg: 15.0,
        fov_y_deg: 35.0,
        up: UpAxis::PosY,
        scene_radius: 4.0,
        projection: Default::default(),
    }
}

#[test]
fn a_path_writes_its_frames_and_an_animation_from_view_to_view() {
    let dir = tempfile::tempdir().unwrap();
    let views = dir.path().join("views.json");
    let (first, last) = (view(0.0, 14.0), view(90.0, 8.0));
    ViewPath::new(&[first, view(45.0, 10.0), last]).write(&views).unwrap();
    let out = dir.path().join("frames/f.png");
    let model = common::bundled_model();
    let args = [
        model.display().to_string(),
        "--path".into(),
        views.display().to_string(),
        "--path-frames".into(),
        "5".into(),
        "--size".into(),
        "96x80".into(),
    ];
    let (ok, stderr) = common::render_cli(&args, &out);
    assert!(ok, "{stderr}");
    let frames: Vec<image::RgbaImage> = (0..5)
        .map(|k| image::open(dir.path().join(format!("frames/f-{k:04}.png"))).expect("frame written").to_rgba8())
        .collect();
    assert!(frames.iter().all(|f| f.dimensions() == (96, 80)));
    assert_ne!(frames[0], frames[4], "the camera moved");
    // The first and last frames are the first and last views.
    let scene = Scene::from(pointblend::cloud::load(&model).unwrap().0);
    let mut renderer = common::renderer();
    let mut gpu = renderer.upload(&scene, None);
    for (camera, frame) in [(first, &frames[0]), (last, &frames[4])] {
        let want = renderer.render_image(&mut gpu, &camera, &RenderSettings::default(), 96, 80).unwrap().0;
        assert_eq!(&want, frame, "a frame at a view is that view's image");
    }
    let gif = std::fs::File::open(dir.path().join("frames/f.gif")).expect("the animation is written");
    let decoder = image::codecs::gif::GifDecoder::new(std::io::BufReader::new(gif)).unwrap();
    let animated = image::AnimationDecoder::into_frames(decoder).collect_frames().unwrap();
    assert_eq!(animated.len(), 5, "one GIF frame per frame");
}

#[test]
fn a_bad_views_file_is_refused_in_one_line_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("frames/f.png");
    let model = common::bundled_model().display().to_string();
    for (text, what) in [
        ("{\"views\": []}", "no view"),
        ("{\"views\": [{\"target\": [0, 0, 0]}]}", "not a views file"),
        ("not json", "not a views file"),
    ] {
        let views = dir.path().join("views.json");
        std::fs::write(&views, text).unwrap();
        let line = common::refused_in_one_line(&[model.as_str(), "--path", &views.display().to_string()], &out, what);
        assert!(line.contains("views.json") && line.contains(what), "{line}");
        assert!(!dir.path().join("frames/f-0000.png").exists() && !dir.path().join("frames/f.gif").exists());
    }
    let (ok, stderr) = common::render_cli(&[model.as_str(), "--path-frames", "1"], &out);
    assert!(!ok && stderr.contains("--path-frames"), "{stderr}");
}
