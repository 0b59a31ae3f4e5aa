//! The render core: for every mode of the registry each texture a recorded
//! pass was given (the view itself, recorded where its bind group or
//! attachment was made, named by identity) is one the shader's binding
//! means, by the binding's name; nothing is allocated that no pass was
//! given; the targets the recorded
//! render passes really bind are the ones the pool allocated (as bound) and
//! the ones the plan (and so `--explain`) says each pass reads and writes;
//! each target a pass binds as input is one its shader's entry point really
//! reads, as an array or not as the plan says, and each colour target it
//! writes is one of the entry point's outputs (read from the WGSL by naga,
//! not from the plan); a new plan frees what it does not use, each pipeline
//! is built once, every plan pass is timed, and each render pass has its own
//! uniforms.

mod common;

use pointblend::cloud::PointCloud;
use pointblend::frame::{Camera, Prefilter, Quality, RenderMode, RenderSettings};
use pointblend::grouping::GroupingSpec;
use pointblend::render::modes::FrameDesc;
use pointblend::render::passes::Command;
use pointblend::render::plan::{Layout, RenderPlan, TargetId};
use pointblend::render::shaders;
use pointblend::render::touches::Slot;
use pointblend::render::{GpuRenderer, GpuScene};

/// The bundled lion scan, a quarter of its splats.
fn model() -> PointCloud {
    common::thinned_lion(4)
}

/// Every setting that changes a plan's targets: quality, lighting, colours,
/// the grouping's K, and the peel layers k (2: one exact layer, whose depth
/// buffers alternate differently from the default's).
fn settings_of(mode: RenderMode) -> Vec<RenderSettings> {
    let mut all = Vec::new();
    for quality in [Quality::Filtered, Quality::Unfiltered] {
        for lighting in [true, false] {
            for grouping in [GroupingSpec::mgc(0.4), GroupingSpec::mgc(1.0)] {
                for peel_layers in [0, 2] {
                    all.push(RenderSettings { mode, quality, lighting, grouping, peel_layers, ..Default::default() });
                }
            }
        }
    }
    // The EWA prefilter: two-pass keeps coverage and sums what is behind.
    for lighting in [true, false] {
        all.push(RenderSettings { mode, lighting, prefilter: Prefilter::Ewa, ..Default::default() });
    }
    all
}

/// Uploads `cloud` as `settings`' mode needs it.
fn upload(renderer: &GpuRenderer, cloud: &PointCloud, settings: &RenderSettings) -> GpuScene {
    let grouping = settings.mode.needs_grouping().then(|| settings.grouping_for_mode().compute(cloud).unwrap());
    renderer.upload_cloud(cloud, grouping.as_ref())
}

/// Checks every render pass of `plan` against its composed WGSL: the group-1
/// textures the entry point uses are exactly the pass's inputs, in binding
/// order, each a 2D array exactly when the plan's target is one; a splat
/// pass's colour targets are the entry point's `@location` outputs.
fn check_against_shaders(plan: &RenderPlan, what: &str) {
    use naga::{Binding, ImageDimension, TypeInner};
    for (step, command) in plan.commands() {
        let (shader, entry, variant, inputs, outputs) = match command {
            Command::Splats(p) => (p.shader, p.entry, p.variant, &p.inputs, Some(p.colour.len())),
            Command::Fullscreen(p) => (p.shader, p.entry, p.variant, &p.inputs, None),
            Command::Compute(p) => {
                check_compute_against_shader(plan, p, &format!("{what}, pass {step}"));
                continue;
            }
        };
        let at = format!("{what}, pass {step} ({shader}:{entry}, {variant})");
        let source = shaders::compose(shader, variant).unwrap();
        let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{at}: {e}"));
        let info = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{at}: {e:?}"));
        let index =
            module.entry_points.iter().position(|e| e.name == entry).unwrap_or_else(|| panic!("{at}: no entry"));
        let uses = info.get_entry_point(index);
        let mut read: Vec<(u32, bool)> = module
            .global_variables
            .iter()
            .filter(|(handle, var)| var.binding.as_ref().is_some_and(|b| b.group == 1) && !uses[*handle].is_empty())
            .map(|(_, var)| {
                let arrayed = match module.types[var.ty].inner {
                    TypeInner::Image { dim: ImageDimension::D2, arrayed, .. } => arrayed,
                    ref other => panic!("{at}: group 1 holds {other:?}"),
                };
                (var.binding.as_ref().unwrap().binding, arrayed)
            })
            .collect();
        read.sort_unstable();
        let planned: Vec<(u32, bool)> = inputs
            .iter()
            .enumerate()
            .map(|(i, id)| (i as u32, matches!(plan.target(*id).unwrap().layout, Layout::Array { .. })))
            .collect();
        assert_eq!(
            read, planned,
            "{at}: the textures the shader reads (binding, array) differ from the pass's inputs {inputs:?}"
        );
        if let Some(outputs) = outputs {
            let result = module.entry_points[index].function.result.as_ref();
            let locations = match result.map(|r| (&r.binding, &module.types[r.ty].inner)) {
                None => 0,
                Some((Some(Binding::Location { .. }), _)) => 1,
                Some((_, TypeInner::Struct { members, .. })) => {
                    members.iter().filter(|m| matches!(m.binding, Some(Binding::Location { .. }))).count()
                }
                Some(_) => 0,
            };
            assert_eq!(locations, outputs, "{at}: the entry point writes {locations} colour outputs");
        }
    }
}

