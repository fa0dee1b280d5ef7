//! `umbra tune`: for each light, the constant, slope and normal bias, the multiplicative offset
//! and the receiver plane (on or off) that give the fewest wrong pixels (false shadow + false
//! lit) over the scene's views (the sample's four, or a scene file's camera): a coarse grid of
//! the three texel biases together, then coordinate descent from the best of it over finer
//! values of all five.
//!
//! Lights do not change each other's shadows, so every candidate is tried on all lights in one
//! render and each light keeps what suits it. Every light of any kind is tuned, with the method
//! it is sampled with.
//!
//! With four views or more (the sample scene), the biases are tuned on the first half of them and
//! also reported on the other half, views the search never saw: the gain there is the one to
//! expect elsewhere.

use super::measure::{MeasureError, Measurer, SubjectId, TruthSettings, place_camera};
use super::metrics::{Tally, tally};
use super::sweep_options::{View, views};
use crate::App;
use crate::biases::LightBiases;
use crate::components::ShadowBias;
use crate::render::Gpu;
use crate::settings::Settings;

/// Bias values tried for each parameter, in texels.
pub const CANDIDATES: [f32; 9] = [0.0, 0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0];

/// Multiplicative offsets tried (shares of the distance to the light).
pub const SCALE_CANDIDATES: [f32; 7] = [0.0, 0.001, 0.002, 0.005, 0.01, 0.02, 0.05];

/// Values of the coarse grid, tried for all three parameters together.
pub const COARSE: [f32; 4] = [0.0, 0.5, 1.0, 2.0];

/// Rounds of coordinate descent over the five parameters.
const ROUNDS: usize = 2;

/// What tuning did for one light.
#[derive(Clone, Debug, PartialEq)]
pub struct LightTune {
    /// Its name: "sun", "spot 1", "point 1", ...
    pub light: String,
    /// Its errors with the biases it started with.
    pub before: Tally,
    /// Its errors with the biases found.
    pub after: Tally,
    /// The biases found.
    pub bias: ShadowBias,
    /// Its errors before and after on the views held out of the search (none with fewer than
    /// four views).
    pub held_out: Option<(Tally, Tally)>,
}

impl LightTune {
    /// Wrong pixels (false shadow + false lit) before and after.
    pub fn wrong(&self) -> (u64, u64) {
        (wrong(&self.before), wrong(&self.after))
    }
}

/// Every light's errors over `views` with `biases`.
fn errors(m: &mut Measurer<'_>, views: &[View], biases: &LightBiases) -> Result<Vec<Tally>, MeasureError> {
    let mut total: Vec<Tally> = Vec::new();
    for v in views {
        let (app, _) = m.parts(SubjectId::Tune)?;
        biases.apply(&mut app.world);
        place_camera(&mut app.world, v.eye, v.target);
        app.set_time(v.time);
        let measured = m.measure(SubjectId::Tune, v.name)?;
        total.resize(measured.truth.len().max(total.len()), Tally::default());
        for (light, t) in total.iter_mut().enumerate() {
            t.merge(&tally(&measured.frame, &measured.truth[light], light, |_| true));
        }
    }
    Ok(total)
}

fn wrong(t: &Tally) -> u64 {
    t.false_shadow + t.false_lit
}

/// The parameters searched: constant, slope, normal, scale, receiver plane.
const PARAMETERS: usize = 5;

/// The values tried for parameter `param` (the receiver plane's: on, off).
fn candidates(param: usize) -> &'static [f32] {
    match param {
        3 => &SCALE_CANDIDATES,
        4 => &[1.0, 0.0],
        _ => &CANDIDATES,
    }
}

fn set(b: &mut ShadowBias, param: usize, v: f32) {
    match param {
        4 => b.receiver_plane = v > 0.5,
        _ => *[&mut b.constant, &mut b.slope, &mut b.normal, &mut b.scale][param] = v,
    }
}

