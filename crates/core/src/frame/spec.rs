//! A frame decided once: [`resolve`] turns the settings a front end asks
//! for, what the scene is ([`SceneFacts`]) and how it is looked at
//! ([`View`]) into a [`FrameSpec`] that says everything the frame will do.
//! Every front end (`render`, `view`, `bench`, `pick`, `measure`, camera
//! paths) resolves its frames here, and the renderer only carries the spec
//! out: it decides nothing again, and nothing patches the settings after.
//!
//! The decisions, each made in one place below:
//! - the mode that runs: the viewer's preview mode while the camera moves,
//!   and a transparent mode on an opaque scene runs the two-pass plan
//!   (Zhang & Pajarola's opaque 1+1 passes need no layers: the fallback);
//! - what is drawn ([`Selection`]): a hybrid frame's leaves and splats
//!   (Guennebaud §4's hybrid rules; not when lit, since Gunjee's translucent
//!   shadows are cast and received by splats, nor in a moving scene), the
//!   nodes under a point budget, a streamed file's selection, or every splat;
//! - the grouping drawn (Zhang & Pajarola §4): the mode's, or its per-frame
//!   hash grouping where the splats drawn change every frame;
//! - lights and shadows, eye-dome lighting, the environment, the low-pass
//!   radius (Guennebaud's EWA approximation) and which mean radius ε is a
//!   multiple of (Botsch & Kobbelt §3);
//! - typed notes ([`FrameNote`]) that `--explain`, the viewer and bench print.

use super::{EyeDome, RenderMode, RenderSettings};
use crate::grouping::hash::HashOptions;
use crate::grouping::{Extension, GroupingAlgo, GroupingSpec};

/// What a frame's decisions read from the scene.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SceneFacts {
    /// Splats of the whole scene (of the streamed selection, for a stream).
    pub splats: usize,
    /// Some splat is less than opaque.
    pub transparent: bool,
    /// The scene has mesh or hybrid objects (triangles it can draw).
    pub surfaces: bool,
    /// The scene moves (an animation or a sequence): its splats change every frame.
    pub moving: bool,
    /// The splats are a streamed file's selection, made under the budget already.
    pub streamed: bool,
    /// The mean splat radius of the whole scene, in world units.
    pub mean_radius: f32,
    /// Whether a lit frame's splats carry shadow coefficients: always for a
    /// scene the renderer prepares; for a bare upload, whether they were uploaded.
    pub shadows_at_hand: bool,
}

/// The viewer's preview while its camera moves: a faster mode, under a budget.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Preview {
    pub mode: RenderMode,
    pub budget: u32,
}

/// What a frame's decisions read from the view.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct View {
    pub size: (u32, u32),
    /// Set by the viewer while the camera moves (its own rule picks the mode).
    pub preview: Option<Preview>,
}

impl View {
    /// A still view of `size` (every front end but the viewer in motion).
    pub fn still(size: (u32, u32)) -> Self {
        Self { size, preview: None }
    }
}

/// Which splats a frame draws.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Selection {
    /// Every splat of the scene.
    Whole,
    /// At most this many, chosen from the multi-resolution hierarchy by screen-space error.
    Budget(u32),
    /// A hybrid object's leaves as triangles where splats would pass this
    /// radius in pixels, and the splats beside them.
    Hybrid(f32),
    /// A streamed file's selection, made under its budget before the frame.
    Streamed,
}

impl Selection {
    /// Whether the splats drawn are chosen per view (and so regrouped per frame).
    pub fn changes_with_view(self) -> bool {
        matches!(self, Selection::Budget(_) | Selection::Hybrid(_))
    }
}

/// The grouping a frame draws.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DrawnGrouping {
    pub spec: GroupingSpec,
    /// Redone every frame by hashing (a moving scene, or splats chosen per
    /// view), so nothing waits for it; else computed once (or cached).
    pub per_frame: bool,
}

/// Which mean splat radius ε is a multiple of.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EpsilonRadius {
    /// The splats drawn (a budget's or a stream's selection, or the whole scene).
    Drawn,
    /// The whole scene's, this many world units: a hybrid frame draws a part
    /// of it beside triangles, as a frame of every splat would.
    Scene(f32),
}

/// Why a frame draws the scene's meshes as their vertex splats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoTriangles {
    /// The mode cannot draw triangles.
    Mode(RenderMode),
    /// Lit by scene lights, whose shadows are cast and received by splats.
    Lit,
    /// The scene moves.
    Moving,
}

/// Why a frame's groups are redone every frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RegroupReason {
    Moving,
    Budget,
    Hybrid,
    /// A streamed file: each node is labelled once, when it arrives.
    Streamed,
}