/// A compute pass of the tile pipeline: the storage textures its entry
/// point writes at group 1 are exactly the pass's outputs, in binding order,
/// and every group-1 binding it uses is one the engine binds.
fn check_compute_against_shader(plan: &RenderPlan, pass: &pointblend::render::passes::ComputePass, at: &str) {
    use naga::TypeInner;
    use pointblend::render::passes::compute::Binding;
    let at = format!("{at} ({}:{}, {})", pass.shader, pass.entry, pass.variant);
    let source = shaders::compose(pass.shader, pass.variant).unwrap();
    let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{at}: {e}"));
    let info = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
        .validate(&module)
        .unwrap_or_else(|e| panic!("{at}: {e:?}"));
    let index = module.entry_points.iter().position(|e| e.name == pass.entry).unwrap_or_else(|| panic!("{at}"));
    let uses = info.get_entry_point(index);
    let format = pass.outputs.first().map_or(wgpu::TextureFormat::Rgba32Float, |&id| plan.target(id).unwrap().format);
    let bound = pointblend::render::tile_layout::bindings(pass.work, pass.variant, format);
    let mut textures = Vec::new();
    for (handle, var) in module.global_variables.iter() {
        let Some(binding) = var.binding.as_ref().filter(|b| b.group == 1) else { continue };
        if uses[handle].is_empty() {
            continue;
        }
        let kind = bound.get(binding.binding as usize).unwrap_or_else(|| panic!("{at}: binding {binding:?} unbound"));
        match module.types[var.ty].inner {
            TypeInner::Image { .. } => {
                assert!(matches!(kind, Binding::StorageTexture(_)), "{at}: binding {} is {kind:?}", binding.binding);
                textures.push(binding.binding);
            }
            _ => assert!(!matches!(kind, Binding::StorageTexture(_)), "{at}: binding {} is a texture", binding.binding),
        }
    }
    textures.sort_unstable();
    let planned: Vec<u32> = bound
        .iter()
        .enumerate()
        .filter(|(_, b)| matches!(b, Binding::StorageTexture(_)))
        .map(|(i, _)| i as u32)
        .collect();
    assert_eq!(textures, planned, "{at}: the images it writes");
    assert_eq!(planned.len(), pass.outputs.len(), "{at}: one binding per output {:?}", pass.outputs);
}