/// Renders every light with `candidate(its bias)`; each light whose error goes down (or stays,
/// with less bias in all: less loosening where the views do not look) takes it. Light `i` of
/// `current` is column `i` of the measurements.
fn try_candidate(
    m: &mut Measurer<'_>,
    views: &[View],
    current: &mut LightBiases,
    best: &mut [Tally],
    candidate: impl Fn(&ShadowBias) -> ShadowBias,
) -> Result<(), MeasureError> {
    let mut trial = current.clone();
    for (_, b) in &mut trial.0 {
        *b = candidate(b);
    }
    let errs = errors(m, views, &trial)?;
    // A share of 0.01 of the distance counts as much as a texel.
    let sum = |b: &ShadowBias| b.constant + b.slope + b.normal + 100.0 * b.scale;
    for (column, ((_, b), (_, t))) in current.0.iter_mut().zip(&trial.0).enumerate() {
        let (Some(&e), Some(kept)) = (errs.get(column), best.get_mut(column)) else { continue };
        if wrong(&e) < wrong(kept) || (wrong(&e) == wrong(kept) && sum(t) < sum(b)) {
            *b = *t;
            *kept = e;
        }
    }
    Ok(())
}

/// Tunes the biases of `base`'s scene (the sample's or a file's) with frames of `size`; `progress` hears
/// each step (done, of). Returns each light's result and the biases to save.
pub fn tune(
    gpu: &Gpu,
    base: &Settings,
    size: (u32, u32),
    mut progress: impl FnMut(usize, usize),
) -> Result<(Vec<LightTune>, LightBiases), MeasureError> {
    let mut m = Measurer::new(gpu, size, TruthSettings { soft_rays: 0, ..TruthSettings::default() });
    let (all_views, mut current) = {
        let subject = m.subject(SubjectId::Tune, base, |s| App::new(s.clone()))?;
        (views(&mut subject.app), LightBiases::of(&mut subject.app.world))
    };
    let (views, held): (&[View], &[View]) =
        if all_views.len() >= 4 { all_views.split_at(all_views.len() / 2) } else { (&all_views, &[]) };
    let initial = current.clone();
    let before = errors(&mut m, views, &current)?;
    let mut best = before.clone();
    let grid: Vec<[f32; 3]> =
        COARSE.iter().flat_map(|&c| COARSE.iter().flat_map(move |&s| COARSE.iter().map(move |&n| [c, s, n]))).collect();
    let steps = grid.len() + ROUNDS * (0..PARAMETERS).map(|p| candidates(p).len()).sum::<usize>();
    let mut done = 0;
    for &[constant, slope, normal] in &grid {
        progress(done, steps);
        done += 1;
        // The grid sets the texel biases; the offset and the receiver plane stay each light's.
        try_candidate(&mut m, views, &mut current, &mut best, |b| ShadowBias { constant, slope, normal, ..*b })?;
    }
    for _ in 0..ROUNDS {
        for param in 0..PARAMETERS {
            for &v in candidates(param) {
                progress(done, steps);
                done += 1;
                try_candidate(&mut m, views, &mut current, &mut best, |b| {
                    let mut b = *b;
                    set(&mut b, param, v);
                    b
                })?;
            }
        }
    }
    progress(steps, steps);
    let after = errors(&mut m, views, &current)?;
    let held_out =
        if held.is_empty() { None } else { Some((errors(&mut m, held, &initial)?, errors(&mut m, held, &current)?)) };
    let tunes = current
        .0
        .iter()
        .enumerate()
        .zip(before.iter().zip(&after))
        .map(|((i, (light, bias)), (&before, &after))| LightTune {
            light: light.clone(),
            before,
            after,
            bias: *bias,
            held_out: held_out.as_ref().and_then(|(b, a)| Some((*b.get(i)?, *a.get(i)?))),
        })
        .collect();
    Ok((tunes, current))
}
