//! `umbra bench --cache`: what a frame costs when the scene is still, when one cube moves and
//! when everything moves, with shadows on and off; `umbra bench --lab`: what the window's panel
//! and a measurement in flight add to a still frame. The scenarios are measured in interleaved
//! rounds in one run, so their ratios are fair even on a machine whose speed drifts.

use crate::components::{Animator, Bob, FlyCamera, Spin, Walker};
use crate::eval::live::{Taken, Worker, snapshot};
use crate::eval::measure::TruthSettings;
use crate::eval::{BenchError, median};
use crate::render::{Gpu, HEADLESS_FORMAT, RenderError, Renderer, ShadowStats};
use crate::ui::{History, Live, Painter};
use crate::{App, Settings};
use bevy_ecs::prelude::*;
use std::time::Instant;

/// What moves in a scenario.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    /// Nothing: the same frame again and again.
    Still,
    /// One cube spins and bobs; everything else stands.
    OneCube,
    /// Every cube moves and the camera turns.
    Everything,
    /// Nothing moves but the camera, which circles the point it looks at (half a degree a
    /// frame): every frame shows ground a little to the side of the last.
    Orbit,
}

/// What the window's lab does on top of the frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lab {
    /// Nothing: the scene alone.
    Off,
    /// The panel is laid out and painted over the frame.
    Panel,
    /// A measurement against the truth (at half the frame's size, as the window measures by
    /// default) starts on a worker thread just before the frame; it is waited for after the
    /// frame is timed, so it slows no other scenario's frames.
    Measuring,
}

/// One measured configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scenario {
    /// Its name in the table.
    pub name: &'static str,
    /// Shadows drawn at all.
    pub shadows: bool,
    /// What moves.
    pub motion: Motion,
    /// What the lab adds.
    pub lab: Lab,
    /// Casters at rest kept in static maps whatever the settings say (see
    /// [`crate::settings::MapSettings::static_cache`]).
    pub static_cache: bool,
}

/// The scenarios of the shadow-cache bench, the baseline (still, no shadows) first; one cube
/// moving is run without the static cache (the default) and with it; the camera orbiting a still
/// scene last.
pub const SCENARIOS: [Scenario; 6] = [
    Scenario { name: "still, shadows off", shadows: false, motion: Motion::Still, lab: Lab::Off, static_cache: false },
    Scenario { name: "still, shadows on", shadows: true, motion: Motion::Still, lab: Lab::Off, static_cache: false },
    Scenario { name: "one cube moving", shadows: true, motion: Motion::OneCube, lab: Lab::Off, static_cache: false },
    Scenario {
        name: "one cube moving, static cache",
        shadows: true,
        motion: Motion::OneCube,
        lab: Lab::Off,
        static_cache: true,
    },
    Scenario {
        name: "everything moving",
        shadows: true,
        motion: Motion::Everything,
        lab: Lab::Off,
        static_cache: false,
    },
    Scenario { name: "camera orbiting", shadows: true, motion: Motion::Orbit, lab: Lab::Off, static_cache: false },
];

/// The scenarios of the lab bench, the baseline (the still scene alone) first.
pub const LAB_SCENARIOS: [Scenario; 3] = [
    Scenario { name: "still, shadows on", shadows: true, motion: Motion::Still, lab: Lab::Off, static_cache: false },
    Scenario { name: "still, panel open", shadows: true, motion: Motion::Still, lab: Lab::Panel, static_cache: false },
    Scenario {
        name: "still, a measurement in flight",
        shadows: true,
        motion: Motion::Still,
        lab: Lab::Measuring,
        static_cache: false,
    },
];

