//! The measuring stick: a scene rendered in its measuring view and compared with the truth,
//! with the truth kept for reuse while only the shadow settings change (the visible surfaces,
//! and so the truth, do not depend on them).

use super::truth::{SizeOverride, Truth, truth_of};
use crate::App;
use crate::render::{
    DebugFrame, Gpu, HEADLESS_FORMAT, RenderError, Renderer, render_debug_frame, render_debug_frame_as_is,
};
use crate::settings::{Settings, SettingsError};
use std::collections::HashMap;

/// How the truth is taken.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TruthSettings {
    /// Light sizes for the soft truth that replace the lights' own, where given.
    pub sizes: SizeOverride,
    /// Rays over each light's disc for the soft truth.
    pub soft_rays: usize,
}

impl Default for TruthSettings {
    fn default() -> Self {
        TruthSettings { sizes: SizeOverride::default(), soft_rays: 32 }
    }
}

/// Why a measurement could not be made.
#[derive(Debug, thiserror::Error)]
pub enum MeasureError {
    /// Rendering failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// A setting is out of range.
    #[error(transparent)]
    Settings(#[from] SettingsError),
    /// The scene could not be set up.
    #[error(transparent)]
    App(#[from] crate::AppError),
    /// The sweep was asked for what it does not have (a family no configuration is of).
    #[error("{0}")]
    Sweep(String),
    /// A scene was asked for before it was set up (a bug in the harness, reported, not a panic).
    #[error("the measurer holds no scene {0:?}: it must be set up with `subject` first")]
    NoSubject(SubjectId),
}

/// Which scene a measurer holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SubjectId {
    /// The measured scene (the sample's or a file's) as the sweep measures it.
    Accuracy,
    /// The measured scene as `tune` measures it.
    Tune,
    /// The sample scene timed with maps of this kind.
    Timing(TimedMaps),
    /// The scene of a failure case.
    Case(CaseScene),
}

/// What a timed scene's shadow maps are made of: the configurations that share it share one
/// scene, so switching between them in the interleaved rounds never makes the maps anew. (When
/// the depth format or the colour maps changed between configurations, they were made anew in
/// every round, and on a software rasterizer the first frame to touch fresh memory pays its page
/// faults: d16 maps timed 1.6 times d32 ones, and the d32 configuration after them 2.5 times.)
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TimedMaps {
    /// Texels a side.
    pub size: u32,
    /// The depth maps' format.
    pub depth: crate::settings::ShadowDepth,
    /// The method, bits and source of the colour maps beside them, for a method that has them.
    pub colour: Option<(crate::components::ShadowMethod, crate::settings::MomentBits, crate::settings::MomentSource)>,
    /// How moments from depth are made.
    pub moment_resolve: crate::settings::MomentResolve,
}

/// The failure cases' scenes (see [`super::cases`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CaseScene {
    /// An open plane.
    Acne,
    /// A cube on the ground.
    PeterPanning,
    /// A ground with boxes, watched through probes.
    Shimmer,
    /// Five 2 cm poles.
    ThinCasters,
    /// A pillar behind the camera.
    OffScreenCaster,
    /// Boxes under a sun along each axis.
    DegenerateLights,
    /// Pillars out to 100 m.
    FarField,
    /// The character posed far from its bind pose.
    SkinnedCaster,
    /// The same with bounds from the bind pose (the defence taken away).
    SkinnedCasterBindBounds,
    /// Boxes round a point light.
    CubeSeams,
    /// Boxes in the outer ring of a 170° spot.
    WideSpot,
    /// An open plane under a low sun, sampled by PCF 5x5.
    SoftAcne,
    /// A tall pole under a 10 cm spot, sampled by PCSS.
    ContactHardening,
    /// Two stacked plates under the sun, sampled by VSM.
    LightBleeding,
    /// A plate's shadow over the end of a ledge, the ground far below.
    LedgeBleeding,
    /// Walls at 1 m to 32 m from a spot.
    Precision,
    /// A hard-edged spot over an open ground, probed at the edge of its tile.
    AtlasSeams,
    /// A spot over posts, seen from higher and higher.
    TileShrink,
    /// The same, seen from a camera creeping up and down.
    TileResize,
    /// A thin bar near the camera over a far ground, with contact shadows.
    ContactHalos,
    /// A cube whose foot a depth bias lifts the map's shadow from, seen whole and cut by the
    /// screen's edge, with contact shadows.
    ContactEdge,
    /// Three spots over sliding posts sharing a starved update budget.
    StarvedBudget,
    /// An open ground under the sun, probed either side of its virtual pages' borders.
    PageSeams,
    /// Two groups of pillars far apart, the camera cut from one to the other.
    CameraCut,
    /// A box sliding across the ground under the sun.
    MovingCaster,
    /// Poles over a wide ground, seen through a virtual-page pool of 1 MiB.
    PoolTooSmall,
    /// Posts seen by a camera creeping to and fro across a virtual level's boundary.
    LevelCreep,
}

