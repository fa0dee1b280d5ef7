//! `umbra bench`: what a frame costs when the scene is still, when one cube moves and when
//! everything moves, with shadows on and off. The scenarios are measured in interleaved rounds
//! in one run, so their ratios are fair even on a machine whose speed drifts.

use crate::components::{Animator, Bob, FlyCamera, Spin, Walker};
use crate::render::{Gpu, HEADLESS_FORMAT, RenderError, Renderer, ShadowStats};
use crate::{App, AppError, Settings};
use bevy_ecs::prelude::*;
use std::time::Instant;

/// Why a bench could not run.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// A setting is out of range or a model does not load.
    #[error(transparent)]
    App(#[from] AppError),
    /// Rendering failed.
    #[error(transparent)]
    Render(#[from] RenderError),
}

/// What moves in a scenario.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    /// Nothing: the same frame again and again.
    Still,
    /// One cube spins and bobs; everything else stands.
    OneCube,
    /// Every cube moves and the camera turns.
    Everything,
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
}

/// The scenarios of the shadow-cache bench, the baseline (still, no shadows) first.
pub const SCENARIOS: [Scenario; 4] = [
    Scenario { name: "still, shadows off", shadows: false, motion: Motion::Still },
    Scenario { name: "still, shadows on", shadows: true, motion: Motion::Still },
    Scenario { name: "one cube moving", shadows: true, motion: Motion::OneCube },
    Scenario { name: "everything moving", shadows: true, motion: Motion::Everything },
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
}

struct Run {
    scenario: Scenario,
    app: App,
    renderer: Renderer,
    times: Vec<f64>,
    drawn: u64,
    kept: u64,
}

impl Run {
    fn new(gpu: &Gpu, scenario: Scenario, settings: &Settings, width: u32, height: u32) -> Result<Run, BenchError> {
        let mut app = App::new(Settings { shadows: scenario.shadows, ..settings.clone() })?;
        if scenario.motion == Motion::OneCube {
            freeze_all_but_one_cube(&mut app.world);
        }
        app.resize(width, height);
        app.set_time(2.0);
        let renderer = Renderer::new(gpu, HEADLESS_FORMAT)?;
        Ok(Run { scenario, app, renderer, times: Vec::new(), drawn: 0, kept: 0 })
    }

    fn advance(&mut self) {
        if self.scenario.motion == Motion::Everything {
            for mut fly in self.app.world.query::<&mut FlyCamera>().iter_mut(&mut self.app.world) {
                fly.yaw += 0.004;
            }
        }
        if self.scenario.motion != Motion::Still {
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
        let start = Instant::now();
        self.renderer.render(gpu, &mut self.app.world, target, size.0, size.1)?;
        gpu.wait()?;
        if record {
            self.times.push(start.elapsed().as_secs_f64() * 1e3);
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
            median_ms: self.times.get(self.times.len() / 2).copied().unwrap_or(f64::NAN),
            min_ms: self.times.first().copied().unwrap_or(f64::NAN),
            max_ms: self.times.last().copied().unwrap_or(f64::NAN),
            drawn_per_frame: self.drawn as f64 / n,
            kept_per_frame: self.kept as f64 / n,
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

/// Runs every scenario for `frames` measured frames (after a few unmeasured ones), interleaved
/// frame by frame, at `width` x `height`; `progress` hears each finished round.
pub fn run(
    gpu: &Gpu,
    settings: &Settings,
    frames: u32,
    width: u32,
    height: u32,
    mut progress: impl FnMut(u32, u32),
) -> Result<Vec<BenchRow>, BenchError> {
    let target = gpu.target("bench frame", (width, height), HEADLESS_FORMAT)?;
    let view = target.create_view(&Default::default());
    let mut runs =
        SCENARIOS.iter().map(|s| Run::new(gpu, *s, settings, width, height)).collect::<Result<Vec<_>, _>>()?;
    const WARM_UP: u32 = 5;
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
    let mut out = String::from(
        "| scenario | median ms | min–max ms | × still, shadows off | layers drawn / kept per frame |\n| --- | --- | --- | --- | --- |\n",
    );
    for r in rows {
        out += &format!(
            "| {} | {:.2} | {:.2}–{:.2} | {:.3} | {:.2} / {:.2} |\n",
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
    fn the_table_gives_ratios_to_the_first_row() {
        let row = |name, median_ms| BenchRow {
            scenario: Scenario { name, shadows: true, motion: Motion::Still },
            median_ms,
            min_ms: 1.0,
            max_ms: 9.0,
            drawn_per_frame: 0.0,
            kept_per_frame: 6.0,
        };
        let t = table(&[row("a", 2.0), row("b", 3.0)]);
        assert!(t.contains("| a | 2.00 | 1.00–9.00 | 1.000 | 0.00 / 6.00 |"), "{t}");
        assert!(t.contains("| b | 3.00 | 1.00–9.00 | 1.500 |"), "{t}");
    }
}