/// What each shader binding means, as the shaders name it, and the targets
/// that may stand there (one name is read in several passes, e.g.
/// `accumulated_colour` is the opaque image's sums too, or only the weight
/// for a cloud of one colour). Written from
/// the shaders' and modes' meaning, not from a run: a pass given another
/// target in a binding, two inputs of one shape swapped for instance, fails.
const MEANINGS: &[(&str, &[&str])] = &[
    // Inputs (group 1 texture bindings), by variable name.
    ("accumulated_colour", &["accumulated colour", "accumulated weight", "opaque colour", "opaque weight"]),
    ("accumulated_normal", &["accumulated normal", "opaque normal"]),
    ("visibility_depth", &["depth"]),
    ("shaded_colour", &["shaded colour"]),
    ("behind_colour", &["behind colour"]),
    ("coverage", &["coverage"]),
    ("opaque_depth", &["opaque depth"]),
    ("opaque_image", &["opaque image"]),
    ("group_images", &["group images I_k", "blended image"]),
    ("group_colour", &["group colour", "group weight"]),
    ("group_depth", &["group depth"]),
    ("group_normal", &["group normal"]),
    ("nearest_colour", &["nearest layer I_k: w·rgb, w"]),
    ("nearest_depth", &["nearest layer I_k: depth"]),
    ("nearest_normal_alpha", &["nearest layer I_k: w·n, w·α"]),
    ("front_depth", &["nearest layer depth d and facing"]),
    ("other_images", &["other layers O_k"]),
    ("previous_layer", &["peel depth (even layers)", "peel depth (odd layers)"]),
    ("composite", &["composite"]),
    ("sums_colour", &["layer colour", "rest colour"]),
    ("sums_opacity", &["layer opacity", "rest opacity"]),
    ("sums_normal", &["layer normal", "rest normal"]),
    ("last_layer_colour", &["layer colour"]),
    ("tiled_colour", &["tiled image"]),
    ("glass_front", &["nearest transparent layer"]),
    ("glass_normal", &["its normal, layers behind"]),
    ("glass_behind", &["layers behind it"]),
    // Storage textures a compute pass writes.
    ("colour_out", &["tiled image"]),
    ("glass_front_out", &["nearest transparent layer"]),
    ("glass_normal_out", &["its normal, layers behind"]),
    ("glass_behind_out", &["layers behind it"]),
];

/// The variable at group 1, `binding` of `module`.
fn variable_at(module: &naga::Module, binding: u32) -> Option<String> {
    module.global_variables.iter().find_map(|(_, var)| {
        var.binding.as_ref().filter(|b| b.group == 1 && b.binding == binding).and_then(|_| var.name.clone())
    })
}

/// A texture view a recorded pass was given, named by identity in the pool.
struct Given {
    pass: usize,
    slot: Slot,
    target: TargetId,
    layer: Option<u32>,
    reads: bool,
    writes: bool,
}

/// Every view the last frame's passes were given; each must be a view of a pooled target.
fn given_views(renderer: &pointblend::render::Renderer, what: &str) -> Vec<Given> {
    renderer
        .last_frame_bindings()
        .iter()
        .map(|b| {
            let (target, layer) = renderer
                .target_of(&b.view)
                .unwrap_or_else(|| panic!("{what}: pass {} was given a view of no target in the pool", b.pass));
            Given { pass: b.pass, slot: b.slot, target, layer, reads: b.reads, writes: b.writes }
        })
        .collect()
}

/// Holds every texture the recorded passes were given (by the view's
/// identity, at the binding it was given to) against what the shader names
/// that binding: the texture bound at `accumulated_normal` must be a normal
/// target, whatever the plan says.
fn check_what_each_binding_was_given(given: &[Given], plan: &RenderPlan, what: &str) {
    let commands: Vec<(usize, &Command)> = plan.commands().collect();
    assert!(!given.is_empty() || commands.is_empty(), "{what}: no binding recorded");
    let mut modules: Vec<(usize, naga::Module)> = Vec::new();
    for g in given {
        let (Slot::Input(binding) | Slot::Storage(binding)) = g.slot else { continue };
        let (shader, variant) = commands
            .iter()
            .find(|(step, _)| *step == g.pass)
            .map(|(_, c)| match c {
                Command::Splats(p) => (p.shader, p.variant),
                Command::Fullscreen(p) => (p.shader, p.variant),
                Command::Compute(p) => (p.shader, p.variant),
            })
            .unwrap();
        if !modules.iter().any(|(pass, _)| *pass == g.pass) {
            let source = shaders::compose(shader, variant).unwrap();
            modules.push((g.pass, naga::front::wgsl::parse_str(&source).unwrap()));
        }
        let module = &modules.iter().find(|(pass, _)| *pass == g.pass).unwrap().1;
        let name = variable_at(module, binding).unwrap_or_else(|| panic!("{what}: {shader} has no binding {binding}"));
        let id = g.target.0;
        assert!(g.layer.is_none(), "{what}: pass {} was given one layer of '{id}' at `{name}`", g.pass);
        let allowed = MEANINGS.iter().find(|(n, _)| *n == name).map(|(_, a)| *a);
        let allowed = allowed.unwrap_or_else(|| panic!("{what}: {shader}'s `{name}` has no meaning listed"));
        assert!(
            allowed.contains(&id),
            "{what}: pass {} ({shader}) was given '{id}' at `{name}` ({:?}), which holds one of {allowed:?}",
            g.pass,
            g.slot
        );
    }
}

