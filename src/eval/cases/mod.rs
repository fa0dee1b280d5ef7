//! The ways shadow maps fail, each a small scene and one number measured against the truth:
//! acne, peter-panning, shimmer, thin casters, an off-screen caster, degenerate lights, the far
//! field, a skinned caster that leaves its bind pose, and the cases of many lights, soft filters,
//! contact shadows and virtual pages. The tests hold each number under a
//! threshold at the default settings and show it crossing when the defence is taken away; the
//! benchmark charts each against the cost of every configuration.

pub mod budget;
mod contact;
pub use contact::contact_edge;
pub mod pages;
pub mod precision;
pub mod scenes;
mod soft;

use super::measure::{CaseScene, MeasureError, Measured, Measurer, SubjectId, place_camera};
use super::metrics::{DISTANCE_BANDS, out_of_range, rendered};
use crate::App;
use crate::assets::ModelInstance;
use crate::assets::Vertex;
use crate::components::{Joints, ModelPart, WorldBounds};
use crate::render::{SHADOW_FADE, probe_visibility};
use crate::settings::Settings;
use glam::{Vec2, Vec3};
use scenes::*;

/// How often a case went wrong: `hits` of `of` samples, and samples that were not numbers at all.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Score {
    /// Samples that went wrong.
    pub hits: u64,
    /// Samples looked at.
    pub of: u64,
    /// Samples whose values were NaN, infinite or out of range (any makes the score 1).
    pub garbage: u64,
}

impl Score {
    /// The share that went wrong, 0..1 (1 with any garbage, 0 with nothing to look at).
    pub fn value(&self) -> f64 {
        match (self.garbage, self.of) {
            (g, _) if g > 0 => 1.0,
            (_, 0) => 0.0,
            (_, of) => self.hits as f64 / of as f64,
        }
    }

    fn add(&mut self, other: Score) {
        self.hits += other.hits;
        self.of += other.of;
        self.garbage += other.garbage;
    }
}

