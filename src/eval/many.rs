//! `umbra bench --lights`: the sample scene with 4 to 1,024 lights (its own four, then lanterns:
//! [`crate::lanterns`]), everything moving, under five policies: no shadows, umbra's atlas
//! (tiles sized by what each light shows, in the default 256 MiB, kept while clean), every
//! light paged (virtual maps sharing one pool of [`PAGES_MIB`], each light's coarse map in the
//! atlas), every layer at the map size as umbra had it before its atlas, and a Bevy-like policy
//! (spots at 2048², point lights 1024² a face, every map drawn every frame, no cache). For each:
//! the frame's cost (wall time, and the shadow and main passes' GPU time where there are
//! timestamps), the shadow memory, the tiles drawn and left stale a frame, the pages resident,
//! drawn and missing, the texels per pixel where shadows are looked up, and each light's error
//! against the ray-traced truth over the pixels it reaches.
//!
//! A policy that needs more shadow memory than [`MAX_RUN_MIB`] is reported with what it needs,
//! not run.

use super::cases::budget::{ShrinkPoint, threshold_sides};
use super::chart::{ChartError, line_chart};
use super::metrics::{Tally, tally};
use super::texels::{Density, Eye, density};
use super::truth::{SizeOverride, truth_of};
use super::{BenchError, median};
use crate::components::ShadowMap;
use crate::light::light_list;
use crate::render::{Gpu, HEADLESS_FORMAT, Renderer, ShadowStats, render_debug_frame};
use crate::settings::{LightMaps, MAX_SHADOW_MEMORY, SunMaps, TileSizes};
use crate::systems::ShadowAtlas;
use crate::{App, Settings};
use std::path::Path;
use std::time::Instant;

/// The light counts of the full sweep, and of `--quick`.
pub const LIGHT_COUNTS: [u32; 5] = [4, 16, 64, 256, 1024];
pub const QUICK_COUNTS: [u32; 3] = [4, 16, 64];

/// The sample scene's own lights (sun, two spots, lantern): lanterns make up the rest.
pub const SAMPLE_LIGHTS: u32 = 4;

/// The most shadow memory a policy is run with, in MiB.
pub const MAX_RUN_MIB: u32 = 4096;

/// The pool every paged light's pages share under the pages policy, in MiB: the bound,
/// half the atlas's default, which holds it and every paged light's coarse map.
pub const PAGES_MIB: u32 = 128;

/// A light must reach this many pixels of the measured frame for its error to count: one wrong
/// pixel is then at most 0.25 %, half the 0.5 % bound (at 50 pixels one pixel was 2 %,
/// and the worst light's share measured the frame's grain, not the shadow).
const MIN_PIXELS: u64 = 400;

/// What the table's columns that need it mean, for the page the table is written to.
#[must_use]
pub fn columns_note() -> String {
    format!(
        "Errors count lights reaching at least {MIN_PIXELS} pixels of the measured frame. *All lights wrong* is the \
         misclassified share of their pixels pooled (a pixel two lights reach counts twice); the worst light's share \
         moves by up to {:.2} % a pixel. Without shadows the atlas is still held (turning shadows on draws into it), \
         so its memory is what it holds, not what it draws.",
        100.0 / MIN_PIXELS as f64
    )
}

/// How shadows are kept.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Policy {
    Unshadowed,
    Atlas,
    Pages,
    Fixed,
    Bevy,
}

impl Policy {
    pub const ALL: [Policy; 5] = [Policy::Unshadowed, Policy::Atlas, Policy::Pages, Policy::Bevy, Policy::Fixed];

    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Policy::Unshadowed => "no shadows",
            Policy::Atlas => "umbra's atlas",
            Policy::Pages => "virtual pages",
            Policy::Fixed => "fixed layers",
            Policy::Bevy => "Bevy-like",
        }
    }

    /// `base` under this policy with `lights` lights.
    #[must_use]
    pub fn settings(self, base: &Settings, lights: u32) -> Settings {
        let s = base.clone().with(|s| s.scene.lanterns = lights.saturating_sub(SAMPLE_LIGHTS));
        match self {
            Policy::Unshadowed => s.with(|s| s.shadow.enabled = false),
            Policy::Atlas => s,
            Policy::Pages => s.with(|s| {
                s.maps.sun_maps = SunMaps::Virtual;
                s.maps.light_maps = LightMaps::Virtual;
                s.maps.page_memory = PAGES_MIB;
            }),
            Policy::Fixed => s.with(|s| s.maps.tile_sizes = TileSizes::Fixed),
            Policy::Bevy => s.with(|s| {
                s.maps.tile_sizes = TileSizes::Bevy;
                s.maps.reuse_shadow_maps = false;
                s.maps.static_cache = false;
            }),
        }
    }
}

