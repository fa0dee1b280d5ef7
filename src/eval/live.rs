//! The live measurement behind the window's error overlay: the measuring view of the frame on
//! screen is rendered on the frame loop (one extra GPU frame and a readback), and everything
//! slow — the BVH, the ray-traced truth, the metrics and the error picture — runs on a worker
//! thread. The frame loop never waits for it: it asks [`Worker::take`] each frame, and a result
//! whose view no longer matches the one on screen is dropped.

use super::measure::TruthSettings;
use super::metrics::{EDGE_RADIUS, LightReport, report};
use super::truth::{CasterTriangle, Occluders, Truth, caster_triangles, truth_frame, truth_lights};
use crate::App;
use crate::light::Emitter;
use crate::render::{DebugFrame, Gpu, RenderError, Renderer, render_debug_frame};
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::time::{Duration, Instant};

/// What the worker needs to measure one frame, taken from the world on the frame loop.
pub struct Snapshot {
    /// The measuring view as the renderer drew it.
    pub frame: DebugFrame,
    triangles: Vec<CasterTriangle>,
    lights: Vec<Emitter>,
    names: Vec<String>,
    soft_rays: usize,
}

/// One measured frame: each light's errors, and the error picture to lay over the view.
#[derive(Clone, Debug)]
pub struct LiveReport {
    /// Per light, in [`crate::light::light_list`] order: its name and its errors.
    pub lights: Vec<(String, LightReport)>,
    /// Width and height of the measured frame (and of `overlay`).
    pub size: (u32, u32),
    /// The error picture, RGBA with straight alpha, rows top to bottom (see [`error_colour`]).
    pub overlay: Vec<u8>,
    /// The measuring view it was taken from.
    pub frame: DebugFrame,
    /// The truth, one column per light.
    pub truth: Vec<Vec<Option<Truth>>>,
    /// How long the worker took.
    pub took: Duration,
}

impl LiveReport {
    /// Every light's errors together.
    #[must_use]
    pub fn all(&self) -> LightReport {
        let mut all = LightReport::default();
        for (_, r) in &self.lights {
            all.merge(r);
        }
        all
    }
}

/// Renders the measuring view of `app` as it is now at `size`, with `renderer`, and takes from
/// its world what the truth needs (its casters' triangles, its lights at `truth`'s sizes).
pub fn snapshot(
    gpu: &Gpu,
    renderer: &mut Renderer,
    app: &mut App,
    size: (u32, u32),
    truth: TruthSettings,
) -> Result<Snapshot, RenderError> {
    let frame = render_debug_frame(gpu, renderer, app, size.0, size.1)?;
    let world = &mut app.world;
    let names = crate::light::light_list(world).iter().map(|l| l.label.to_string()).collect();
    let lights = truth_lights(world, truth.sizes);
    Ok(Snapshot { frame, triangles: caster_triangles(world), lights, names, soft_rays: truth.soft_rays })
}

impl Snapshot {
    /// Casts the truth for every pixel and light and compares (the slow part: run it off the
    /// frame loop).
    #[must_use]
    pub fn measure(self) -> LiveReport {
        let started = Instant::now();
        let occluders = Occluders::with_cutouts(self.triangles);
        let truth = truth_frame(&self.frame, &occluders, &self.lights, self.soft_rays);
        let reports = report(&self.frame, &truth, EDGE_RADIUS);
        let overlay = error_picture(&self.frame, &truth);
        LiveReport {
            lights: self.names.into_iter().zip(reports).collect(),
            size: (self.frame.width, self.frame.height),
            overlay,
            frame: self.frame,
            truth,
            took: started.elapsed(),
        }
    }
}

/// How a pixel's error is shown: `rendered` visibility against the truth there. A pixel on the
/// wrong side of [`super::metrics::DARK`] from the hard truth is marked at full opacity, red for
/// a false shadow (acne, over-darkening) and blue for a false lit (leaks, peter-panning); any
/// other pixel off the soft truth is marked fainter, at most [`FAINT`] of that, red when darker
/// and blue when lighter, the more wrong the more opaque. Right pixels are clear.
#[must_use]
pub fn error_colour(rendered: f32, truth: Truth) -> [u8; 4] {
    // Not a number counts as lit, as the tally counts it.
    let rendered = if rendered.is_nan() { 1.0 } else { rendered.clamp(0.0, 1.0) };
    let error = rendered - truth.soft;
    let wrong_side = (rendered < super::metrics::DARK) == truth.lit;
    let strength = if wrong_side { 1.0 } else { FAINT * (error.abs() * 2.0).min(1.0) };
    let alpha = (strength * OVERLAY_OPACITY * 255.0).round() as u8;
    let too_dark = if wrong_side { truth.lit } else { error < 0.0 };
    match (alpha, too_dark) {
        (0, _) => [0; 4],
        (a, true) => [255, 40, 30, a],
        (a, false) => [40, 90, 255, a],
    }
}

/// The most opaque an overlay pixel gets, so the picture still shows through.
pub const OVERLAY_OPACITY: f32 = 0.85;

/// The share of full opacity the most off-truth pixel on the right side gets, so a full mark
/// always means a wrong pixel.
pub const FAINT: f32 = 0.6;