fn sorted(ids: &[TargetId]) -> Vec<&'static str> {
    let mut ids: Vec<&'static str> = ids.iter().map(|t| t.0).collect();
    ids.sort_unstable();
    ids
}

#[test]
fn every_target_the_recorded_passes_bind_is_allocated_as_bound_explained_as_used_and_nothing_else_is() {
    let colour = model();
    let mut one_colour = colour.clone();
    one_colour.colours.iter_mut().for_each(|c| *c = [90, 160, 200]);
    // Transparent modes plan their layers only for a transparent scene.
    let mut see_through = colour.clone();
    see_through.opacity.iter_mut().for_each(|a| *a = 0.5);
    let camera = Camera::default_for(&colour, 1.0);
    let mut renderer = common::renderer();
    let mut checked = 0;
    for mode in RenderMode::ALL.into_iter().filter(|m| m.is_gpu()) {
        for cloud in [&colour, &one_colour, &see_through] {
            for settings in settings_of(mode) {
                let mut gpu = upload(&renderer, cloud, &settings);
                let plan = renderer.render(&mut gpu, &camera, &settings, (96, 80)).unwrap();
                let held = renderer.renderer.allocated_targets();
                let given = given_views(&renderer.renderer, &mode.to_string());
                let what = format!("{mode} ({})", plan.variant);
                // The pool holds what the plan lists, no more, no less.
                let (mut sorted_held, mut planned) = (held.clone(), plan.targets.clone());
                sorted_held.sort_by_key(|t| t.id.0);
                planned.sort_by_key(|t| t.id.0);
                assert_eq!(sorted_held, planned, "{what}: the pool holds other targets than the plan lists\n{plan}");
                // What the passes were given is allocated as their pipelines and
                // views expect it: the plan's format, the frame's size, a layer
                // the texture has, in a pass of the plan.
                for g in &given {
                    let (t, id) = (held.iter().find(|t| t.id == g.target).unwrap(), g.target.0);
                    assert_eq!(Some(t), plan.target(g.target), "{what}: pass {} was given {id} unlike planned", g.pass);
                    assert_eq!((t.width, t.height), (96, 80), "{what}: {id}");
                    assert!(g.layer.is_none_or(|l| l < t.layers()), "{what}: {id} layer {:?}", g.layer);
                    assert!(g.pass < plan.steps.len(), "{what}: a pass outside the plan");
                }
                // Nothing is allocated that no pass was given, and every layer of an array is drawn.
                for target in &held {
                    let layers: std::collections::BTreeSet<u32> =
                        given.iter().filter(|g| g.target == target.id).filter_map(|g| g.layer).collect();
                    assert!(
                        given.iter().any(|g| g.target == target.id),
                        "{what}: {} is allocated but no pass binds it\n{plan}",
                        target.id.0
                    );
                    if target.layers() > 1 {
                        assert_eq!(layers.len() as u32, target.layers(), "{what}: {} layers drawn", target.id.0);
                    }
                }
                // --explain's reads and writes are the ones the GPU was given:
                // the views bound to each pass (by identity), read or written
                // as its pipeline and load operations were set up.
                for (i, step) in plan.steps.iter().enumerate() {
                    let given_as = |reading: bool| {
                        let mut ids: Vec<&'static str> = given
                            .iter()
                            .filter(|g| g.pass == i && if reading { g.reads } else { g.writes })
                            .map(|g| g.target.0)
                            .collect();
                        ids.sort_unstable();
                        ids.dedup();
                        ids
                    };
                    assert_eq!(
                        given_as(true),
                        sorted(&step.reads()),
                        "{what}: reads of pass {i} ({})\n{plan}",
                        step.name
                    );
                    assert_eq!(
                        given_as(false),
                        sorted(&step.writes()),
                        "{what}: writes of pass {i} ({})\n{plan}",
                        step.name
                    );
                }
                check_against_shaders(&plan, &what);
                check_what_each_binding_was_given(&given, &plan, &what);
                checked += 1;
            }
        }
    }
    assert!(checked >= 32, "{checked} plans checked");
}