/// One policy at one light count.
#[derive(Clone, Debug, PartialEq)]
pub struct LightsRow {
    pub policy: Policy,
    pub lights: u32,
    /// The shadow atlas's memory, MiB (what the policy needs, when it was not run).
    pub memory_mib: u32,
    /// Run (false: it needs more than [`MAX_RUN_MIB`]).
    pub ran: bool,
    /// Median milliseconds of a whole frame, waited for.
    pub frame_ms: f64,
    /// Median GPU milliseconds of the shadow and the main pass (NaN without timestamps).
    pub shadow_ms: f64,
    pub main_ms: f64,
    /// Shadow layers drawn, and left stale, a frame (means).
    pub drawn: f64,
    pub stale: f64,
    /// Where lights are paged: pages holding slots after the timed frames, and pages drawn and
    /// pages missing (asked for, with no slot) a frame, means (NaN where none is paged).
    pub pages_resident: f64,
    pub pages_drawn: f64,
    pub pages_missing: f64,
    /// Texels across a pixel where the measured lights' lookups are made, all together: the
    /// median pixel's and the 99th percentile's.
    pub texels_median: f64,
    pub texels_p99: f64,
    /// Lights reaching enough of the measured frame to count.
    pub measured: usize,
    /// Their misclassified shares of the pixels each reaches: the median light's and the worst's.
    pub median_wrong: f64,
    pub worst_wrong: f64,
    /// The worst light: its name, its layers' side and how many pixels it reaches.
    pub worst: String,
    /// Misclassified share of every measured light's pixels together: a pixel reached by two
    /// lights counts twice. Unlike the worst light's share, one pixel more or less barely moves it.
    pub pooled_wrong: f64,
    /// Mean error against the soft truth over every light's pixels together.
    pub soft_error: f64,
}

/// What a run measures with.
#[derive(Clone, Copy, Debug)]
pub struct LightsOptions {
    /// Measured frames per run (after the warm-up).
    pub frames: u32,
    /// Timed frames' size.
    pub size: (u32, u32),
    /// The measured frame's size.
    pub measure: (u32, u32),
    /// Rays over each light's disc for the soft truth.
    pub soft_rays: usize,
}

/// The shadow memory `settings` need for every light's layers at their policy's size, in MiB
/// (as a first update sizes them with all the memory there is).
fn memory_needed(settings: &Settings) -> Result<u32, BenchError> {
    let mut app = App::new(settings.clone().with(|s| s.maps.shadow_memory = MAX_SHADOW_MEMORY))?;
    app.set_time(0.0);
    let bytes = u64::from(app.world.resource::<ShadowAtlas>().texel_bytes);
    let mut maps = app.world.query::<&ShadowMap>();
    let texels: u64 = maps.iter(&app.world).map(|m| m.layers.len() as u64 * u64::from(m.resolution).pow(2)).sum();
    Ok(u32::try_from((texels * bytes).div_ceil(1 << 20)).unwrap_or(u32::MAX))
}

