//! The sweep behind `umbra bench`: every configuration's shadow cost and its accuracy on the
//! sample scene and in each failure case, measured in one run.

use super::cases::{CASES, Score};
use super::config::{Config, distinct_as_run};
use super::cost::{Cost, time_all};
use super::measure::{MeasureError, Measurer, SubjectId, TruthSettings, place_camera};
use super::metrics::{LightReport, report};
use super::sweep_options::{SweepOptions, View};
use crate::App;
use crate::render::Gpu;
use crate::settings::Settings;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// One configuration's results.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// The configuration.
    pub config: Config,
    /// Its cost on the measured scene (the sample's or a file's).
    pub cost: Cost,
    /// Its accuracy on the measured scene, per light, all views together.
    pub scene: Vec<LightReport>,
    /// The measured scene's lights' names, in the order of `scene`.
    pub lights: Vec<String>,
    /// Its score in each failure case, in [`CASES`] order; none where the sweep left the case out
    /// ([`SweepOptions::cases`]).
    pub cases: Vec<Option<Score>>,
}

impl Row {
    /// All lights of the sample scene together.
    pub fn scene_all(&self) -> LightReport {
        let mut all = LightReport::default();
        for r in &self.scene {
            all.merge(r);
        }
        all
    }
}

/// Accuracy of `settings` on its scene, per light, over `views`, with the lights' names.
pub fn scene_accuracy(
    m: &mut Measurer<'_>,
    settings: &Settings,
    views: &[View],
) -> Result<(Vec<LightReport>, Vec<String>), MeasureError> {
    let app = &mut m.subject(SubjectId::Accuracy, settings, |s| App::new(s.clone()))?.app;
    let names = crate::light::light_list(&app.world).iter().map(|l| l.label.to_string()).collect();
    let mut total: Vec<LightReport> = Vec::new();
    for v in views {
        let (app, _) = m.parts(SubjectId::Accuracy)?;
        place_camera(&mut app.world, v.eye, v.target);
        app.set_time(v.time);
        let measured = m.measure(SubjectId::Accuracy, v.name)?;
        let mut reports = report(&measured.frame, &measured.truth, super::metrics::EDGE_RADIUS);
        let (app, _) = m.parts(SubjectId::Accuracy)?;
        add_density(&mut reports, &measured.frame, app);
        total.resize(reports.len().max(total.len()), LightReport::default());
        for (t, r) in total.iter_mut().zip(&reports) {
            t.merge(r);
        }
    }
    Ok((total, names))
}

/// Counts each light's texels per pixel of `frame` (the measuring view of `app` as it is now)
/// into its report.
fn add_density(reports: &mut [LightReport], frame: &crate::render::DebugFrame, app: &mut App) {
    let Some(eye) = super::texels::Eye::of(&mut app.world, frame.height) else { return };
    for (column, (light, r)) in crate::light::light_list(&app.world).iter().zip(reports.iter_mut()).enumerate() {
        r.texels.merge(&super::texels::density(frame, column, light, eye));
    }
}

/// What [`run`] tells its progress while it times the configurations (then it names the one
/// being measured).
pub const TIMING: &str = "timing every configuration";

/// The configurations of `options` the sweep measures on `gpu`: those it supports, each that
/// runs as an earlier one does left out.
pub fn configs_on(gpu: &Gpu, options: &SweepOptions) -> Result<Vec<Config>, MeasureError> {
    let full_floats = gpu.full_float_moments();
    let configs = options.configs().map_err(MeasureError::Sweep)?;
    let counts = crate::render::sample_counts(&gpu.adapter, gpu.device.features());
    let supported = configs.into_iter().filter(|c| c.supported(full_floats, counts)).collect();
    Ok(distinct_as_run(supported, gpu.software()))
}