/// One failure case.
pub struct Case {
    /// Short name, used for files and tables.
    pub name: &'static str,
    /// What its number counts.
    pub measures: &'static str,
    /// The largest value the tests accept at the default settings.
    pub threshold: f64,
    /// Measures it under `settings`.
    pub run: fn(&mut Measurer<'_>, &Settings) -> Result<Score, MeasureError>,
}

/// Every case, in the order the issues list them.
pub const CASES: [Case; 25] = [
    Case {
        name: "acne", measures: "false-shadow share of an open plane, sun at 2°..89°", threshold: 0.001, run: acne
    },
    Case {
        name: "peter-panning",
        measures: "share of the true shadow within 10 cm of a resting cube's foot rendered lit",
        threshold: 0.03,
        run: peter_panning,
    },
    Case {
        name: "shimmer",
        measures: "share of fixed ground points flipping lit/shadowed per frame as the camera creeps and turns",
        threshold: 0.0001,
        run: shimmer,
    },
    Case {
        name: "thin-casters",
        measures: "share of 2 cm poles' true shadow rendered lit",
        threshold: 0.2,
        run: thin_casters,
    },
    Case {
        name: "off-screen-caster",
        measures: "share of the true shadow of a pillar behind the camera rendered lit",
        threshold: 0.02,
        run: offscreen_caster,
    },
    Case {
        name: "degenerate-lights",
        measures: "misclassified share with the sun along ±X, ±Y, ±Z, grazing and below the horizon (any NaN: 100%)",
        threshold: 0.005,
        run: degenerate_lights,
    },
    Case {
        name: "far-field",
        measures: "misclassified share in the worst view-distance band before the fade, looking to the horizon",
        threshold: 0.01,
        run: far_field,
    },
    Case {
        name: "skinned-caster",
        measures: "share of the true shadow of a character posed far from its bind pose rendered lit",
        threshold: 0.1,
        run: skinned_caster,
    },
    Case {
        name: "cube-seams",
        measures: "misclassified share of the ground along the seams of a point light's shadow cube",
        threshold: CUBE_SEAMS_THRESHOLD,
        run: cube_seams,
    },
    Case {
        name: "wide-spot",
        measures: "misclassified share of the ground in the outer ring (60° to 85°) of a 170° spot",
        threshold: WIDE_SPOT_THRESHOLD,
        run: wide_spot,
    },
    Case {
        name: "soft-acne",
        measures: "mean false darkening of an open plane under PCF 5x5, sun at 10°..60°",
        threshold: 0.005,
        run: soft::soft_acne,
    },
    Case {
        name: "contact-hardening",
        measures: "share of a 2.5 m pole's penumbra under a 10 cm spot drawn where the soft truth has none, or missed (PCSS)",
        threshold: 0.2,
        run: soft::contact_hardening,
    },
    Case {
        name: "light-bleeding",
        measures: "share of the ground in two stacked plates' shadow, across the high one's edge, showing light (VSM, or the moment method in use)",
        threshold: 0.01,
        run: soft::light_bleeding,
    },
    Case {
        name: "ledge-bleeding",
        measures: "mean false light on a ledge's shadowed end, where the filter takes in the ground far below (the method in use)",
        threshold: 0.05,
        run: soft::ledge_bleeding,
    },
    Case {
        name: "atlas-seams",
        measures: "share of a hard-edged spot's lit ground 0.5 to 3 texels inside its tile's edge darkened by 10 % (Poisson 32)",
        threshold: 0.001,
        run: atlas_seams,
    },
    Case {
        name: "precision",
        measures: "false-shadow share of the worst of six walls square to a spot at 1 m to 32 m (depth rounding)",
        threshold: 0.005,
        run: precision::precision,
    },
    Case {
        name: "tile-shrink",
        measures: "misclassified share of a spot's ground as the camera backs away and its tile shrinks (worst of three heights)",
        threshold: 0.005,
        run: budget::tile_shrink,
    },
    Case {
        name: "tile-resize",
        measures: "share of ground points round a spot flipping lit/shadowed per frame as the camera creeps across its tile's size-class edge",
        threshold: 0.0001,
        run: budget::tile_resize,
    },
    Case {
        name: "starved-budget",
        measures: "misclassified share of three spots' ground while a budget of a third of what their slides redraw unlimited (one spot's share: a spot's atlas tile, or the pages its posts cross) serves their sliding posts, 4 cm a frame (a wait past 8 frames and a turn: 100%)",
        threshold: 0.05,
        run: budget::starved_budget,
    },
    Case {
        name: "contact-halos",
        measures: "false-shadow share of the ground seen past a 5 cm bar near the camera, with contact shadows on",
        threshold: 0.002,
        run: contact::contact_halos,
    },
    Case {
        name: "page-seams",
        measures: "share of the sun's open ground 0.5 to 3 texels either side of its virtual pages' borders darkened by 10 % (Poisson 32)",
        threshold: 0.001,
        run: pages::page_seams,
    },
    Case {
        name: "camera-cut",
        measures: "misclassified share of the sun's pixels from a camera cut until every page the new view needs is resident (not within 6 frames: 100%)",
        threshold: 0.01,
        run: pages::camera_cut,
    },
    Case {
        name: "moving-caster",
        measures: "misclassified share of the ground while a 1 m box slides 50 cm a frame under the sun",
        threshold: 0.001,
        run: pages::moving_caster,
    },
    Case {
        name: "pool-too-small",
        measures: "misclassified share of the sun's pixels over 10 cm poles and a canopy with 1 MiB of virtual pages, from a cut to them until the pool has made do (not within 6 frames: 100%)",
        threshold: 0.015,
        run: pages::pool_too_small,
    },
    Case {
        name: "level-creep",
        measures: "share of ground points round posts flipping lit/shadowed per frame as the camera creeps to and fro across a virtual level's boundary",
        threshold: 0.0004,
        run: pages::level_creep,
    },
];

const CUBE_SEAMS_THRESHOLD: f64 = 0.01;
const WIDE_SPOT_THRESHOLD: f64 = 0.003;

/// The case called `name`.
pub fn case(name: &str) -> Option<&'static Case> {
    CASES.iter().find(|c| c.name == name)
}

/// Counts, over the pixels `keep` accepts where `light` was tested, those the truth calls dark
/// (`of`) and those of them rendered lit (`hits`): how much of a shadow went missing.
fn missing_shadow(m: &Measured, light: usize, keep: impl Fn(usize) -> bool) -> Score {
    let mut s = Score::default();
    for (i, t) in m.truth[light].iter().enumerate() {
        if let (Some(t), Some(r), true) = (t, rendered(&m.frame, light, i), keep(i))
            && !t.lit
        {
            s.of += 1;
            s.hits += (r >= 0.5) as u64;
        }
    }
    s
}