/// Runs `policy` with `lights` lights: warm-up frames, `frames` timed ones, then one measured
/// against the truth.
pub fn run_one(
    gpu: &Gpu,
    base: &Settings,
    policy: Policy,
    lights: u32,
    o: LightsOptions,
) -> Result<LightsRow, BenchError> {
    let mut settings = policy.settings(base, lights);
    if matches!(policy, Policy::Fixed | Policy::Bevy) {
        settings.maps.shadow_memory = memory_needed(&settings)?.max(settings.maps.shadow_memory);
    }
    let mut row = LightsRow {
        policy,
        lights,
        memory_mib: settings.maps.shadow_memory,
        ran: settings.maps.shadow_memory <= MAX_RUN_MIB,
        frame_ms: f64::NAN,
        shadow_ms: f64::NAN,
        main_ms: f64::NAN,
        drawn: 0.0,
        stale: 0.0,
        pages_resident: f64::NAN,
        pages_drawn: f64::NAN,
        pages_missing: f64::NAN,
        texels_median: f64::NAN,
        texels_p99: f64::NAN,
        measured: 0,
        median_wrong: f64::NAN,
        worst_wrong: f64::NAN,
        worst: String::new(),
        pooled_wrong: f64::NAN,
        soft_error: f64::NAN,
    };
    if !row.ran {
        return Ok(row);
    }
    let mut app = App::new(settings.clone())?;
    app.resize(o.size.0, o.size.1);
    let mut renderer = Renderer::new(gpu, HEADLESS_FORMAT)?;
    app.hear(renderer.news());
    let stamps = renderer.enable_timing(gpu);
    let target = gpu.target("lights bench", o.size, HEADLESS_FORMAT)?;
    let view = target.create_view(&Default::default());
    let warm_up = crate::systems::REST_AFTER as u32 + 5;
    let (mut frames, mut shadow, mut main) = (Vec::new(), Vec::new(), Vec::new());
    for round in 0..warm_up + o.frames {
        app.step();
        let start = Instant::now();
        renderer.render(gpu, &app.world, &view, o.size.0, o.size.1)?;
        app.hear(renderer.news());
        gpu.wait()?;
        if round < warm_up {
            continue;
        }
        frames.push(start.elapsed().as_secs_f64() * 1e3);
        if let Some(times) = renderer.pass_times(gpu).filter(|_| stamps) {
            let times = times?;
            shadow.push(times.shadow_ms);
            main.push(times.main_ms);
        }
        let stats = app.world.resource::<ShadowStats>();
        let share = |n: u32| f64::from(n) / f64::from(o.frames);
        row.drawn += share(stats.drawn());
        row.stale += share(stats.stale());
        let page_drawn = share(stats.pages.drawn);
        if let Some((resident, missing)) = page_counts(&mut app.world) {
            row.pages_resident = f64::from(resident);
            row.pages_drawn = row.pages_drawn.max(0.0) + page_drawn;
            row.pages_missing = row.pages_missing.max(0.0) + share(missing);
        }
    }
    (row.frame_ms, row.shadow_ms, row.main_ms) = (median(&mut frames), median(&mut shadow), median(&mut main));
    row.memory_mib = (app.world.resource::<ShadowAtlas>().bytes() >> 20) as u32;
    if policy != Policy::Unshadowed {
        measure(gpu, &mut app, &mut renderer, o, &mut row)?;
    }
    Ok(row)
}

/// Pages holding slots, and pages asked for with no slot at the last update, over every paged
/// light of `world`; none where no light is paged.
fn page_counts(world: &mut bevy_ecs::world::World) -> Option<(u32, u32)> {
    let mut maps = world.query::<&ShadowMap>();
    let paged: Vec<_> = maps.iter(world).filter_map(|m| m.pages.as_ref()).collect();
    let counts = paged.iter().map(|p| (p.resident, p.update.residency.missing));
    (!paged.is_empty()).then(|| counts.fold((0, 0), |(r, m), (a, b)| (r + a, m + b)))
}

/// Measures the frame the app is at against the truth, light by light, into `row`.
fn measure(
    gpu: &Gpu,
    app: &mut App,
    renderer: &mut Renderer,
    o: LightsOptions,
    row: &mut LightsRow,
) -> Result<(), BenchError> {
    let (w, h) = o.measure;
    app.resize(w, h);
    app.step_held();
    let frame = render_debug_frame(gpu, renderer, app, w, h)?;
    let truth = truth_of(&mut app.world, &frame, SizeOverride::default(), o.soft_rays);
    let eye = Eye::of(&mut app.world, h);
    let lights = light_list(&app.world);
    let mut all = Tally::default();
    let mut texels = Density::default();
    let mut wrong: Vec<f64> = Vec::new();
    for (l, light) in lights.iter().enumerate().take(truth.len()) {
        let t = tally(&frame, &truth[l], l, |_| true);
        if t.pixels < MIN_PIXELS {
            continue;
        }
        all.merge(&t);
        if let Some(eye) = eye {
            texels.merge(&density(&frame, l, light, eye));
        }
        // A NaN share counts as the worst.
        if t.misclassified().partial_cmp(&row.worst_wrong).is_none_or(|o| o.is_gt()) {
            row.worst_wrong = t.misclassified();
            // A paged light's first layer is its coarse map; its shadow is mostly its pages.
            let map = match light.pages {
                Some(_) => "pages".to_string(),
                None => format!("{}²", light.layers.first().map_or(0, |layer| layer.resolution)),
            };
            row.worst = format!("{} ({map}, {} px)", light.label, t.pixels);
        }
        wrong.push(t.misclassified());
    }
    row.measured = wrong.len();
    row.median_wrong = median(&mut wrong);
    row.pooled_wrong = all.misclassified();
    row.soft_error = all.mae_soft();
    let quantile = |q| texels.quantile(q).map_or(f64::NAN, f64::from);
    (row.texels_median, row.texels_p99) = (quantile(0.5), quantile(0.99));
    Ok(())
}

