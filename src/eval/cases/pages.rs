//! The virtual-page cases: filters reading past a page's border, a camera cut (the error while
//! its pages come), a caster moving through cached pages, a page pool too small for the view, and
//! a camera creeping to and fro across the distance where a virtual level gives way to the next.
//! Each is measured for every configuration: with cascades the same scene tells how the sun's
//! cascades do there.

use super::scenes::{add_box, ground, sun_direction};
use super::{Score, flips, ground_probes, measure_at, misclassified, on_ground};
use crate::App;
use crate::components::{Camera, DirectionalLight, ShadowMap, ShadowMethod, Transform, Viewport};
use crate::eval::measure::{CaseScene, MeasureError, Measurer, SubjectId, place_camera};
use crate::eval::metrics::{out_of_range, rendered};
use crate::render::PRIME_ROUNDS;
use crate::settings::Settings;
use crate::shadow::{Clipmap, FINEST_TEXEL_LOG2, wanted_texel};
use bevy_ecs::prelude::*;
use glam::Vec3;

const PAGE_SEAMS: SubjectId = SubjectId::Case(CaseScene::PageSeams);
const CAMERA_CUT: SubjectId = SubjectId::Case(CaseScene::CameraCut);
const MOVING_CASTER: SubjectId = SubjectId::Case(CaseScene::MovingCaster);
const POOL_TOO_SMALL: SubjectId = SubjectId::Case(CaseScene::PoolTooSmall);
const LEVEL_CREEP: SubjectId = SubjectId::Case(CaseScene::LevelCreep);

/// The sun of the page cases: 40° up, from the south-west.
fn sun() -> Vec3 {
    sun_direction(40.0, 210.0)
}

/// The sun's clipmap in `app` as a paged sun would have it (its grid depends only on the sun's
/// direction and the shadow distance, so it is the same with cascades).
fn clipmap(app: &App) -> Clipmap {
    Clipmap::new(sun(), app.settings().cascade.shadow_distance, (0.0, 0.0))
}

/// Octaves of level 0 a surface facing up at `p` wants, seen from `eye` (its page is that,
/// rounded, within the clipmap's levels): what `page_level` in pages.wgsl figures.
fn wanted_octaves(app: &App, eye: Vec3, p: Vec3) -> f32 {
    let height = app.world.resource::<Viewport>().height;
    let angle = Camera::default().pixel_angle(height);
    let to_eye = eye - p;
    let wanted = wanted_texel(to_eye.length(), angle, to_eye.normalize().y, -sun().y);
    wanted.log2() - FINEST_TEXEL_LOG2 as f32 + app.settings().maps.page_bias
}

/// How far from `target` along `from` (a unit vector) an eye stands for the ground at `target`
/// to want `octaves` (octaves grow with distance one for one in log2).
fn distance_wanting(app: &App, target: Vec3, from: Vec3, octaves: f32) -> f32 {
    let at_one = wanted_octaves(app, target + from, target);
    2f32.powf(octaves - at_one)
}

/// An open ground that casts (its pages hold its depths), the sun on it through a Poisson disc
/// of 32 (2.5 texels wide, the widest fixed filter), the camera straight over the origin.
fn seams_scene(settings: &Settings) -> Result<App, crate::AppError> {
    let mut app = ground(settings, 80.0, true, sun(), (Vec3::new(0.0, 8.0, 0.01), Vec3::ZERO))?;
    let suns: Vec<Entity> = app.world.query_filtered::<Entity, With<DirectionalLight>>().iter(&app.world).collect();
    for sun in suns {
        app.world.entity_mut(sun).insert(ShadowMethod::Poisson32);
    }
    Ok(app)
}

/// The pixels of the open ground within 0.5 to 3 texels either side of a border between the
/// pages they read (the level each wants; the camera straight over the ground in the middle of a
/// level's octave), and the share of them darkened by 10 % (nothing shades the ground). A filter
/// that reads past its page finds its neighbour's tile in the atlas; with the border, what the
/// neighbouring page holds.
pub fn page_seams(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    let app = &mut m.subject(PAGE_SEAMS, settings, seams_scene)?.app;
    let level = wanted_octaves(app, Vec3::Y * 8.0, Vec3::ZERO).round().max(0.0);
    let eye = Vec3::Y * distance_wanting(app, Vec3::ZERO, Vec3::Y, level) + Vec3::Z * 0.01;
    let c = clipmap(app);
    let last = (c.levels - 1) as f32;
    let level_at = |app: &App, p: Vec3| wanted_octaves(app, eye, p).round().clamp(0.0, last) as u32;
    let measured = measure_at(m, PAGE_SEAMS, "over", |app| place_camera(&mut app.world, eye, Vec3::ZERO))?;
    let (app, _) = m.parts(PAGE_SEAMS)?;
    let mut score = Score::default();
    for (i, t) in measured.truth[0].iter().enumerate() {
        let p = measured.frame.position[i].truncate();
        let (Some(t), Some(v), true) = (t, rendered(&measured.frame, 0, i), on_ground(&measured)(i)) else { continue };
        let level = level_at(app, p);
        let texels = c.across(p) / c.texel(level);
        // Texels to the nearest border of the page it lies in, along each axis.
        let pages = texels / crate::shadow::PAGE_TEXELS as f32;
        let to_border = (pages - pages.round()).abs() * crate::shadow::PAGE_TEXELS as f32;
        if t.lit && (0.5..=3.0).contains(&to_border.min_element()) {
            score.of += 1;
            score.hits += (v < 0.9) as u64;
        }
    }
    score.garbage += (0..measured.frame.position.len()).filter(|&i| out_of_range(&measured.frame, 0, i)).count() as u64;
    Ok(score)
}

