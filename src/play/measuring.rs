//! The window's error overlay: when asked (or when the view has been still a while), the frame on
//! screen is measured against the ray-traced truth on a worker thread; the result is shown only
//! while the view is still the one measured.

use crate::App;
use crate::components::{Camera, Time, Transform, Viewport};
use crate::eval::live::{LiveReport, Taken, Worker, snapshot};
use crate::eval::measure::TruthSettings;
use crate::light::{Light, light_list};
use crate::render::{Gpu, RenderError, Renderer};
use crate::settings::{CascadeSettings, MapSettings, ShadowSettings, ViewSettings};
use crate::ui::Lab;
use crate::ui::panel::STILL_FOR;
use bevy_ecs::prelude::*;
use std::time::Instant;

/// Everything that decides what a measurement shows: the camera, the scene's time, the frame's
/// size, the settings and the lights. Two frames with the same stamp are the same picture.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewStamp {
    camera: Option<Transform>,
    frame: u64,
    size: Viewport,
    shadow: ShadowSettings,
    maps: MapSettings,
    cascade: CascadeSettings,
    view: ViewSettings,
    lights: Vec<Light>,
}

/// The stamp of `world` as it is now.
pub fn stamp(world: &mut World) -> ViewStamp {
    let camera = world.query_filtered::<&Transform, With<Camera>>().iter(world).next().copied();
    ViewStamp {
        camera,
        frame: world.resource::<Time>().frame,
        size: *world.resource::<Viewport>(),
        shadow: *world.resource::<ShadowSettings>(),
        maps: *world.resource::<MapSettings>(),
        cascade: *world.resource::<CascadeSettings>(),
        view: world.resource::<ViewSettings>().clone(),
        // Without their layers: a layer's version and dirty flag change with no change to the
        // picture.
        lights: light_list(world).into_iter().map(|l| Light { layers: Vec::new(), ..l }).collect(),
    }
}

/// The overlay's state between frames.
pub struct Measuring {
    worker: Worker<ViewStamp>,
    /// The measurement shown, with the view it is of and its picture for egui.
    shown: Option<(ViewStamp, LiveReport, egui::TextureHandle)>,
    /// What is going on, in a few words, for the panel.
    pub status: String,
    /// The view as it was last frame, and since when it has been so.
    still: Option<(ViewStamp, Instant)>,
    /// The truth's settings: the bench's, so the numbers match its.
    truth: TruthSettings,
}

impl Default for Measuring {
    fn default() -> Self {
        Measuring {
            worker: Worker::default(),
            shown: None,
            status: "nothing measured yet: M measures the view".into(),
            still: None,
            truth: TruthSettings::default(),
        }
    }
}

impl Measuring {
    /// The measurement shown now and its picture, if any.
    pub fn shown(&self) -> Option<(&LiveReport, &egui::TextureHandle)> {
        self.shown.as_ref().map(|(_, r, t)| (r, t))
    }

    /// Once a frame, before drawing: takes a finished measurement (dropping it if the view has
    /// changed since), hides one the view no longer matches, and tracks how long the view has
    /// been still.
    pub fn update(&mut self, world: &mut World, ctx: &egui::Context) {
        let now = stamp(world);
        match self.worker.take() {
            Taken::Nothing => {}
            Taken::Failed(why) => self.status = why,
            Taken::Done(tag, report) if tag == now => {
                self.status = format!(
                    "measured {}x{} in {:.1} s (truth from {} rays a light a pixel)",
                    report.size.0,
                    report.size.1,
                    report.took.as_secs_f32(),
                    self.truth.soft_rays + 1
                );
                let size = [report.size.0 as usize, report.size.1 as usize];
                let image = egui::ColorImage::from_rgba_unmultiplied(size, &report.overlay);
                let texture = ctx.load_texture("error overlay", image, egui::TextureOptions::NEAREST);
                self.shown = Some((tag, report, texture));
            }
            Taken::Done(..) => self.status = "dropped a measurement: the view changed while it ran".into(),
        }
        if self.shown.as_ref().is_some_and(|(tag, _, _)| *tag != now) {
            self.shown = None;
            self.status = "the view changed: M measures it again".into();
        }
        if let Some(t) = self.worker.running_for() {
            self.status = format!("measuring… {:.1} s", t.as_secs_f32());
        }
        match &self.still {
            Some((last, _)) if *last == now => {}
            _ => self.still = Some((now, Instant::now())),
        }
    }

    /// True when the lab asks for a measurement now: asked outright, or measuring when still
    /// and the view has been still long enough and is not measured or being measured.
    pub fn wanted(&self, lab: &Lab) -> bool {
        if lab.asked.measure {
            return true;
        }
        let still_long = self.still.as_ref().is_some_and(|(_, since)| since.elapsed().as_secs_f32() >= STILL_FOR);
        let measured = self.shown.as_ref().zip(self.still.as_ref()).is_some_and(|((a, _, _), (b, _))| a == b);
        lab.auto_measure && still_long && !measured && !self.worker.busy()
    }

    /// Renders the measuring view of `app` as it is now, at the window's size divided by
    /// `scale`, and hands it to the worker.
    pub fn start(&mut self, gpu: &Gpu, renderer: &mut Renderer, app: &mut App, scale: u32) -> Result<(), RenderError> {
        let window = *app.world.resource::<Viewport>();
        let scale = scale.clamp(1, 8);
        let size = ((window.width / scale).max(1), (window.height / scale).max(1));
        let tag = stamp(&mut app.world);
        let shot = snapshot(gpu, renderer, app, size, self.truth)?;
        self.worker.start(tag, shot);
        self.status = "measuring…".into();
        Ok(())
    }
}