/// Misclassified pixels of `light` (dark but lit, or lit but dark) over `keep`, with any
/// visibility that is no share of light as garbage.
fn misclassified(m: &Measured, light: usize, keep: impl Fn(usize) -> bool) -> Score {
    let mut s = Score::default();
    for (i, t) in m.truth[light].iter().enumerate() {
        if out_of_range(&m.frame, light, i) {
            s.garbage += 1;
        }
        if let (Some(t), Some(r), true) = (t, rendered(&m.frame, light, i), keep(i)) {
            s.of += 1;
            s.hits += ((r < 0.5) == t.lit) as u64;
        }
    }
    s
}

/// Pixels showing the ground (y = 0, facing up).
fn on_ground(m: &Measured) -> impl Fn(usize) -> bool + '_ {
    |i| m.frame.covered(i) && m.frame.position[i].y.abs() < 1e-3 && m.frame.normal[i].y > 0.99
}

/// Sets the scene's time (running its update) and measures view `key`.
fn measure_at(
    m: &mut Measurer<'_>,
    id: SubjectId,
    key: &str,
    prepare: impl FnOnce(&mut App),
) -> Result<Measured, MeasureError> {
    let (app, _) = m.parts(id)?;
    prepare(app);
    app.set_time(0.0);
    m.measure(id, key)
}

const ACNE: SubjectId = SubjectId::Case(CaseScene::Acne);
const PETER_PANNING: SubjectId = SubjectId::Case(CaseScene::PeterPanning);
const SHIMMER: SubjectId = SubjectId::Case(CaseScene::Shimmer);
const THIN_CASTERS: SubjectId = SubjectId::Case(CaseScene::ThinCasters);
const OFF_SCREEN_CASTER: SubjectId = SubjectId::Case(CaseScene::OffScreenCaster);
const DEGENERATE_LIGHTS: SubjectId = SubjectId::Case(CaseScene::DegenerateLights);
const FAR_FIELD: SubjectId = SubjectId::Case(CaseScene::FarField);
const CUBE_SEAMS: SubjectId = SubjectId::Case(CaseScene::CubeSeams);
const WIDE_SPOT_SCENE: SubjectId = SubjectId::Case(CaseScene::WideSpot);
const ATLAS_SEAMS: SubjectId = SubjectId::Case(CaseScene::AtlasSeams);

fn acne(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    let view = (Vec3::new(0.0, 5.0, 10.0), Vec3::new(0.0, 0.0, -2.0));
    m.subject(ACNE, settings, |s| ground(s, 80.0, true, Vec3::NEG_Y, view))?;
    let mut score = Score::default();
    for elevation in [2.0, 5.0, 10.0, 20.0, 35.0, 50.0, 70.0, 89.0] {
        let measured =
            measure_at(m, ACNE, &format!("{elevation}"), |app| set_sun(app, sun_direction(elevation, 30.0)))?;
        // Nothing stands on the plane, so every pixel the sun reaches is truly lit.
        score.add(misclassified(&measured, 0, on_ground(&measured)));
    }
    Ok(score)
}

fn peter_panning(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    let view = (Vec3::new(2.2, 2.4, 4.0), Vec3::new(-0.2, 0.2, 0.0));
    m.subject(PETER_PANNING, settings, |s| {
        let mut app = ground(s, 40.0, true, Vec3::NEG_Y, view)?;
        add_box(&mut app, Vec3::new(0.0, 0.5, 0.0), Vec3::splat(0.5));
        Ok(app)
    })?;
    let mut score = Score::default();
    for azimuth in [160.0, 220.0] {
        let sun = sun_direction(35.0, azimuth);
        let measured = measure_at(m, PETER_PANNING, &format!("{azimuth}"), |app| set_sun(app, sun))?;
        // The band along the cube's foot: ground within 10 cm outside its 1 m footprint.
        let band = |i: usize| {
            let p = measured.frame.position[i];
            let outside = (Vec2::new(p.x.abs(), p.z.abs()) - Vec2::splat(0.5)).max(Vec2::ZERO).length();
            on_ground(&measured)(i) && outside > 0.0 && outside <= 0.1
        };
        score.add(missing_shadow(&measured, 0, band));
    }
    Ok(score)
}

