//! `umbra bench --shadow-pass`: umbra's shadow pass against a bare depth pass that draws the same
//! casters into the same layers and does nothing else (see [`crate::render`]'s bare depth pass),
//! on scenes of more and more cubes, and how the cost grows with the casters inside the layers.
//!
//! Every layer is drawn every frame (the cache off), everything moves, and the two passes are
//! timed alternately frame by frame, each to the end of the GPU's work. umbra's time includes the
//! extract it needs (bounds, culling, instancing, uploads); the bare pass is given the frame's
//! culled lists and pays only for uploading its placements and drawing.

use super::chart::{ChartError, line_chart};
use super::{BenchError, median};
use crate::render::{Gpu, HEADLESS_FORMAT, Renderer, ShadowStats, extract};
use crate::{App, Settings};
use std::path::Path;
use std::time::Instant;

/// The scene sizes the bench plays: the sample's ring, then ever larger fields round it.
pub const SCENE_SIZES: [u32; 6] = [10, 1_000, 2_500, 5_000, 10_000, 20_000];

/// One scene's result.
#[derive(Clone, Debug, PartialEq)]
pub struct PassRow {
    /// Animated cubes in the scene.
    pub cubes: u32,
    /// Objects that cast shadows.
    pub casters: usize,
    /// Casters inside the layers, summed over the layers (a caster in three layers counts
    /// three times): what both passes draw.
    pub inside: usize,
    /// Layers drawn each frame.
    pub layers: usize,
    /// Draw calls umbra's pass takes a frame.
    pub calls: u32,
    /// Median milliseconds of umbra's shadow pass, extract included.
    pub umbra_ms: f64,
    /// Median milliseconds of the bare depth pass.
    pub bare_ms: f64,
}

impl PassRow {
    /// umbra's pass over the bare one.
    #[must_use]
    pub fn ratio(&self) -> f64 {
        self.umbra_ms / self.bare_ms
    }
}

/// Plays each scene of `sizes` cubes for `frames` measured frames (after 3 unmeasured) under
/// `settings`; `progress` hears each finished scene.
pub fn run(
    gpu: &Gpu,
    settings: &Settings,
    sizes: &[u32],
    frames: u32,
    mut progress: impl FnMut(&PassRow),
) -> Result<Vec<PassRow>, BenchError> {
    let mut rows = Vec::new();
    for &cubes in sizes {
        let settings = settings.clone().with(|s| {
            s.scene.cubes = cubes;
            s.maps.reuse_shadow_maps = false;
        });
        let mut app = App::new(settings.clone())?;
        let mut renderer = Renderer::new(gpu, HEADLESS_FORMAT)?;
        app.hear(renderer.news());
        let (mut umbra, mut bare) = (Vec::new(), Vec::new());
        let mut row = PassRow { cubes, casters: 0, inside: 0, layers: 0, calls: 0, umbra_ms: 0.0, bare_ms: 0.0 };
        for round in 0..frames + 3 {
            app.step();
            let time_umbra = |app: &mut App, renderer: &mut Renderer| -> Result<f64, BenchError> {
                let start = Instant::now();
                renderer.render_shadow_maps(gpu, &app.world)?;
                app.hear(renderer.news());
                gpu.wait()?;
                Ok(start.elapsed().as_secs_f64() * 1e3)
            };
            let data = extract(&app.world);
            let time_bare = |renderer: &mut Renderer| -> Result<f64, BenchError> {
                let start = Instant::now();
                renderer.render_bare_depth(gpu, &data, settings.maps.shadow_depth)?;
                gpu.wait()?;
                Ok(start.elapsed().as_secs_f64() * 1e3)
            };
            // Alternate which goes first, so neither always finds the caches warm.
            let (a, b) = if round % 2 == 0 {
                let a = time_umbra(&mut app, &mut renderer)?;
                (a, time_bare(&mut renderer)?)
            } else {
                let b = time_bare(&mut renderer)?;
                (time_umbra(&mut app, &mut renderer)?, b)
            };
            if round >= 3 {
                umbra.push(a);
                bare.push(b);
            }
            row.casters = data.items.iter().filter(|i| i.caster).count();
            row.inside = data.draws.iter().map(|d| d.casters.len()).sum();
            row.layers = data.draws.len();
            row.calls = app.world.resource::<ShadowStats>().calls();
        }
        (row.umbra_ms, row.bare_ms) = (median(&mut umbra), median(&mut bare));
        progress(&row);
        rows.push(row);
    }
    Ok(rows)
}

/// The results as a Markdown table.
#[must_use]
pub fn table(rows: &[PassRow]) -> String {
    let mut out = String::from(
        "| cubes | casters | casters inside layers | layers | umbra's calls | umbra ms | bare ms | umbra / bare |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- |\n",
    );
    for r in rows {
        out += &format!(
            "| {} | {} | {} | {} | {} | {:.2} | {:.2} | {:.3} |\n",
            r.cubes,
            r.casters,
            r.inside,
            r.layers,
            r.calls,
            r.umbra_ms,
            r.bare_ms,
            r.ratio()
        );
    }
    out
}

/// The chart of both passes' cost against the casters inside the layers, as `stem`.png and .svg.
pub fn chart(stem: &Path, title: &str, rows: &[PassRow]) -> Result<(), ChartError> {
    let series = |f: fn(&PassRow) -> f64| rows.iter().map(|r| (r.inside as f64, f(r))).collect::<Vec<_>>();
    let labels: Vec<String> = rows.iter().map(|r| format!("{} cubes", r.cubes)).collect();
    let lines = [
        ("umbra's shadow pass".to_string(), series(|r| r.umbra_ms)),
        ("bare depth pass".to_string(), series(|r| r.bare_ms)),
    ];
    line_chart(stem, title, ("casters inside the layers (summed)", "milliseconds a frame"), &lines, &labels)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_gives_each_scene_its_ratio() {
        let row = PassRow { cubes: 10, casters: 17, inside: 60, layers: 12, calls: 40, umbra_ms: 3.3, bare_ms: 3.0 };
        let t = table(std::slice::from_ref(&row));
        assert!(t.contains("| 10 | 17 | 60 | 12 | 40 | 3.30 | 3.00 | 1.100 |"), "{t}");
        assert!((row.ratio() - 1.1).abs() < 1e-9);
        assert!(median(&mut []).is_nan());
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
    }
}