/// Runs every policy at every count of `counts`, `progress` hearing each row.
pub fn run(
    gpu: &Gpu,
    base: &Settings,
    counts: &[u32],
    o: LightsOptions,
    mut progress: impl FnMut(&LightsRow),
) -> Result<Vec<LightsRow>, BenchError> {
    let mut rows = Vec::new();
    for &lights in counts {
        for policy in Policy::ALL {
            let row = run_one(gpu, base, policy, lights, o)?;
            progress(&row);
            rows.push(row);
        }
    }
    Ok(rows)
}

/// A number, or a dash where it was not measured.
fn cell(x: f64, decimals: usize) -> String {
    if x.is_finite() { format!("{x:.decimals$}") } else { "–".into() }
}

/// The results as a Markdown table, each row's frame also as a ratio to the atlas's with 4
/// lights.
#[must_use]
pub fn table(rows: &[LightsRow]) -> String {
    let base = rows.iter().find(|r| r.policy == Policy::Atlas && r.ran).map_or(f64::NAN, |r| r.frame_ms);
    let mut out = String::from(
        "| lights | policy | shadow MiB | frame ms | x atlas at the fewest | shadow pass ms | main pass ms | \
         layers drawn / frame | stale / frame | pages resident, drawn / frame, missing / frame | \
         texels per pixel, median and 99 % | lights measured | all lights wrong % | median light wrong % | \
         worst light wrong % | worst light | soft error |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n",
    );
    for r in rows {
        if !r.ran {
            let needs = format!("needs {} MiB: not run", r.memory_mib);
            out += &format!("| {} | {} | {needs} | | | | | | | | | | | | | | |\n", r.lights, r.policy.name());
            continue;
        }
        out += &format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            r.lights,
            r.policy.name(),
            r.memory_mib,
            cell(r.frame_ms, 1),
            cell(r.frame_ms / base, 2),
            cell(r.shadow_ms, 1),
            cell(r.main_ms, 1),
            cell(r.drawn, 1),
            cell(r.stale, 1),
            pages_cell(r),
            if r.texels_median.is_finite() {
                format!("{}, {}", cell(r.texels_median, 2), cell(r.texels_p99, 2))
            } else {
                "–".into()
            },
            r.measured,
            cell(r.pooled_wrong * 100.0, 3),
            cell(r.median_wrong * 100.0, 3),
            cell(r.worst_wrong * 100.0, 3),
            r.worst,
            cell(r.soft_error, 4),
        );
    }
    out
}

/// A row's pages: resident, drawn a frame and missing a frame; a dash where none is paged.
fn pages_cell(r: &LightsRow) -> String {
    if !r.pages_resident.is_finite() {
        return "–".into();
    }
    format!("{}, {}, {}", cell(r.pages_resident, 0), cell(r.pages_drawn, 1), cell(r.pages_missing, 1))
}

/// The tile-shrink sweep as a Markdown table, with the side where it crosses `threshold`,
/// predicted and measured.
#[must_use]
pub fn shrink_table(points: &[ShrinkPoint], threshold: f64) -> String {
    let mut out = String::from("| tile side | predicted wrong % | measured wrong % |\n| --- | --- | --- |\n");
    for p in points {
        out += &format!("| {}² | {} | {} |\n", p.side, cell(p.predicted * 100.0, 3), cell(p.measured * 100.0, 3));
    }
    let (measured, predicted) = threshold_sides(points, threshold);
    let measured = measured.map_or("none of these".into(), |s| format!("{s}²"));
    let predicted = predicted.map_or("–".into(), |s| format!("{s:.0}²"));
    out + &format!("\nit passes {:.1} % from {measured} measured, {predicted} predicted\n", threshold * 100.0)
}