#[test]
fn a_new_plan_frees_the_targets_it_does_not_use_and_pipelines_are_built_once() {
    let cloud = model();
    let camera = Camera::default_for(&cloud, 1.0);
    let mut renderer = common::renderer();
    let deferred = RenderSettings { mode: "deferred".parse().unwrap(), ..Default::default() };
    let two_pass = RenderSettings { mode: "two-pass".parse().unwrap(), ..Default::default() };
    let mut grouped = upload(&renderer, &cloud, &deferred);
    let mut plain = upload(&renderer, &cloud, &two_pass);
    renderer.render(&mut grouped, &camera, &deferred, (128, 128)).unwrap();
    let deferred_bytes = renderer.renderer.allocated_bytes();
    let plan = renderer.render(&mut plain, &camera, &two_pass, (128, 128)).unwrap();
    assert_eq!(renderer.renderer.allocated_bytes(), plan.target_bytes());
    assert!(plan.target_bytes() < deferred_bytes, "the group layers were freed");
    let built = renderer.renderer.pipelines_built();
    for _ in 0..3 {
        renderer.render(&mut grouped, &camera, &deferred, (128, 128)).unwrap();
        renderer.render(&mut plain, &camera, &two_pass, (128, 128)).unwrap();
    }
    assert_eq!(renderer.renderer.pipelines_built(), built, "the same frames built new pipelines");
    // A new output size reallocates targets but needs no new pipeline.
    renderer.render(&mut plain, &camera, &two_pass, (64, 200)).unwrap();
    assert_eq!(renderer.renderer.pipelines_built(), built);
}

#[test]
fn every_plan_pass_is_timed_even_with_many_groups() {
    let cloud = model();
    let camera = Camera::default_for(&cloud, 1.0);
    // Its own renderer, so turning timing on does not touch the shared one.
    let mut renderer = GpuRenderer::new().unwrap();
    if !renderer.renderer.enable_pass_timing(&renderer.ctx) {
        println!("this adapter has no timestamps: nothing to check");
        return;
    }
    for settings in settings_of("deferred".parse().unwrap()).into_iter().chain(settings_of("two-pass".parse().unwrap()))
    {
        let mut gpu = upload(&renderer, &cloud, &settings);
        let plan = renderer.render(&mut gpu, &camera, &settings, (96, 96)).unwrap();
        let times = renderer.renderer.pass_times(&renderer.ctx, &plan).unwrap().expect("timing is on");
        assert_eq!(times.len(), plan.steps.len(), "{plan}");
        assert!(times.iter().all(|t| t.is_finite() && *t >= 0.0), "{times:?}");
    }
}

#[test]
fn each_group_layer_pass_carries_its_own_layer_in_its_uniforms() {
    let cloud = model();
    let grouping = GroupingSpec::mgc(1.0).compute(&cloud).unwrap();
    let settings = RenderSettings { mode: "deferred".parse().unwrap(), ..Default::default() };
    let facts = pointblend::frame::SceneFacts { splats: cloud.len(), mean_radius: 0.001, ..Default::default() };
    let spec = pointblend::frame::resolve(&settings, &facts, &pointblend::frame::View::still((64, 64)));
    let frame = FrameDesc {
        settings: &spec.drawn,
        spec: &spec,
        width: 64,
        height: 64,
        splats: cloud.len(),
        groups: &grouping.ranges,
        transparent_groups: &grouping.ranges,
        opaque: 0..0,
        uniform_colour: None,
        epsilon: 0.001,
        depth_steps: 100.0,
        transparent: false,
        environment: None,
        sums: pointblend::render::targets::SumPrecision::F32,
        lights: false,
        triangles: 0,
    };
    let plan = pointblend::render::modes::plan(&frame).unwrap();
    let layers: Vec<u32> = plan
        .commands()
        .filter_map(|(_, c)| match c {
            Command::Splats(pass) => Some(pass.uniforms.layers[0]),
            Command::Fullscreen(_) | Command::Compute(_) => None,
        })
        .collect();
    assert_eq!(layers, (0..grouping.k() as u32).collect::<Vec<_>>());
    assert_eq!(plan.geometry_render_passes(), grouping.k());
}
