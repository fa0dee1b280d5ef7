//! What a configuration costs: the shadow pass and the extra work of the lookups, timed on the
//! sample scene with every map redrawn every frame.
//!
//! Every configuration is timed in the same interleaved rounds (three frames of each, then the
//! next round): the frame with every map drawn, the same frame with every map kept, and with
//! shadows off. A machine whose speed drifts over the run slows all configurations alike and the
//! ratios stay fair.

use super::config::Config;
use super::measure::{MeasureError, Measurer, Subject, SubjectId, TimedMaps, place_camera};
use super::sweep_options::SweepOptions;
use crate::App;
use crate::render::{Gpu, HEADLESS_FORMAT, Renderer};
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

/// Where and how frames are timed: the GPU, whether by its timestamps, and the picture drawn.
#[derive(Clone, Copy)]
struct Stopwatch<'a> {
    gpu: &'a Gpu,
    /// Time the GPU's passes by its timestamps (else the wall clock, the frame waited for).
    stamps: bool,
    view: &'a wgpu::TextureView,
    size: (u32, u32),
}

impl Stopwatch<'_> {
    /// One timed frame of `app` under `settings` at scene time `t`, in milliseconds.
    fn frame(&self, app: &mut App, renderer: &mut Renderer, settings: &Settings, t: f64) -> Result<f64, MeasureError> {
        let Stopwatch { gpu, stamps, view, size: (width, height) } = *self;
        app.set_settings(settings)?;
        app.set_time(t);
        let start = Instant::now();
        renderer.render(gpu, &app.world, view, width, height)?;
        app.hear(renderer.news());
        gpu.wait()?;
        let wall = start.elapsed().as_secs_f64() * 1e3;
        Ok(match renderer.pass_times(gpu) {
            Some(times) if stamps => {
                let t = times?;
                t.shadow_ms + t.main_ms
            }
            _ => wall,
        })
    }
}

/// One round's three frames of a configuration: every map drawn, every map kept (the same
/// frame again, nothing dirty), and shadows off.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Timed {
    drawn: f64,
    kept: f64,
    off: f64,
}

/// Times every configuration in `configs` over the options' views; `progress` hears each round. One scene
/// per kind of map ([`TimedMaps`]) is kept, so switching configuration never makes the maps anew.
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
    let stamps = timed_on_gpu(gpu);
    let watch = Stopwatch { gpu, stamps, view: &view, size: (w, h) };
    let mut m = Measurer::new(gpu, options.size, options.truth);
    let mut times: Vec<Vec<Timed>> = vec![Vec::new(); configs.len()];
    let mut round = 0;
    for v in &options.views {
        for k in 0..options.frames + 2 {
            progress(round);
            round += 1;
            for (c, config) in configs.iter().enumerate() {
                let drawn = config.settings(base).with(|s| s.maps.reuse_shadow_maps = false);
                let kept = drawn.clone().with(|s| s.maps.reuse_shadow_maps = true);
                let off = kept.clone().with(|s| s.shadow.enabled = false);
                let id = SubjectId::Timing(timed_maps(config));
                let Subject { app, renderer } = m.subject(id, &drawn, |s| App::new(s.clone()))?;
                if stamps {
                    renderer.enable_timing(gpu);
                }
                place_camera(&mut app.world, v.eye, v.target);
                let t = Timed {
                    drawn: watch.frame(app, renderer, &drawn, v.time)?,
                    kept: watch.frame(app, renderer, &kept, v.time)?,
                    off: watch.frame(app, renderer, &off, v.time)?,
                };
                if k >= 2 {
                    times[c].push(t);
                }
            }
        }
    }
    Ok(times.iter().map(|t| cost(t)).collect())
}

/// The kind of map `config` draws: the configurations of one kind are timed in one scene.
fn timed_maps(config: &Config) -> TimedMaps {
    TimedMaps {
        size: config.map_size,
        depth: config.depth,
        colour: config.method.colour_map().then_some((config.method, config.moment_bits, config.moments_from)),
        moment_resolve: config.moment_resolve,
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

/// The cost from each round's three frames: drawing the maps is what a frame with every map drawn
/// costs over the same frame with every map kept; the lookups, what that kept frame costs over one
/// with shadows off.
fn cost(frames: &[Timed]) -> Cost {
    let shadow: Vec<f64> = frames.iter().map(|t| t.drawn - t.kept).collect();
    let lookup = median(frames.iter().map(|t| t.kept - t.off).collect());
    let range = (
        shadow.iter().copied().fold(f64::INFINITY, f64::min),
        shadow.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
    Cost { shadow_ms: median(shadow), lookup_ms: lookup, range_ms: range }
}

/// Whether timing came from the GPU's timestamps on this device.
pub fn timed_on_gpu(gpu: &Gpu) -> bool {
    gpu.device.features().contains(wgpu::Features::TIMESTAMP_QUERY)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cost_is_the_median_difference_between_drawn_kept_and_off() {
        let t = |drawn, kept, off| Timed { drawn, kept, off };
        let c = cost(&[t(9.0, 5.0, 2.0), t(12.0, 6.0, 2.5), t(9.0, 4.0, 3.0)]);
        assert_eq!((c.shadow_ms, c.lookup_ms, c.range_ms), (5.0, 3.0, (4.0, 6.0)));
        assert_eq!(c.total_ms(), 8.0);
    }

    #[test]
    fn configurations_share_a_timed_scene_only_when_their_maps_are_alike() {
        use crate::components::ShadowMethod;
        use crate::settings::{MomentBits, MomentSource, ShadowDepth, ShadowFaces};
        let d = Config::default_settings();
        let same = [
            Config { method: ShadowMethod::Pcf3, receiver_plane: false, ..d },
            Config { bias: 0.0, faces: ShadowFaces::Back, cascades: 1, ..d },
            Config { fit: crate::shadow::FitMode::Sdsm, ..d },
        ];
        assert!(same.iter().all(|c| timed_maps(c) == timed_maps(&d)));
        let apart = [
            Config { depth: ShadowDepth::Unorm16, ..d },
            Config { map_size: d.map_size * 2, ..d },
            Config { method: ShadowMethod::Vsm, ..d },
            Config { method: ShadowMethod::Vsm, moment_bits: MomentBits::Half, ..d },
            Config { method: ShadowMethod::Vsm, moments_from: MomentSource::Half, ..d },
            Config { method: ShadowMethod::DepthR32f, ..d },
        ];
        for (i, a) in apart.iter().enumerate() {
            assert_ne!(timed_maps(a), timed_maps(&d), "{}", a.label());
            assert!(apart[i + 1..].iter().all(|b| timed_maps(a) != timed_maps(b)), "{}", a.label());
        }
    }
}