/// The scene the shimmer case watches: a ground with a few boxes.
fn shimmer_scene(s: &Settings) -> Result<App, crate::AppError> {
    let mut app = ground(s, 80.0, true, sun_direction(40.0, 30.0), (Vec3::new(0.0, 4.0, 8.0), Vec3::ZERO))?;
    for (x, z, h) in [(-3.0, -2.0, 1.0), (2.0, -3.0, 2.0), (0.5, 0.5, 0.6), (-1.5, 2.0, 1.5), (3.5, 1.5, 0.8)] {
        add_box(&mut app, Vec3::new(x, h / 2.0, z), Vec3::new(0.4, h / 2.0, 0.4));
    }
    Ok(app)
}

fn shimmer(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    m.subject(SHIMMER, settings, shimmer_scene)?;
    // Fixed points on the ground every 10 cm (those under a box stay dark and never flip).
    let points = ground_probes(
        (0..=120).flat_map(|i| (0..=100).map(move |j| Vec3::new(-6.0 + i as f32 * 0.1, 0.0, -6.0 + j as f32 * 0.1))),
    );
    // 120 frames: the camera creeps 1 mm and turns 0.03° a frame, far less than a texel.
    flips(m, SHIMMER, &points, 120, |app, frame| {
        let f = frame as f32;
        let eye = Vec3::new(f * 0.001, 4.0, 8.0);
        let turn = glam::Quat::from_rotation_y((f * 0.03).to_radians());
        place_camera(&mut app.world, eye, eye + turn * (Vec3::ZERO - Vec3::new(0.0, 4.0, 8.0)));
    })
}

/// Probes at `points` on the ground, facing up.
fn ground_probes(points: impl Iterator<Item = Vec3>) -> Vec<Vertex> {
    points.map(|p| Vertex::new(p.to_array(), [0.0, 1.0, 0.0])).collect()
}

/// The share of the probes at `points` that flip lit/shadowed from one frame to the next over
/// `frames` frames of scene `id`, its camera placed by `place` before each frame (given the
/// frame's number); any probe that is not a number counts as garbage.
fn flips(
    m: &mut Measurer<'_>,
    id: SubjectId,
    points: &[Vertex],
    frames: u32,
    mut place: impl FnMut(&mut App, u32),
) -> Result<Score, MeasureError> {
    let gpu = m.gpu();
    let (app, renderer) = m.parts(id)?;
    let mut last: Option<Vec<bool>> = None;
    let mut score = Score::default();
    for frame in 0..frames {
        place(app, frame);
        app.set_time(0.0);
        let seen = probe_visibility(gpu, renderer, app, points)?.swap_remove(0);
        count_flips(&seen, &mut last, &mut score);
    }
    Ok(score)
}

/// Adds to `score` the probes of `seen` that flipped lit/shadowed since `last` (then `seen`
/// becomes the last), and any that are not numbers as garbage.
fn count_flips(seen: &[f32], last: &mut Option<Vec<bool>>, score: &mut Score) {
    score.garbage += seen.iter().filter(|v| !v.is_finite()).count() as u64;
    let dark: Vec<bool> = seen.iter().map(|&v| (0.0..0.5).contains(&v)).collect();
    if let Some(before) = last {
        score.of += dark.len() as u64;
        score.hits += before.iter().zip(&dark).filter(|(a, b)| a != b).count() as u64;
    }
    *last = Some(dark);
}

