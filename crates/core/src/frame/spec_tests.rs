//! Each decision of [`resolve`], on its own, with no GPU.

use super::*;
use crate::frame::{Light, Lights, Parameter};

fn mode(name: &str) -> RenderMode {
    name.parse().unwrap()
}

fn settings(name: &str) -> RenderSettings {
    RenderSettings { mode: mode(name), ..Default::default() }
}

fn transparent() -> SceneFacts {
    SceneFacts { splats: 1000, transparent: true, mean_radius: 0.5, shadows_at_hand: true, ..Default::default() }
}

fn opaque() -> SceneFacts {
    SceneFacts { transparent: false, ..transparent() }
}

fn still() -> View {
    View::still((64, 48))
}

fn lit(mut s: RenderSettings) -> RenderSettings {
    let light = Light::directional(glam::Vec3::NEG_Z);
    s.lights = Lights::new(&[light]).unwrap();
    s
}

#[test]
fn a_transparent_mode_on_an_opaque_scene_runs_the_two_pass_plan_and_says_so() {
    for mode in ["alg1", "alg2", "depth-peel", "approx-peel", "alpha-blend"] {
        let spec = resolve(&settings(mode), &opaque(), &still());
        assert!(spec.opaque_fallback, "{mode}");
        assert!(spec.notes.contains(&FrameNote::OpaqueFallback(mode.parse().unwrap())), "{mode}");
        assert!(!resolve(&settings(mode), &transparent(), &still()).opaque_fallback, "{mode}");
    }
    // tiled draws opaque scenes itself; opaque modes have nothing to fall back from; the reference runs on the CPU.
    for mode in ["tiled", "two-pass", "deferred", "reference"] {
        assert!(!resolve(&settings(mode), &opaque(), &still()).opaque_fallback, "{mode}");
    }
}

#[test]
fn the_preview_swaps_the_mode_and_takes_the_smaller_budget() {
    let asked = RenderSettings { point_budget: Some(5000), ..settings("alg2") };
    let preview = Preview { mode: mode("approx-peel"), budget: 200 };
    let large = SceneFacts { splats: 100_000, ..transparent() };
    let spec = resolve(&asked, &large, &View { size: (8, 8), preview: Some(preview) });
    assert_eq!(spec.mode(), mode("approx-peel"));
    assert_eq!(spec.asked.mode, mode("alg2"), "the asked settings are kept as asked");
    assert_eq!(spec.selection, Selection::Budget(200));
    let wide = Preview { budget: 9000, ..preview };
    let spec = resolve(&asked, &large, &View { size: (8, 8), preview: Some(wide) });
    assert_eq!(spec.selection, Selection::Budget(5000), "the asked budget when it is smaller");
}

#[test]
fn a_budget_applies_to_a_still_gpu_frame_with_more_splats_than_it() {
    let with = |budget| RenderSettings { point_budget: Some(budget), ..settings("two-pass") };
    assert_eq!(resolve(&with(100), &opaque(), &still()).selection, Selection::Budget(100));
    assert_eq!(resolve(&with(1000), &opaque(), &still()).selection, Selection::Whole, "a budget of every splat");
    let moving = SceneFacts { moving: true, ..opaque() };
    let spec = resolve(&with(100), &moving, &still());
    assert_eq!(spec.selection, Selection::Whole);
    assert!(spec.notes.contains(&FrameNote::BudgetInMotion));
    let streamed = SceneFacts { streamed: true, ..opaque() };
    assert_eq!(resolve(&with(100), &streamed, &still()).selection, Selection::Streamed, "the stream applied it");
    let reference = RenderSettings { point_budget: Some(100), ..settings("reference") };
    assert_eq!(resolve(&reference, &opaque(), &still()).selection, Selection::Whole, "the reference draws every splat");
}

#[test]
fn no_budget_is_left_in_the_settings_a_gpu_frame_draws_with() {
    let asked = RenderSettings { point_budget: Some(100), ..settings("two-pass") };
    for facts in [opaque(), SceneFacts { streamed: true, ..opaque() }, SceneFacts { surfaces: true, ..opaque() }] {
        let spec = resolve(&asked, &facts, &still());
        assert_eq!(spec.drawn.point_budget, None, "{facts:?}");
        assert_eq!(spec.asked.point_budget, Some(100));
    }
}

#[test]
fn triangles_are_drawn_by_modes_that_can_in_still_unlit_frames() {
    let meshes = SceneFacts { surfaces: true, ..transparent() };
    let spec = resolve(&settings("two-pass"), &meshes, &still());
    assert!(spec.draws_triangles());
    assert_eq!(spec.selection, Selection::Hybrid(settings("two-pass").hybrid_pixels));
    assert_eq!(spec.epsilon_radius, EpsilonRadius::Scene(0.5), "ε of the whole scene beside triangles");

    let refused = |s: &RenderSettings, facts: &SceneFacts| {
        let spec = resolve(s, facts, &still());
        assert!(!spec.draws_triangles());
        assert_eq!(spec.epsilon_radius, EpsilonRadius::Drawn);
        spec.notes.iter().find_map(|n| if let FrameNote::MeshesAsSplats(why) = n { Some(*why) } else { None })
    };
    assert_eq!(refused(&settings("alg2"), &meshes), Some(NoTriangles::Mode(mode("alg2"))));
    assert_eq!(refused(&lit(settings("two-pass")), &meshes), Some(NoTriangles::Lit));
    assert_eq!(refused(&settings("two-pass"), &SceneFacts { moving: true, ..meshes }), Some(NoTriangles::Moving));
    // A transparent mode that falls back to two-pass on an opaque scene draws triangles as two-pass does.
    let opaque_meshes = SceneFacts { transparent: false, ..meshes };
    assert!(resolve(&settings("alg2"), &opaque_meshes, &still()).draws_triangles());
    assert_eq!(refused(&settings("two-pass"), &transparent()), None, "no meshes, no note");
}