/// The error picture of a measured frame: at each pixel, the colour of the light most wrong
/// there (see [`error_colour`]).
#[must_use]
pub fn error_picture(frame: &DebugFrame, truth: &[Vec<Option<Truth>>]) -> Vec<u8> {
    let pixels = (frame.width * frame.height) as usize;
    let mut out = vec![0u8; pixels * 4];
    for (i, rgba) in out.chunks_exact_mut(4).enumerate() {
        let worst = truth
            .iter()
            .enumerate()
            .filter_map(|(light, column)| {
                let t = (*column.get(i)?)?;
                Some(error_colour(super::metrics::rendered(frame, light, i)?, t))
            })
            .max_by_key(|c| c[3]);
        rgba.copy_from_slice(&worst.unwrap_or([0; 4]));
    }
    out
}

/// Measurements in flight on worker threads, each tagged with the view it was taken of.
pub struct Worker<Tag> {
    in_flight: Option<(Tag, Instant, Receiver<LiveReport>)>,
}

impl<Tag> Default for Worker<Tag> {
    fn default() -> Self {
        Worker { in_flight: None }
    }
}

/// What a [`Worker`] has for the frame loop.
pub enum Taken<Tag> {
    /// Nothing asked, or nothing back yet.
    Nothing,
    /// A measurement of the view tagged so.
    Done(Tag, LiveReport),
    /// The worker thread died without a result (a bug; said, not hidden).
    Failed(String),
}

impl<Tag: Send + 'static> Worker<Tag> {
    /// True while a measurement is on its way.
    #[must_use]
    pub fn busy(&self) -> bool {
        self.in_flight.is_some()
    }

    /// How long the measurement on its way has been running.
    #[must_use]
    pub fn running_for(&self) -> Option<Duration> {
        self.in_flight.as_ref().map(|(_, since, _)| since.elapsed())
    }

    /// Starts measuring `snapshot` on a thread of its own; one on its way already is forgotten.
    pub fn start(&mut self, tag: Tag, snapshot: Snapshot) {
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let _ = tx.send(snapshot.measure());
        });
        self.in_flight = Some((tag, Instant::now(), rx));
    }

    /// The finished measurement, if one has come back; never waits.
    pub fn take(&mut self) -> Taken<Tag> {
        let Some((_, _, rx)) = &self.in_flight else { return Taken::Nothing };
        match rx.try_recv() {
            Err(TryRecvError::Empty) => Taken::Nothing,
            Ok(report) => self.in_flight.take().map_or(Taken::Nothing, |(tag, _, _)| Taken::Done(tag, report)),
            Err(TryRecvError::Disconnected) => {
                self.in_flight = None;
                Taken::Failed("the measuring thread stopped without a result".into())
            }
        }
    }

    /// Waits for the measurement on its way (for tests and headless use).
    pub fn wait(&mut self) -> Taken<Tag> {
        let Some((tag, _, rx)) = self.in_flight.take() else { return Taken::Nothing };
        match rx.recv() {
            Ok(report) => Taken::Done(tag, report),
            Err(_) => Taken::Failed("the measuring thread stopped without a result".into()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    #[test]
    fn wrong_sides_are_marked_fully_and_right_pixels_are_clear() {
        let lit = Truth { lit: true, soft: 1.0 };
        let dark = Truth { lit: false, soft: 0.0 };
        let full = (OVERLAY_OPACITY * 255.0).round() as u8;
        assert_eq!(error_colour(0.0, lit), [255, 40, 30, full], "acne: red");
        assert_eq!(error_colour(1.0, dark), [40, 90, 255, full], "a leak: blue");
        assert_eq!(error_colour(1.0, lit)[3], 0);
        assert_eq!(error_colour(0.0, dark)[3], 0);
        // In a penumbra: a little too dark is a faint red, as strong as it is wrong.
        let half = Truth { lit: true, soft: 0.7 };
        let c = error_colour(0.6, half);
        assert_eq!(c[..3], [255, 40, 30]);
        assert!(c[3] > 0 && c[3] < full / 2, "{c:?}");
        assert_eq!(error_colour(f32::NAN, lit)[3], 0, "NaN counts as lit, as the tally counts it");
        assert_eq!(error_colour(f32::NAN, dark), [40, 90, 255, full]);
    }

    #[test]
    fn the_picture_shows_the_worst_light_and_nothing_where_nothing_was_tested() {
        let frame = DebugFrame {
            width: 3,
            height: 1,
            position: vec![Vec4::W, Vec4::W, Vec4::ZERO],
            normal: vec![Vec4::Y; 3],
            // Pixel 0: light 0 right, light 1 acne. Pixel 1: light 0 untested, light 1 a leak.
            visibility: vec![vec![1.0, -1.0, 0.0], vec![0.0, 1.0, 0.0]],
        };
        let lit = Some(Truth { lit: true, soft: 1.0 });
        let dark = Some(Truth { lit: false, soft: 0.0 });
        let truth = vec![vec![lit, lit, lit], vec![lit, dark, lit]];
        let p = error_picture(&frame, &truth);
        assert_eq!(p[0..3], [255, 40, 30], "the acne of light 1 wins over light 0's right answer");
        assert_eq!(p[4..7], [40, 90, 255]);
        assert_eq!(p[8..12], [0; 4], "the sky is clear");
    }
}