/// A scenario's result.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchRow {
    /// Which scenario.
    pub scenario: Scenario,
    /// Median frame time (update excluded; extract, shadow pass, main pass and GPU wait included).
    pub median_ms: f64,
    /// Fastest frame.
    pub min_ms: f64,
    /// Slowest frame.
    pub max_ms: f64,
    /// Shadow-map layers drawn per frame, on average.
    pub drawn_per_frame: f64,
    /// Shadow-map layers kept per frame, on average.
    pub kept_per_frame: f64,
    /// Frames a measurement was still running at the end of (the rest overlapped it only in part).
    pub measured: u32,
    /// How long the worker took for each measurement, median, in milliseconds (NaN with none).
    pub measure_ms: f64,
}

struct Run {
    scenario: Scenario,
    app: App,
    renderer: Renderer,
    times: Vec<f64>,
    drawn: u64,
    kept: u64,
    panel: Option<(Painter, crate::ui::Lab)>,
    worker: Worker<()>,
    /// Timed frames a measurement was still running at the end of.
    measured: u32,
    /// The worker's time for each measurement, in milliseconds.
    measure_ms: Vec<f64>,
}

impl Run {
    fn new(gpu: &Gpu, scenario: Scenario, settings: &Settings, width: u32, height: u32) -> Result<Run, BenchError> {
        let settings = settings.clone().with(|s| {
            s.shadow.enabled = scenario.shadows;
            s.maps.static_cache = scenario.static_cache || settings.maps.static_cache;
        });
        let mut app = App::new(settings)?;
        if scenario.motion == Motion::OneCube {
            freeze_all_but_one_cube(&mut app.world);
        }
        let mut renderer = Renderer::new(gpu, HEADLESS_FORMAT)?;
        app.hear(renderer.news());
        app.resize(width, height);
        app.set_time(2.0);
        let panel = (scenario.lab == Lab::Panel)
            .then(|| (Painter::new(gpu, HEADLESS_FORMAT), crate::ui::Lab { panel: true, ..Default::default() }));
        let worker = Worker::default();
        Ok(Run {
            scenario,
            app,
            renderer,
            times: Vec::new(),
            drawn: 0,
            kept: 0,
            panel,
            worker,
            measured: 0,
            measure_ms: Vec::new(),
        })
    }

    /// Starts a measurement (not timed: in the window it is one extra frame, once).
    fn start_measuring(&mut self, gpu: &Gpu, size: (u32, u32)) -> Result<(), RenderError> {
        if self.scenario.lab == Lab::Measuring {
            let half = ((size.0 / 2).max(1), (size.1 / 2).max(1));
            let truth = TruthSettings::default();
            let shot = snapshot(gpu, &mut self.renderer, &mut self.app, half, truth)?;
            self.worker.start((), shot);
        }
        Ok(())
    }

    /// Waits for the measurement started for this frame; true if it was still running when the
    /// frame was done.
    fn finish_measuring(&mut self) -> bool {
        let mut taken = self.worker.take();
        let still = matches!(taken, Taken::Nothing) && self.worker.busy();
        if still {
            taken = self.worker.wait();
        }
        if let Taken::Done(_, report) = taken {
            self.measure_ms.push(report.took.as_secs_f64() * 1e3);
        }
        still
    }