fn thin_casters(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    let view = (Vec3::new(0.0, 4.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
    m.subject(THIN_CASTERS, settings, |s| {
        let mut app = ground(s, 60.0, false, sun_direction(45.0, 200.0), view)?;
        for x in [-2.0, -1.0, 0.0, 1.0, 2.0] {
            add_box(&mut app, Vec3::new(x, 1.5, -1.0 + x * 0.3), Vec3::new(0.01, 1.5, 0.01));
        }
        Ok(app)
    })?;
    let measured = measure_at(m, THIN_CASTERS, "poles", |_| {})?;
    Ok(missing_shadow(&measured, 0, on_ground(&measured)))
}

fn offscreen_caster(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    let view = (Vec3::new(0.0, 3.0, 10.0), Vec3::ZERO);
    m.subject(OFF_SCREEN_CASTER, settings, |s| {
        // 20 m tall at z = 16, behind the camera; the sun at 45° throws its shadow along x = 0
        // from z = 16 to z = -4, right through the view.
        let mut app = ground(s, 200.0, false, Vec3::new(0.0, -1.0, -1.0).normalize(), view)?;
        add_box(&mut app, Vec3::new(0.0, 10.0, 16.0), Vec3::new(0.5, 10.0, 0.5));
        Ok(app)
    })?;
    let measured = measure_at(m, OFF_SCREEN_CASTER, "behind", |_| {})?;
    Ok(missing_shadow(&measured, 0, on_ground(&measured)))
}

fn degenerate_lights(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    let view = (Vec3::new(3.0, 4.0, 6.0), Vec3::ZERO);
    m.subject(DEGENERATE_LIGHTS, settings, |s| {
        let mut app = ground(s, 40.0, true, Vec3::NEG_Y, view)?;
        add_box(&mut app, Vec3::new(0.0, 0.75, 0.0), Vec3::splat(0.75));
        add_box(&mut app, Vec3::new(-2.0, 0.25, 1.0), Vec3::new(1.0, 0.25, 0.3));
        Ok(app)
    })?;
    let directions = [
        ("+x", Vec3::X),
        ("-x", Vec3::NEG_X),
        ("+y", Vec3::Y),
        ("-y", Vec3::NEG_Y),
        ("+z", Vec3::Z),
        ("-z", Vec3::NEG_Z),
        ("grazing", sun_direction(0.5, 60.0)),
        ("below", sun_direction(-10.0, 60.0)),
    ];
    let mut score = Score::default();
    for (key, direction) in directions {
        let measured = measure_at(m, DEGENERATE_LIGHTS, key, |app| set_sun(app, direction))?;
        score.add(misclassified(&measured, 0, |_| true));
    }
    Ok(score)
}

fn far_field(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    let view = (Vec3::new(0.0, 1.7, 0.0), Vec3::new(0.0, 1.0, -20.0));
    m.subject(FAR_FIELD, settings, |s| {
        let mut app = ground(s, 400.0, false, sun_direction(30.0, 250.0), view)?;
        for i in -4..=4 {
            for k in 1..=14 {
                let (x, z) = (i as f32 * 7.0 + (k % 3) as f32, -(k as f32) * 7.0);
                add_box(&mut app, Vec3::new(x, 2.0, z), Vec3::new(0.4, 2.0, 0.4));
            }
        }
        Ok(app)
    })?;
    let measured = measure_at(m, FAR_FIELD, "horizon", |_| {})?;
    // Bands that end before the shadow starts fading out count; the worst of them is the score.
    let fade = settings.cascade.shadow_distance * (1.0 - SHADOW_FADE);
    let mut start = 0.0;
    let mut worst = Score::default();
    for end in DISTANCE_BANDS.into_iter().take_while(|&end| end <= fade) {
        let band = |i: usize| (start..end).contains(&measured.frame.normal[i].w);
        let s = misclassified(&measured, 0, band);
        if s.value() >= worst.value() {
            worst = s;
        }
        start = end;
    }
    Ok(worst)
}

fn cube_seams(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    m.subject(CUBE_SEAMS, settings, seams_scene)?;
    let measured = measure_at(m, CUBE_SEAMS, "seams", |_| {})?;
    // Near a seam the two largest components of the direction from the light are within 4 %.
    let near_seam = |i: usize| {
        let d = (measured.frame.position[i].truncate() - SEAMS_LAMP).abs();
        let mut c = d.to_array();
        c.sort_by(f32::total_cmp);
        c[1] >= 0.96 * c[2]
    };
    Ok(misclassified(&measured, 0, |i| on_ground(&measured)(i) && near_seam(i)))
}

fn wide_spot(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    m.subject(WIDE_SPOT_SCENE, settings, wide_spot_scene)?;
    let measured = measure_at(m, WIDE_SPOT_SCENE, "ring", |_| {})?;
    // The outer ring: more than 60° from the spot's axis (straight down).
    let outer_ring = |i: usize| {
        let d = (measured.frame.position[i].truncate() - WIDE_SPOT.0).normalize_or_zero();
        d.dot(Vec3::NEG_Y) < 60f32.to_radians().cos()
    };
    Ok(misclassified(&measured, 0, |i| on_ground(&measured)(i) && outer_ring(i)))
}

/// Probes on the lit ground next to the edge of the seams spot's tile: where its cone touches the
/// map's edge (at each side's middle), from 0.5 to 3 texels in, along 20 texels each way. A
/// filter that reads past the tile finds a neighbour's depths, or the nearest depth of an empty
/// page, and darkens ground that nothing shades.
fn atlas_seams(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    m.subject(ATLAS_SEAMS, settings, atlas_seams_scene)?;
    let gpu = m.gpu();
    let (app, renderer) = m.parts(ATLAS_SEAMS)?;
    app.set_time(0.0);
    let resolution = app.world.query::<&crate::components::ShadowMap>().iter(&app.world).map(|s| s.resolution).max();
    let resolution = resolution.unwrap_or(settings.maps.shadow_map_size).max(1) as f32;
    let (at, half) = (SEAMS_SPOT.0, SEAMS_SPOT.1.to_radians());
    let rim = at.y * half.tan();
    let texel = 2.0 * rim / resolution;
    let sides = [Vec3::X, Vec3::NEG_X, Vec3::Z, Vec3::NEG_Z];
    let points: Vec<Vertex> = sides
        .iter()
        .flat_map(|&out| {
            let along = out.cross(Vec3::Y);
            (1..=6).flat_map(move |d| (-20..=20).map(move |s| (out, along, d as f32 * 0.5, s as f32)))
        })
        .map(|(out, along, d, s)| Vec3::new(at.x, 0.0, at.z) + out * (rim - d * texel) + along * (s * texel))
        // Inside the cone by a tenth of a texel, where the spot's light is full.
        .filter(|p| p.distance(Vec3::new(at.x, 0.0, at.z)) < rim - 0.1 * texel)
        .map(|p| Vertex::new(p.to_array(), [0.0, 1.0, 0.0]))
        .collect();
    let seen = probe_visibility(gpu, renderer, app, &points)?.swap_remove(0);
    let mut score = Score::default();
    for v in seen {
        if !v.is_finite() {
            score.garbage += 1;
        } else if v >= 0.0 {
            score.of += 1;
            score.hits += (v < 0.9) as u64;
        }
    }
    Ok(score)
}

/// How far the leaping character's hips are carried from their bind pose.
const LEAP: Vec3 = Vec3::new(6.0, 1.5, 0.0);

fn leaper_scene(s: &Settings) -> Result<App, crate::AppError> {
    let view = (Vec3::new(5.0, 3.0, 5.0), Vec3::new(6.5, 0.0, 0.5));
    with_leaper(s, LEAP, sun_direction(50.0, 300.0), view)
}

fn skinned_caster(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    skinned_caster_bounded(m, settings, false)
}

/// The skinned-caster case; with `bind_pose_bounds` its bounds are put back to the bind pose's
/// before drawing, as a renderer that ignores the pose would have them (to show the failure).
pub fn skinned_caster_bounded(
    m: &mut Measurer<'_>,
    settings: &Settings,
    bind_pose_bounds: bool,
) -> Result<Score, MeasureError> {
    let scene = if bind_pose_bounds { CaseScene::SkinnedCasterBindBounds } else { CaseScene::SkinnedCaster };
    let id = SubjectId::Case(scene);
    let app = &mut m.subject(id, settings, leaper_scene)?.app;
    app.set_time(0.0);
    if bind_pose_bounds {
        use_bind_pose_bounds(app);
    }
    let measured = m.measure(id, "leap")?;
    Ok(missing_shadow(&measured, 0, on_ground(&measured)))
}

/// Replaces every skinned part's bounds with its bind pose's (breaking culling on purpose).
fn use_bind_pose_bounds(app: &mut App) {
    let models: Vec<(bevy_ecs::entity::Entity, std::sync::Arc<crate::assets::Model>)> = app
        .world
        .query::<(bevy_ecs::entity::Entity, &ModelInstance)>()
        .iter(&app.world)
        .map(|(e, m)| (e, m.0.clone()))
        .collect();
    let mut parts = app.world.query_filtered::<(&ModelPart, &mut WorldBounds), bevy_ecs::query::With<Joints>>();
    for (link, mut bounds) in parts.iter_mut(&mut app.world) {
        if let Some((_, model)) = models.iter().find(|(e, _)| *e == link.root) {
            bounds.0 = model.parts[link.part].mesh.bounds;
        }
    }
}