/// Two charts against the number of lights (on a log₂ axis), one line per policy: the frame's
/// cost as `stem`-cost and the worst light's error as `stem`-error (.png and .svg each).
pub fn charts(stem: &Path, adapter: &str, rows: &[LightsRow]) -> Result<(), ChartError> {
    let line = |p: Policy, y: fn(&LightsRow) -> f64| {
        let at = rows.iter().filter(|r| r.policy == p && r.ran).map(|r| (f64::from(r.lights).log2(), y(r)));
        (p.name().to_string(), at.filter(|(_, y)| y.is_finite()).collect::<Vec<_>>())
    };
    let counts: Vec<String> =
        rows.iter().filter(|r| r.policy == Policy::ALL[0]).map(|r| format!("{}", r.lights)).collect();
    let cost: Vec<_> = Policy::ALL.iter().map(|&p| line(p, |r| r.frame_ms)).collect();
    let name =
        |s: &str| stem.with_file_name(format!("{}-{s}", stem.file_name().and_then(|n| n.to_str()).unwrap_or("lights")));
    let axes = ("lights (log2)", "milliseconds a frame (median)");
    line_chart(&name("cost"), &format!("frame cost against lights ({adapter})"), axes, &cost, &counts)?;
    let error: Vec<_> = Policy::ALL[1..].iter().map(|&p| line(p, |r| r.worst_wrong * 100.0)).collect();
    let axes = ("lights (log2)", "worst light's misclassified %");
    line_chart(&name("error"), &format!("error against lights ({adapter})"), axes, &error, &counts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn policies_set_what_they_stand_for() {
        let base = Settings::default();
        let bevy = Policy::Bevy.settings(&base, 64);
        assert_eq!(
            (bevy.scene.lanterns, bevy.maps.tile_sizes, bevy.maps.reuse_shadow_maps, bevy.maps.static_cache),
            (60, TileSizes::Bevy, false, false)
        );
        assert_eq!(Policy::Atlas.settings(&base, 4), base.clone().with(|s| s.scene.lanterns = 0));
        assert!(!Policy::Unshadowed.settings(&base, 16).shadow.enabled);
        let pages = Policy::Pages.settings(&base, 64).maps;
        assert_eq!(
            (pages.sun_maps, pages.light_maps, pages.page_memory),
            (SunMaps::Virtual, LightMaps::Virtual, PAGES_MIB)
        );
        assert!(PAGES_MIB <= base.maps.shadow_memory / 2, "the pool fits the default atlas");
        // Every lamp at 2048² a face: far more than the atlas's default.
        let fixed = memory_needed(&Policy::Fixed.settings(&base, 16)).unwrap();
        let bevy = memory_needed(&bevy).unwrap();
        assert!(fixed >= 4 * base.maps.shadow_memory && bevy > base.maps.shadow_memory, "{fixed} and {bevy} MiB");
    }

    #[test]
    fn the_table_names_what_did_not_run_and_gives_ratios() {
        let row = |policy, lights, frame_ms, ran| LightsRow {
            policy,
            lights,
            memory_mib: 256,
            ran,
            frame_ms,
            shadow_ms: f64::NAN,
            main_ms: 1.0,
            drawn: 2.0,
            stale: 0.0,
            pages_resident: f64::NAN,
            pages_drawn: f64::NAN,
            pages_missing: f64::NAN,
            texels_median: 1.5,
            texels_p99: 6.0,
            measured: 3,
            median_wrong: 0.001,
            worst_wrong: 0.004,
            worst: "spot (512², 900 px)".into(),
            pooled_wrong: 0.002,
            soft_error: 0.01,
        };
        let paged = LightsRow {
            pages_resident: 812.0,
            pages_drawn: 3.5,
            pages_missing: 0.0,
            ..row(Policy::Pages, 64, 20.0, true)
        };
        let t = table(&[
            row(Policy::Atlas, 4, 10.0, true),
            row(Policy::Atlas, 64, 25.0, true),
            paged,
            row(Policy::Fixed, 64, 0.0, false),
        ]);
        assert!(t.contains("| 64 | umbra's atlas | 256 | 25.0 | 2.50 | – | 1.0 | 2.0 | 0.0 | – | 1.50, 6.00 | 3 | 0.200 | 0.100 | 0.400 | spot (512², 900 px) | 0.0100 |"), "{t}");
        assert!(
            t.contains("| 64 | virtual pages | 256 | 20.0 | 2.00 | – | 1.0 | 2.0 | 0.0 | 812, 3.5, 0.0 | 1.50, 6.00 |"),
            "{t}"
        );
        assert!(t.contains("| 64 | fixed layers | needs 256 MiB: not run |"), "{t}");
    }

    #[test]
    fn the_shrink_table_names_where_the_threshold_is_crossed() {
        let p = |side, predicted, measured| ShrinkPoint { side, predicted, measured };
        let points = [p(32, 0.02, 0.018), p(64, 0.01, 0.009), p(128, 0.005, 0.004), p(256, 0.0025, 0.001)];
        let t = shrink_table(&points, 0.005);
        assert!(t.contains("| 64² | 1.000 | 0.900 |"), "{t}");
        assert!(t.ends_with("it passes 0.5 % from 128² measured, 128² predicted\n"), "{t}");
        assert!(shrink_table(&points[..1], 0.005).contains("from none of these measured"));
    }
}