#[test]
fn a_budget_beside_triangles_is_not_applied_and_says_so() {
    let meshes = SceneFacts { surfaces: true, ..transparent() };
    let asked = RenderSettings { point_budget: Some(10), ..settings("tiled") };
    let spec = resolve(&asked, &meshes, &still());
    assert!(matches!(spec.selection, Selection::Hybrid(_)));
    assert!(spec.notes.contains(&FrameNote::BudgetBesideTriangles(10)));
}

#[test]
fn the_grouping_drawn_is_the_modes_or_its_per_frame_hash_grouping() {
    let group = |s: &RenderSettings, facts: &SceneFacts| resolve(s, facts, &still()).grouping;
    // The opaque deferred mode draws the grouping as set, computed once.
    let deferred = group(&settings("deferred"), &opaque()).unwrap();
    assert_eq!((deferred.spec, deferred.per_frame), (GroupingSpec::default(), false));
    // alg1 draws its covering grouping; on an opaque scene it falls back and draws none.
    assert_eq!(group(&settings("alg1"), &transparent()).unwrap().spec.to_string(), "wgc-k4-radius");
    assert_eq!(group(&settings("alg1"), &opaque()), None);
    assert_eq!(group(&settings("two-pass"), &transparent()), None);
    assert_eq!(group(&settings("reference"), &transparent()), None);
    // Moving, budgeted and hybrid frames regroup by hashing every frame.
    let budgeted = RenderSettings { point_budget: Some(10), ..settings("alg1") };
    // A streamed file's selection draws its nodes' hash groups, made once each.
    for (asked, facts, why) in [
        (settings("alg1"), SceneFacts { moving: true, ..transparent() }, RegroupReason::Moving),
        (budgeted, transparent(), RegroupReason::Budget),
        (settings("alg1"), SceneFacts { streamed: true, ..transparent() }, RegroupReason::Streamed),
    ] {
        let spec = resolve(&asked, &facts, &still());
        let drawn = spec.grouping.unwrap();
        assert!(drawn.per_frame);
        assert_eq!(drawn.spec.to_string(), "hash-k8-est");
        let asked = asked.grouping_for_mode();
        assert!(spec.notes.contains(&FrameNote::PerFrameGrouping { asked, drawn: drawn.spec, why }));
    }
    let meshes = SceneFacts { surfaces: true, ..opaque() };
    let hybrid = group(&settings("deferred"), &meshes).unwrap();
    assert!(hybrid.per_frame, "a hybrid frame's splats change with the view");
}

#[test]
fn lights_need_shadow_coefficients_at_hand() {
    let spec = resolve(&lit(settings("two-pass")), &opaque(), &still());
    assert!(spec.lights);
    let bare = SceneFacts { shadows_at_hand: false, ..opaque() };
    assert!(!resolve(&lit(settings("two-pass")), &bare, &still()).lights);
    let unlit = RenderSettings { lighting: false, ..lit(settings("two-pass")) };
    assert!(!resolve(&unlit, &opaque(), &still()).lights, "lighting off");
    assert!(!resolve(&settings("two-pass"), &opaque(), &still()).lights, "no scene lights");
}

#[test]
fn eye_dome_environment_and_low_pass_follow_what_the_mode_reads() {
    let edl = Some(crate::frame::EyeDome::default());
    let spec = resolve(&RenderSettings { eye_dome: edl, ..settings("two-pass") }, &opaque(), &still());
    assert_eq!(spec.eye_dome, edl);
    let spec = resolve(&RenderSettings { eye_dome: edl, ..settings("alg2") }, &opaque(), &still());
    assert_eq!(spec.eye_dome, None, "alg2 draws no EDL, not even on its two-pass fallback");

    let mut env = settings("alg2");
    env.environment.enabled = true;
    assert!(resolve(&env, &transparent(), &still()).environment);
    env.mode = mode("alg1");
    assert!(!resolve(&env, &transparent(), &still()).environment, "alg1 draws no environment");

    let mut filtered = settings("two-pass");
    Parameter::Prefilter.apply(&mut filtered, "ewa").unwrap();
    assert!(resolve(&filtered, &opaque(), &still()).low_pass_px > 0.0);
    filtered.mode = mode("alg1");
    assert_eq!(resolve(&filtered, &transparent(), &still()).low_pass_px, 0.0, "alg1 reads no prefilter");
}

#[test]
fn the_reference_and_an_empty_frame_run_on_the_cpu() {
    assert!(resolve(&settings("reference"), &transparent(), &still()).on_cpu);
    let empty = SceneFacts { splats: 0, ..transparent() };
    let spec = resolve(&settings("alg2"), &empty, &still());
    assert!(spec.on_cpu && spec.grouping.is_none() && !spec.opaque_fallback);
    assert!(!resolve(&settings("alg2"), &transparent(), &still()).on_cpu);
}

#[test]
fn every_note_reads_as_a_sentence() {
    let meshes = SceneFacts { surfaces: true, moving: true, ..opaque() };
    let asked = RenderSettings { point_budget: Some(5), ..settings("alg2") };
    let mut notes = resolve(&asked, &meshes, &still()).note_lines();
    notes.extend(resolve(&asked, &SceneFacts { surfaces: true, ..opaque() }, &still()).note_lines());
    assert!(notes.iter().any(|n| n.contains("runs the opaque two-pass plan")), "{notes:?}");
    assert!(notes.iter().any(|n| n.contains("the scene moves (triangles")), "{notes:?}");
    assert!(notes.iter().any(|n| n.contains("point budget 5 not applied")), "{notes:?}");
}