    /// Lays out and paints the panel over `target`, as the window does.
    fn paint_panel(&mut self, gpu: &Gpu, target: &wgpu::TextureView, size: (u32, u32)) {
        let Some((painter, lab)) = self.panel.as_mut() else { return };
        let (history, stats) = (History::default(), self.app.world.resource::<ShadowStats>().clone());
        let live = Live { history: &history, stats: &stats, measured: None, status: "", camera: "", adapter: "" };
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(size.0 as f32, size.1 as f32))),
            ..Default::default()
        };
        let world = &mut self.app.world;
        let (painted, _) = painter.run(input, |ui| crate::ui::panel(ui, world, lab, &live));
        painter.paint(gpu, &[target], size, painted);
    }

    fn advance(&mut self) {
        if self.scenario.motion == Motion::Everything {
            for mut fly in self.app.world.query::<&mut FlyCamera>().iter_mut(&mut self.app.world) {
                fly.yaw += 0.004;
            }
        }
        if self.scenario.motion == Motion::Orbit {
            orbit(&mut self.app.world, ORBIT_STEP);
        }
        // A still scene still updates (with its clock held): a virtual map takes in the pages
        // its last marking asked for. The update is not timed.
        if matches!(self.scenario.motion, Motion::Still | Motion::Orbit) {
            self.app.step_held();
        } else {
            self.app.step();
        }
    }

    fn frame(
        &mut self,
        gpu: &Gpu,
        target: &wgpu::TextureView,
        size: (u32, u32),
        record: bool,
    ) -> Result<(), RenderError> {
        self.advance();
        self.start_measuring(gpu, size)?;
        let start = Instant::now();
        self.renderer.render(gpu, &self.app.world, target, size.0, size.1)?;
        self.app.hear(self.renderer.news());
        self.paint_panel(gpu, target, size);
        gpu.wait()?;
        let elapsed = start.elapsed();
        let overlapped = self.finish_measuring();
        if record {
            self.measured += overlapped as u32;
            self.times.push(elapsed.as_secs_f64() * 1e3);
            let stats = self.app.world.resource::<ShadowStats>();
            self.drawn += stats.drawn() as u64;
            self.kept += stats.kept() as u64;
        }
        Ok(())
    }

    fn row(mut self) -> BenchRow {
        self.times.sort_by(f64::total_cmp);
        let n = self.times.len().max(1) as f64;
        BenchRow {
            scenario: self.scenario,
            median_ms: median(&mut self.times),
            min_ms: self.times.first().copied().unwrap_or(f64::NAN),
            max_ms: self.times.last().copied().unwrap_or(f64::NAN),
            drawn_per_frame: self.drawn as f64 / n,
            kept_per_frame: self.kept as f64 / n,
            measured: self.measured,
            measure_ms: median(&mut self.measure_ms),
        }
    }
}

/// Stops every animated cube but the first, and the walking character, so exactly one caster
/// moves.
fn freeze_all_but_one_cube(world: &mut World) {
    let mut cubes: Vec<Entity> = world.query_filtered::<Entity, With<Spin>>().iter(world).collect();
    cubes.sort();
    for e in cubes.into_iter().skip(1) {
        world.entity_mut(e).remove::<(Spin, Bob)>();
    }
    let walkers: Vec<Entity> = world.query_filtered::<Entity, With<Walker>>().iter(world).collect();
    for e in walkers {
        world.entity_mut(e).remove::<(Walker, Animator)>();
    }
}

/// How far the orbiting camera circles a frame, radians.
const ORBIT_STEP: f32 = 0.5 * std::f32::consts::PI / 180.0;

/// Turns the camera `angle` radians round the vertical through the ground point it looks at (the
/// point 10 m ahead where it looks up or along the ground), still looking at it.
fn orbit(world: &mut World, angle: f32) {
    let mut cameras = world.query_filtered::<&crate::components::Transform, With<crate::components::Camera>>();
    let Some(t) = cameras.iter(world).next().copied() else { return };
    let (eye, forward) = (t.translation, t.forward());
    let ahead = if forward.y < -1e-3 { (-eye.y / forward.y).min(100.0) } else { 10.0 };
    let target = eye + forward * ahead;
    let turned = target + glam::Quat::from_rotation_y(angle) * (eye - target);
    crate::scene::place_camera(world, turned, target);
}