/// What a frame's decisions say, for `--explain`, the viewer and bench rows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FrameNote {
    /// A transparent mode on a scene with nothing transparent runs the two-pass plan.
    OpaqueFallback(RenderMode),
    /// The viewer's camera moves: `preview` draws in place of `asked`.
    Preview {
        asked: RenderMode,
        preview: RenderMode,
        budget: u32,
    },
    MeshesAsSplats(NoTriangles),
    /// A point budget does not apply to a moving scene.
    BudgetInMotion,
    /// A frame with triangles draws every splat it chooses.
    BudgetBesideTriangles(u32),
    /// A grouping that cannot be redone every frame gives way to a hash grouping.
    PerFrameGrouping {
        asked: GroupingSpec,
        drawn: GroupingSpec,
        why: RegroupReason,
    },
}

impl FrameNote {
    /// Whether the note is worth a warning (once) besides the plan's notes.
    pub fn is_warning(&self) -> bool {
        matches!(self, FrameNote::MeshesAsSplats(_) | FrameNote::BudgetInMotion | FrameNote::PerFrameGrouping { .. })
    }
}

impl std::fmt::Display for FrameNote {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FrameNote::OpaqueFallback(mode) => write!(
                f,
                "nothing in the scene is transparent, so {mode} runs the opaque two-pass plan: no peeling pass, no layer target"
            ),
            FrameNote::Preview { asked, preview, budget } => {
                write!(f, "the camera moves: {preview} under a budget of {budget} splats previews {asked}")
            }
            FrameNote::MeshesAsSplats(why) => {
                match why {
                    NoTriangles::Mode(mode) => {
                        let drawing: Vec<&str> =
                            RenderMode::ALL.into_iter().filter(|m| m.info().triangles).map(RenderMode::name).collect();
                        write!(f, "{mode} cannot draw triangles ({} do)", drawing.join(", "))?
                    }
                    NoTriangles::Lit => {
                        f.write_str("the frame is lit by scene lights, whose shadows are cast and received by splats")?
                    }
                    NoTriangles::Moving => f.write_str("the scene moves (triangles are drawn in still scenes)")?,
                }
                f.write_str(": the scene's mesh and hybrid objects are drawn as their vertex splats")
            }
            FrameNote::BudgetInMotion => {
                f.write_str("the scene moves: every splat is drawn (a point budget applies to still scenes)")
            }
            FrameNote::BudgetBesideTriangles(budget) => {
                write!(f, "point budget {budget} not applied (a frame with triangles draws every splat it chooses)")
            }
            FrameNote::PerFrameGrouping { asked, drawn, why } => {
                let cannot = if *why == RegroupReason::Streamed { "made node by node" } else { "redone every frame" };
                let why = match why {
                    RegroupReason::Moving => "the scene moves",
                    RegroupReason::Budget => "under a point budget the splats drawn change with the view",
                    RegroupReason::Hybrid => "in a hybrid frame the splats drawn change with the view",
                    RegroupReason::Streamed => "a streamed file's nodes are grouped once each, when they arrive",
                };
                write!(f, "{why}: {asked} cannot be {cannot}, so {drawn} is drawn instead")
            }
        }
    }
}

/// Everything a frame will do, decided once by [`resolve`].
#[derive(Debug, Clone, PartialEq)]
pub struct FrameSpec {
    /// The settings as asked.
    pub asked: RenderSettings,
    /// The settings the passes read: the mode that runs (the preview's while
    /// the camera moves), and no point budget (the selection applied it).
    pub drawn: RenderSettings,
    pub size: (u32, u32),
    /// Whether the frame is ray cast on the CPU (the reference, or a frame
    /// with no splats, which is the background).
    pub on_cpu: bool,
    /// A transparent mode on an opaque scene: the two-pass plan runs.
    pub opaque_fallback: bool,
    pub selection: Selection,
    pub grouping: Option<DrawnGrouping>,
    /// Lit by scene lights with shadow coefficients (else the headlight of the shading).
    pub lights: bool,
    pub eye_dome: Option<EyeDome>,
    /// Whether the scene's environment map is drawn (reflection, refraction).
    pub environment: bool,
    /// The splat passes' low-pass radius in pixels (0: none).
    pub low_pass_px: f32,
    pub epsilon_radius: EpsilonRadius,
    pub notes: Vec<FrameNote>,
}

impl FrameSpec {
    /// The mode that runs (after the preview; its plan is two-pass under the opaque fallback).
    pub fn mode(&self) -> RenderMode {
        self.drawn.mode
    }

    /// Whether the scene's triangles are drawn (a hybrid selection).
    pub fn draws_triangles(&self) -> bool {
        matches!(self.selection, Selection::Hybrid(_))
    }

    /// The notes in words.
    pub fn note_lines(&self) -> Vec<String> {
        self.notes.iter().map(ToString::to_string).collect()
    }
}