/// The truth of a frame: one column per light in the frame's order (sun, then spots), one entry
/// per pixel; shared between the measurements of one view.
pub type TruthColumns = std::rc::Rc<Vec<Vec<Option<Truth>>>>;

/// A measured frame: what the renderer drew and what the truth says, per light.
pub struct Measured {
    /// The measuring view.
    pub frame: DebugFrame,
    /// What the truth says of each pixel, per light.
    pub truth: TruthColumns,
}

/// A scene being measured: its app and a renderer of its own (a renderer holds the meshes of
/// one app).
pub struct Subject {
    /// The scene.
    pub app: App,
    /// Its renderer.
    pub renderer: Renderer,
}

/// Renders measuring views at one size and keeps each view's truth.
pub struct Measurer<'g> {
    gpu: &'g Gpu,
    /// Frame width and height in pixels.
    pub size: (u32, u32),
    /// How the truth is taken.
    pub truth: TruthSettings,
    subjects: HashMap<SubjectId, Subject>,
    cache: HashMap<(SubjectId, String), (Vec<glam::Vec4>, TruthColumns)>,
    /// The failure case set up last: its atlas is freed when another scene is set up. With
    /// every case's atlas held, `bench --quick` peaked at 16.4 GB resident on lavapipe; with
    /// only the one being drawn, 5.7 GB, and the same results to the last digit.
    last_case: Option<SubjectId>,
}

impl<'g> Measurer<'g> {
    /// A measurer on `gpu` for frames of `size`.
    pub fn new(gpu: &'g Gpu, size: (u32, u32), truth: TruthSettings) -> Self {
        Measurer { gpu, size, truth, subjects: HashMap::new(), cache: HashMap::new(), last_case: None }
    }

    /// The GPU it renders on.
    pub fn gpu(&self) -> &'g Gpu {
        self.gpu
    }

    /// The scene `id`, built by `build` the first time and given `settings` every time.
    pub fn subject(
        &mut self,
        id: SubjectId,
        settings: &Settings,
        build: impl FnOnce(&Settings) -> Result<App, crate::AppError>,
    ) -> Result<&mut Subject, MeasureError> {
        settings.validate()?;
        if let Some(last) = self.last_case.filter(|&last| last != id)
            && let Some(s) = self.subjects.get_mut(&last)
        {
            s.renderer.release_shadow_maps(self.gpu);
        }
        self.last_case = matches!(id, SubjectId::Case(_)).then_some(id);
        let subject = match self.subjects.entry(id) {
            std::collections::hash_map::Entry::Occupied(e) => e.into_mut(),
            std::collections::hash_map::Entry::Vacant(e) => {
                let mut app = build(settings)?;
                app.resize(self.size.0, self.size.1);
                let mut renderer = Renderer::new(self.gpu, HEADLESS_FORMAT)?;
                app.hear(renderer.news());
                e.insert(Subject { app, renderer })
            }
        };
        subject.app.set_settings(settings)?;
        Ok(subject)
    }

    /// Renders the measuring view of scene `id` as its app is now, with the truth; `key` names
    /// the view (same key, same scene and camera: the truth is reused).
    pub fn measure(&mut self, id: SubjectId, key: &str) -> Result<Measured, MeasureError> {
        self.measure_drawn(id, key, true)
    }

    /// [`Measurer::measure`] of the frame as a window would draw it next: nothing drawn first
    /// (no SDSM fit or virtual page made ready for it; see [`render_debug_frame_as_is`]).
    pub fn measure_as_is(&mut self, id: SubjectId, key: &str) -> Result<Measured, MeasureError> {
        self.measure_drawn(id, key, false)
    }

    fn measure_drawn(&mut self, id: SubjectId, key: &str, primed: bool) -> Result<Measured, MeasureError> {
        let (w, h) = self.size;
        let subject = self.subjects.get_mut(&id).ok_or(MeasureError::NoSubject(id))?;
        let (gpu, renderer, app) = (self.gpu, &mut subject.renderer, &mut subject.app);
        let frame = if primed {
            render_debug_frame(gpu, renderer, app, w, h)?
        } else {
            render_debug_frame_as_is(gpu, renderer, app, w, h)?
        };
        let key = (id, key.to_string());
        if let Some((positions, truth)) = self.cache.get(&key)
            && *positions == frame.position
        {
            return Ok(Measured { frame, truth: truth.clone() });
        }
        let t = self.truth;
        let world = &mut subject.app.world;
        let truth = std::rc::Rc::new(truth_of(world, &frame, t.sizes, t.soft_rays));
        self.cache.insert(key, (frame.position.clone(), truth.clone()));
        Ok(Measured { frame, truth })
    }

    /// The app and renderer of scene `id`, for timing or probes.
    pub fn parts(&mut self, id: SubjectId) -> Result<(&mut App, &mut Renderer), MeasureError> {
        self.subjects.get_mut(&id).map(|s| (&mut s.app, &mut s.renderer)).ok_or(MeasureError::NoSubject(id))
    }
}

pub use crate::scene::place_camera;
