//! The measuring stick: a scene rendered in its measuring view and compared with the truth,
//! with the truth kept for reuse while only the shadow settings change (the visible surfaces,
//! and so the truth, do not depend on them).

use super::truth::{Occluders, SizeOverride, Truth, truth_frame, truth_lights};
use crate::App;
use crate::components::{Camera, FlyCamera, Transform};
use crate::render::{DebugFrame, Gpu, HEADLESS_FORMAT, RenderError, Renderer, render_debug_frame};
use crate::settings::{Settings, SettingsError};
use bevy_ecs::prelude::*;
use glam::Vec3;
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
    renderer: Renderer,
}

/// Renders measuring views at one size and keeps each view's truth.
pub struct Measurer<'g> {
    gpu: &'g Gpu,
    /// Frame width and height in pixels.
    pub size: (u32, u32),
    /// How the truth is taken.
    pub truth: TruthSettings,
    subjects: HashMap<String, Subject>,
    cache: HashMap<String, (Vec<glam::Vec4>, TruthColumns)>,
}

impl<'g> Measurer<'g> {
    /// A measurer on `gpu` for frames of `size`.
    pub fn new(gpu: &'g Gpu, size: (u32, u32), truth: TruthSettings) -> Self {
        Measurer { gpu, size, truth, subjects: HashMap::new(), cache: HashMap::new() }
    }

    /// The GPU it renders on.
    pub fn gpu(&self) -> &'g Gpu {
        self.gpu
    }

    /// The scene called `name`, built by `build` the first time and given `settings` every time.
    pub fn subject(
        &mut self,
        name: &str,
        settings: &Settings,
        build: impl FnOnce(&Settings) -> Result<App, crate::AppError>,
    ) -> Result<&mut Subject, MeasureError> {
        settings.validate()?;
        if !self.subjects.contains_key(name) {
            let mut app = build(settings)?;
            app.resize(self.size.0, self.size.1);
            let renderer = Renderer::new(self.gpu, HEADLESS_FORMAT)?;
            self.subjects.insert(name.to_string(), Subject { app, renderer });
        }
        let subject = self.subjects.get_mut(name).expect("inserted above");
        apply_settings(&mut subject.app, settings);
        Ok(subject)
    }

    /// Renders the measuring view of subject `name` as its app is now, with the truth; `key`
    /// names the view (same key, same scene and camera: the truth is reused).
    pub fn measure(&mut self, name: &str, key: &str) -> Result<Measured, MeasureError> {
        let (w, h) = self.size;
        let subject = self.subjects.get_mut(name).expect("measure needs a subject");
        let frame = render_debug_frame(self.gpu, &mut subject.renderer, &mut subject.app, w, h)?;
        let key = format!("{name}/{key}");
        if let Some((positions, truth)) = self.cache.get(&key)
            && *positions == frame.position
        {
            return Ok(Measured { frame, truth: truth.clone() });
        }
        let t = self.truth;
        let world = &mut subject.app.world;
        let lights = truth_lights(world, t.sizes);
        let truth = std::rc::Rc::new(truth_frame(&frame, &Occluders::from_world(world), &lights, t.soft_rays));
        self.cache.insert(key, (frame.position.clone(), truth.clone()));
        Ok(Measured { frame, truth })
    }

    /// The renderer and app of subject `name`, for timing or probes.
    pub fn parts(&mut self, name: &str) -> Option<(&mut App, &mut Renderer)> {
        self.subjects.get_mut(name).map(|s| (&mut s.app, &mut s.renderer))
    }
}

/// Puts `settings` in force in `app` (lights without a bias or method of their own take the
/// settings').
pub fn apply_settings(app: &mut App, settings: &Settings) {
    if app.world.resource::<Settings>() != settings {
        *app.world.resource_mut::<Settings>() = settings.clone();
    }
}

/// Points the app's camera from `eye` at `target` (turning its fly camera to match, so the
/// update does not turn it back).
pub fn place_camera(world: &mut World, eye: Vec3, target: Vec3) {
    let (_, fly, transform) = crate::scene::camera_looking(eye, target);
    for (mut t, f) in world.query_filtered::<(&mut Transform, Option<&mut FlyCamera>), With<Camera>>().iter_mut(world) {
        *t = transform;
        if let Some(mut f) = f {
            (f.yaw, f.pitch) = (fly.yaw, fly.pitch);
        }
    }
}