/// The grouping a moving scene (or splats chosen per view) draws in place
/// of `spec`: the same hash grouping, or hash with K = 8 for MGC and WGC
/// (which cannot run every frame), with §4.4.2's radius estimate in place
/// of an extension.
pub fn per_frame_grouping(spec: GroupingSpec) -> GroupingSpec {
    let algo = match spec.algo {
        GroupingAlgo::Hash { .. } => spec.algo,
        _ => GroupingAlgo::Hash { k: 8, resolve_collisions: true },
    };
    let extension = match spec.extension {
        Extension::None => Extension::None,
        _ => Extension::Estimate,
    };
    GroupingSpec { algo, relax: Default::default(), extension }
}

/// The hash grouping [`per_frame_grouping`] draws for `spec`, as the
/// options a streamed file's nodes are labelled with when they arrive.
pub fn per_node_hash(spec: GroupingSpec) -> Option<HashOptions> {
    per_frame_grouping(spec).algo.hash_options()
}

/// Decides a frame of `asked` over a scene with `facts` in `view`.
pub fn resolve(asked: &RenderSettings, facts: &SceneFacts, view: &View) -> FrameSpec {
    let mut notes = Vec::new();
    let mut drawn = *asked;
    if let Some(preview) = view.preview {
        drawn.mode = preview.mode;
        drawn.point_budget = Some(preview.budget.min(asked.point_budget.unwrap_or(u32::MAX)));
        notes.push(FrameNote::Preview { asked: asked.mode, preview: preview.mode, budget: preview.budget });
    }
    let mode = drawn.mode;
    let on_cpu = !mode.is_gpu() || facts.splats == 0;
    let opaque_fallback = !on_cpu && mode.runs_opaque(facts.transparent);
    if opaque_fallback {
        notes.push(FrameNote::OpaqueFallback(mode));
    }
    let lit = drawn.lit_by_lights();
    let triangles = !on_cpu && facts.surfaces && {
        let refused = if !mode.info().triangles && !opaque_fallback {
            Some(NoTriangles::Mode(mode))
        } else if lit {
            Some(NoTriangles::Lit)
        } else if facts.moving {
            Some(NoTriangles::Moving)
        } else {
            None
        };
        notes.extend(refused.map(FrameNote::MeshesAsSplats));
        refused.is_none()
    };
    let selection = select(&drawn, facts, on_cpu, triangles, &mut notes);
    let grouping = (!on_cpu).then(|| drawn_grouping(&drawn, facts, selection, &mut notes)).flatten();
    let epsilon_radius = if triangles { EpsilonRadius::Scene(facts.mean_radius) } else { EpsilonRadius::Drawn };
    let spec_drawn = if on_cpu { drawn } else { drawn.without_budget() };
    FrameSpec {
        asked: *asked,
        drawn: spec_drawn,
        size: view.size,
        on_cpu,
        opaque_fallback,
        selection,
        grouping,
        lights: lit && (on_cpu || facts.shadows_at_hand),
        eye_dome: drawn.eye_dome_drawn(),
        environment: drawn.draws_environment(),
        low_pass_px: drawn.low_pass_radius_px(),
        epsilon_radius,
        notes,
    }
}

/// Which splats a frame of `drawn` draws.
fn select(
    drawn: &RenderSettings,
    facts: &SceneFacts,
    on_cpu: bool,
    triangles: bool,
    notes: &mut Vec<FrameNote>,
) -> Selection {
    if on_cpu {
        return Selection::Whole;
    }
    if triangles {
        notes.extend(drawn.point_budget.map(FrameNote::BudgetBesideTriangles));
        return Selection::Hybrid(drawn.hybrid_pixels);
    }
    if facts.streamed {
        return Selection::Streamed;
    }
    match drawn.point_budget {
        Some(_) if facts.moving => {
            notes.push(FrameNote::BudgetInMotion);
            Selection::Whole
        }
        Some(budget) if (budget as usize) < facts.splats => Selection::Budget(budget),
        _ => Selection::Whole,
    }
}

/// The grouping a GPU frame of `drawn` draws over `selection`, if its mode draws groups.
fn drawn_grouping(
    drawn: &RenderSettings,
    facts: &SceneFacts,
    selection: Selection,
    notes: &mut Vec<FrameNote>,
) -> Option<DrawnGrouping> {
    if !drawn.mode.needs_grouping_for(facts.transparent) {
        return None;
    }
    let asked = drawn.grouping_for_mode();
    let why = match selection {
        _ if facts.moving => RegroupReason::Moving,
        Selection::Budget(_) => RegroupReason::Budget,
        Selection::Hybrid(_) => RegroupReason::Hybrid,
        Selection::Streamed => RegroupReason::Streamed,
        _ => return Some(DrawnGrouping { spec: asked, per_frame: false }),
    };
    let spec = per_frame_grouping(asked);
    if spec != asked {
        notes.push(FrameNote::PerFrameGrouping { asked, drawn: spec, why });
    }
    Some(DrawnGrouping { spec, per_frame: true })
}

#[cfg(test)]
#[path = "spec_tests.rs"]
mod tests;