/// Runs every scenario of `scenarios` for `frames` measured frames (after a few unmeasured ones),
/// interleaved frame by frame, at `width` x `height`; `progress` hears each finished round.
pub fn run(
    gpu: &Gpu,
    settings: &Settings,
    scenarios: &[Scenario],
    frames: u32,
    width: u32,
    height: u32,
    mut progress: impl FnMut(u32, u32),
) -> Result<Vec<BenchRow>, BenchError> {
    let target = gpu.target("bench frame", (width, height), HEADLESS_FORMAT)?;
    let view = target.create_view(&Default::default());
    let mut runs =
        scenarios.iter().map(|s| Run::new(gpu, *s, settings, width, height)).collect::<Result<Vec<_>, _>>()?;
    // Long enough for still casters to come to rest, so the static maps are in their steady state.
    const WARM_UP: u32 = crate::systems::REST_AFTER as u32 + 5;
    for round in 0..WARM_UP + frames {
        for run in &mut runs {
            run.frame(gpu, &view, (width, height), round >= WARM_UP)?;
        }
        if round >= WARM_UP {
            progress(round + 1 - WARM_UP, frames);
        }
    }
    Ok(runs.into_iter().map(Run::row).collect())
}

/// The results as a Markdown table, each median also given as a ratio to the first row's.
pub fn table(rows: &[BenchRow]) -> String {
    let base = rows.first().map_or(f64::NAN, |r| r.median_ms);
    let first = rows.first().map_or("the first row", |r| r.scenario.name);
    let mut out = format!(
        "| scenario | median ms | min–max ms | × {first} | layers drawn / kept per frame |\n| --- | --- | --- | --- | --- |\n"
    );
    for r in rows {
        let measured = match r.scenario.lab {
            Lab::Measuring => format!(
                " (one takes {:.0} ms on the worker; still running at the end of {} frames)",
                r.measure_ms, r.measured
            ),
            _ => String::new(),
        };
        out += &format!(
            "| {}{measured} | {:.2} | {:.2}–{:.2} | {:.3} | {:.2} / {:.2} |\n",
            r.scenario.name,
            r.median_ms,
            r.min_ms,
            r.max_ms,
            r.median_ms / base,
            r.drawn_per_frame,
            r.kept_per_frame
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_one_cube_keeps_moving() {
        let mut app = App::new(Settings::default()).unwrap();
        freeze_all_but_one_cube(&mut app.world);
        assert_eq!(app.world.query::<(&Spin, &Bob)>().iter(&app.world).count(), 1);
        assert_eq!(app.world.query::<&Walker>().iter(&app.world).count(), 0);
    }

    #[test]
    fn an_orbit_keeps_the_camera_looking_at_the_same_point_from_as_far() {
        let mut app = App::new(Settings::default()).unwrap();
        let eye = |w: &mut World| {
            w.query_filtered::<&crate::components::Transform, With<crate::components::Camera>>()
                .single(w)
                .unwrap()
                .translation
        };
        let before = eye(&mut app.world);
        for _ in 0..90 {
            orbit(&mut app.world, ORBIT_STEP);
        }
        let after = eye(&mut app.world);
        assert!((after.y - before.y).abs() < 1e-3, "{before} -> {after}");
        assert!(after.distance(before) > 1.0, "an eighth of a turn moves the camera");
        let t = app
            .world
            .query_filtered::<&crate::components::Transform, With<crate::components::Camera>>()
            .single(&app.world)
            .unwrap();
        assert!(t.forward().y < 0.0, "still looking down at the scene");
    }

    #[test]
    fn the_table_gives_ratios_to_the_first_row() {
        let row = |name, median_ms| BenchRow {
            scenario: Scenario { name, shadows: true, motion: Motion::Still, lab: Lab::Off, static_cache: false },
            median_ms,
            min_ms: 1.0,
            max_ms: 9.0,
            drawn_per_frame: 0.0,
            kept_per_frame: 6.0,
            measured: 0,
            measure_ms: f64::NAN,
        };
        let t = table(&[row("a", 2.0), row("b", 3.0)]);
        assert!(t.contains("| a | 2.00 | 1.00–9.00 | 1.000 | 0.00 / 6.00 |"), "{t}");
        assert!(t.contains("| b | 3.00 | 1.00–9.00 | 1.500 |"), "{t}");
    }
}
