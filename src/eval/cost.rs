//! What a configuration costs: the shadow pass and the extra work of the lookups, timed on the
//! sample scene with every map redrawn every frame.
//!
//! Every configuration is timed in the same interleaved rounds (one frame of each, then the next
//! round), and every frame is followed by the same frame with shadows off, so a machine whose
//! speed drifts over the run slows all configurations alike and the ratios stay fair.

use super::measure::{MeasureError, Measurer, Subject, SubjectId, apply_settings, place_camera};
use super::sweep::{Config, SweepOptions};
use crate::App;
use crate::render::{Gpu, HEADLESS_FORMAT, PassTimes, Renderer};
use crate::settings::Settings;
use std::time::Instant;

/// What a configuration costs per frame, from the medians of every timed frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Cost {
    /// Drawing every shadow layer, milliseconds.
    pub shadow_ms: f64,
    /// What the shadow lookups add to the main pass, milliseconds (the median difference, which
    /// timing noise can make slightly negative for the cheapest filters).
    pub lookup_ms: f64,
    /// Fastest and slowest frame's shadow cost, milliseconds.
    pub range_ms: (f64, f64),
}

impl Cost {
    /// The whole shadow cost: drawing the maps plus looking them up.
    pub fn total_ms(&self) -> f64 {
        self.shadow_ms + self.lookup_ms
    }
}

/// One timed frame under `settings` at scene time `t`: GPU pass times, or the wall time of the
/// whole frame where the device has no timestamps.
fn frame(
    gpu: &Gpu,
    app: &mut App,
    renderer: &mut Renderer,
    target: (&wgpu::TextureView, u32, u32),
    (settings, t): (&Settings, f64),
) -> Result<PassTimes, MeasureError> {
    apply_settings(app, settings);
    app.set_time(t);
    let start = Instant::now();
    renderer.render(gpu, &mut app.world, target.0, target.1, target.2)?;
    gpu.wait()?;
    let wall = start.elapsed().as_secs_f64() * 1e3;
    Ok(match renderer.pass_times(gpu) {
        Some(t) => t?,
        None => PassTimes { shadow_ms: wall, main_ms: 0.0 },
    })
}

/// Times every configuration in `configs` over the options' views; `progress` hears each round. One scene
/// per map size is kept, so switching configuration never re-allocates the maps.
pub fn time_all(
    gpu: &Gpu,
    base: &Settings,
    configs: &[Config],
    options: &SweepOptions,
    mut progress: impl FnMut(usize),
) -> Result<Vec<Cost>, MeasureError> {
    let (w, h) = options.size;
    let texture = gpu.target("timed frame", (w, h), HEADLESS_FORMAT)?;
    let view = texture.create_view(&Default::default());
    let mut m = Measurer::new(gpu, options.size, options.truth);
    let mut times: Vec<Vec<(PassTimes, PassTimes)>> = vec![Vec::new(); configs.len()];
    let mut round = 0;
    for v in &options.views {
        for k in 0..options.frames + 2 {
            progress(round);
            round += 1;
            for (c, config) in configs.iter().enumerate() {
                let on = Settings { reuse_shadow_maps: false, ..config.settings(base) };
                let off = Settings { shadows: false, ..on.clone() };
                let Subject { app, renderer } =
                    m.subject(SubjectId::Timing(config.map_size), &on, |s| App::new(s.clone()))?;
                renderer.enable_timing(gpu);
                place_camera(&mut app.world, v.eye, v.target);
                let target = (&view, w, h);
                let pair = (
                    frame(gpu, app, renderer, target, (&on, v.time))?,
                    frame(gpu, app, renderer, target, (&off, v.time))?,
                );
                if k >= 2 {
                    times[c].push(pair);
                }
            }
        }
    }
    Ok(times.iter().map(|t| cost(t)).collect())
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

/// The cost from frames timed with shadows and without: drawing the maps, plus what the lookups
/// add to the main pass (without timestamps, the whole frame's difference).
fn cost(frames: &[(PassTimes, PassTimes)]) -> Cost {
    let shadow: Vec<f64> = frames.iter().map(|(on, off)| on.shadow_ms - off.shadow_ms).collect();
    let lookup = median(frames.iter().map(|(on, off)| on.main_ms - off.main_ms).collect());
    let range = (
        shadow.iter().copied().fold(f64::INFINITY, f64::min),
        shadow.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
    Cost { shadow_ms: median(shadow), lookup_ms: lookup, range_ms: range }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cost_is_the_median_difference_with_shadows_off() {
        let pair = |shadow, main, off_main| {
            (PassTimes { shadow_ms: shadow, main_ms: main }, PassTimes { shadow_ms: 0.0, main_ms: off_main })
        };
        let c = cost(&[pair(4.0, 3.0, 2.0), pair(6.0, 3.5, 2.0), pair(5.0, 9.0, 2.0)]);
        assert_eq!((c.shadow_ms, c.lookup_ms, c.range_ms), (5.0, 1.5, (4.0, 6.0)));
        assert_eq!(c.total_ms(), 6.5);
    }
}