/// Where the camera-cut case's two groups of pillars stand: far enough apart that the pages of
/// one view hold nothing of the other's.
const CUT_FROM: Vec3 = Vec3::ZERO;
const CUT_TO: Vec3 = Vec3::new(48.0, 0.0, -20.0);

/// Pillars round `at`, each 30 cm square, of three heights.
fn pillars(app: &mut App, at: Vec3) {
    for k in 0..9 {
        let (x, z, h) = ((k % 3) as f32 * 2.2 - 2.2, (k / 3) as f32 * 2.2 - 2.2, 0.8 + (k % 4) as f32 * 0.6);
        add_box(app, at + Vec3::new(x + 0.3 * (k % 2) as f32, h / 2.0, z), Vec3::new(0.15, h / 2.0, 0.15));
    }
}

/// A view of the pillars round `at`, from 8 m along +Z and 5 m up.
fn view_of(at: Vec3) -> (Vec3, Vec3) {
    (at + Vec3::new(1.0, 5.0, 8.0), at)
}

fn cut_scene(settings: &Settings) -> Result<App, crate::AppError> {
    let mut app = ground(settings, 200.0, false, sun(), view_of(CUT_FROM))?;
    pillars(&mut app, CUT_FROM);
    pillars(&mut app, CUT_TO);
    Ok(app)
}

/// True when no paged light in `app` waits for a page (one without pages never does).
fn pages_settled(app: &mut App) -> bool {
    let mut maps = app.world.query::<&ShadowMap>();
    maps.iter(&app.world).filter_map(|m| m.pages.as_ref()).all(|p| p.update.settled())
}

/// The misclassified share of the sun's pixels from a camera cut to the other group of pillars
/// until every page the new view needs is resident (not within [`PRIME_ROUNDS`] frames: garbage).
pub fn camera_cut(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    m.subject(CAMERA_CUT, settings, cut_scene)?;
    after_cut(m, CAMERA_CUT, view_of(CUT_FROM), view_of(CUT_TO))
}

/// Scene `id` drawn ready from `from` (eye, target), then the camera cut to `to`: the misclassified
/// share of the sun's pixels over the frames until every page the new view needs is resident,
/// as a window draws them (a page comes the frame after it is marked); not settled within
/// [`PRIME_ROUNDS`] frames more: garbage.
fn after_cut(m: &mut Measurer<'_>, id: SubjectId, from: (Vec3, Vec3), to: (Vec3, Vec3)) -> Result<Score, MeasureError> {
    measure_at(m, id, "before", |app| place_camera(&mut app.world, from.0, from.1))?;
    let (app, _) = m.parts(id)?;
    place_camera(&mut app.world, to.0, to.1);
    let mut score = Score::default();
    for frame in 0..=PRIME_ROUNDS {
        let gpu = m.gpu();
        let (app, renderer) = m.parts(id)?;
        renderer.wait_for_samples(gpu);
        app.hear(renderer.news());
        app.step_held();
        // The first frame's update heard the marks of the view before the cut.
        let settled = frame > 0 && pages_settled(app);
        let measured = m.measure_as_is(id, "after")?;
        score.add(misclassified(&measured, 0, |_| true));
        if settled {
            return Ok(score);
        }
    }
    score.garbage += 1;
    Ok(score)
}

/// Where the sliding box starts and how far it slides a frame.
const SLIDE_FROM: Vec3 = Vec3::new(-1.5, 0.5, 0.0);
const SLIDE_STEP: Vec3 = Vec3::new(0.5, 0.0, 0.0);
const SLIDE_FRAMES: u32 = 6;

fn sliding_scene(settings: &Settings) -> Result<App, crate::AppError> {
    let mut app = ground(settings, 80.0, false, sun(), (Vec3::new(0.0, 6.0, 7.0), Vec3::new(0.0, 0.0, -1.0)))?;
    add_box(&mut app, SLIDE_FROM, Vec3::splat(0.5));
    Ok(app)
}