/// Runs the sweep on `gpu`: first every configuration's cost, timed in interleaved rounds, then
/// each one's accuracy (`options.workers` configurations at once); `progress` hears each step
/// as it starts (done, of, what).
pub fn run(
    gpu: &Gpu,
    options: &SweepOptions,
    mut progress: impl FnMut(usize, usize, &str) + Send,
) -> Result<Vec<Row>, MeasureError> {
    let base = &options.base;
    base.validate()?;
    let configs = configs_on(gpu, options)?;
    let rounds = (options.frames as usize + 2) * options.views.len();
    let steps = rounds + configs.len();
    let costs = time_all(gpu, base, &configs, options, |round| progress(round, steps, TIMING))?;
    let timed: Vec<(Config, Cost)> = configs.into_iter().zip(costs).collect();
    let progress = Mutex::new(progress);
    let begun = AtomicUsize::new(rounds);
    let rows = measure_all(gpu, options, &timed, |label| {
        let done = begun.fetch_add(1, Ordering::Relaxed);
        if let Ok(mut progress) = progress.lock() {
            progress(done, steps, label);
        }
    })?;
    if let Ok(mut progress) = progress.lock() {
        progress(steps, steps, "done");
    }
    Ok(rows)
}

/// The errors of every timed configuration of `timed`, measured by `options.workers` threads at
/// once, each taking the next configuration not yet taken and measuring it with measurers (and
/// renderers) of its own; `begins` hears each configuration's label as it is taken. Rows in the
/// order of `timed`.
fn measure_all(
    gpu: &Gpu,
    options: &SweepOptions,
    timed: &[(Config, Cost)],
    begins: impl Fn(&str) + Sync,
) -> Result<Vec<Row>, MeasureError> {
    let next = AtomicUsize::new(0);
    let worker = || -> Result<Vec<(usize, Row)>, MeasureError> {
        let mut scene = Measurer::new(gpu, options.size, options.truth);
        let mut cases = Measurer::new(gpu, options.case_size, TruthSettings { soft_rays: 0, ..options.truth });
        let mut rows = Vec::new();
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            let Some(&(config, cost)) = timed.get(i) else { return Ok(rows) };
            begins(&config.label());
            let settings = config.settings(&options.base);
            let (accuracy, lights) = scene_accuracy(&mut scene, &settings, &options.views)?;
            let scores = CASES
                .iter()
                .map(|c| options.measures_case(c.name).then(|| (c.run)(&mut cases, &settings)).transpose())
                .collect::<Result<Vec<_>, _>>()?;
            rows.push((i, Row { config, cost, scene: accuracy, lights, cases: scores }));
        }
    };
    let workers = options.workers.clamp(1, timed.len().max(1));
    let done: Vec<Result<Vec<(usize, Row)>, MeasureError>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..workers).map(|_| s.spawn(worker)).collect();
        handles.into_iter().map(|h| h.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic))).collect()
    });
    let mut rows = Vec::with_capacity(timed.len());
    for worker_rows in done {
        rows.extend(worker_rows?);
    }
    rows.sort_by_key(|(i, _)| *i);
    Ok(rows.into_iter().map(|(_, row)| row).collect())
}

/// Indices of the rows on the Pareto front of (cost, error): none is both cheaper and more
/// accurate. In order of cost.
pub fn pareto(points: &[(f64, f64)]) -> Vec<usize> {
    let mut order: Vec<usize> =
        (0..points.len()).filter(|&i| points[i].0.is_finite() && points[i].1.is_finite()).collect();
    order.sort_by(|&a, &b| points[a].0.total_cmp(&points[b].0).then(points[a].1.total_cmp(&points[b].1)));
    let mut best = f64::INFINITY;
    order
        .into_iter()
        .filter(|&i| {
            let better = points[i].1 < best;
            best = best.min(points[i].1);
            better
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_front_keeps_only_points_nothing_beats() {
        let points = [(1.0, 5.0), (2.0, 3.0), (3.0, 4.0), (4.0, 1.0), (2.5, 3.0), (5.0, f64::NAN)];
        assert_eq!(pareto(&points), vec![0, 1, 3]);
    }
}