/// The misclassified share of the ground while a 1 m box slides 50 cm a frame: a page its old
/// shadow lay on must be drawn again, else the old shadow stays there.
pub fn moving_caster(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    m.subject(MOVING_CASTER, settings, sliding_scene)?;
    let slide = |app: &mut App, step: u32| {
        let mut boxes = app.world.query_filtered::<&mut Transform, With<crate::components::ShadowCaster>>();
        for mut t in boxes.iter_mut(&mut app.world) {
            t.translation = SLIDE_FROM + SLIDE_STEP * step as f32;
        }
    };
    measure_at(m, MOVING_CASTER, "0", |app| slide(app, 0))?;
    let mut score = Score::default();
    for step in 1..=SLIDE_FRAMES {
        let measured = measure_at(m, MOVING_CASTER, &step.to_string(), |app| slide(app, step))?;
        score.add(misclassified(&measured, 0, on_ground(&measured)));
    }
    Ok(score)
}

/// The pool-too-small case's page memory, MiB: 64 pages of 64².
pub const SMALL_POOL: u32 = 1;

/// Where the pool-too-small case looks at its poles from, and at.
const POLES_VIEW: (Vec3, Vec3) = (Vec3::new(0.0, 3.0, 9.0), Vec3::new(0.0, 0.0, -4.0));

fn poles_scene(settings: &Settings) -> Result<App, crate::AppError> {
    let mut app = ground(settings, 800.0, false, sun(), POLES_VIEW)?;
    for k in 0..12 {
        let (x, z) = ((k % 4) as f32 * 2.5 - 3.75, -(k / 4) as f32 * 4.0);
        add_box(&mut app, Vec3::new(x, 1.0, z), Vec3::new(0.05, 1.0, 0.05));
    }
    // A canopy whose shadow covers much of the view.
    add_box(&mut app, Vec3::new(1.0, 2.05, -3.0), Vec3::new(2.5, 0.05, 2.0));
    Ok(app)
}

/// The misclassified share of the sun's pixels over 10 cm poles and a canopy with a page pool of
/// [`SMALL_POOL`] MiB, over the frames from a cut to them until the pool has made do (it takes
/// coarser levels while pages go missing): what it cannot hold must read coarser levels, not
/// nothing.
pub fn pool_too_small(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    let small = settings.clone().with(|s| s.maps.page_memory = SMALL_POOL);
    m.subject(POOL_TOO_SMALL, &small, poles_scene)?;
    // Farther than the coarsest page the pool may take there reaches.
    let elsewhere = (POLES_VIEW.0 + Vec3::X * 300.0, POLES_VIEW.1 + Vec3::X * 300.0);
    after_cut(m, POOL_TOO_SMALL, elsewhere, POLES_VIEW)
}

/// Frames the level-creep camera creeps, and how far it swings either way (octaves round the
/// boundary between two levels).
const CREEP_FRAMES: u32 = 12;
const CREEP_SWING: f32 = 0.2;
/// The direction the level-creep camera looks at its target from.
const CREEP_FROM: Vec3 = Vec3::new(0.0, 0.6, 0.8);

fn creep_scene(settings: &Settings) -> Result<App, crate::AppError> {
    let mut app = ground(settings, 80.0, false, sun(), (CREEP_FROM * 6.0, Vec3::ZERO))?;
    for (x, z, h) in [(-0.8, -0.6, 0.5), (0.6, -0.9, 0.8), (0.0, 0.5, 0.3), (-0.7, 0.8, 0.6), (0.9, 0.4, 0.4)] {
        add_box(&mut app, Vec3::new(x, h / 2.0, z), Vec3::new(0.08, h / 2.0, 0.08));
    }
    Ok(app)
}

/// Share of fixed ground points round the posts (every 3 cm) that flip lit/shadowed per frame
/// as the camera creeps to and fro along its view, so that the ground it looks at wants a
/// level's boundary ± 0.2 octaves.
pub fn level_creep(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    let app = &mut m.subject(LEVEL_CREEP, settings, creep_scene)?.app;
    let from = CREEP_FROM.normalize();
    let boundary = wanted_octaves(app, from * 6.0, Vec3::ZERO).floor() + 0.5;
    let points = ground_probes(
        (-50..=50).flat_map(|i| (-50..=50).map(move |j| Vec3::new(i as f32 * 0.03, 0.0, j as f32 * 0.03))),
    );
    flips(m, LEVEL_CREEP, &points, CREEP_FRAMES, |app, frame| {
        let swing = CREEP_SWING * (frame as f32 * std::f32::consts::TAU / 6.0).sin();
        let distance = distance_wanting(app, Vec3::ZERO, from, boundary + swing);
        place_camera(&mut app.world, from * distance, Vec3::ZERO);
    })
}
