//! The many-lights cases: a spot whose tile shrinks as the camera backs away (and the tile side
//! at which its error passes the threshold, predicted from the truth's edges and measured), a
//! spot whose tile changes size as the camera creeps to and fro across a size class's edge, and
//! spots that wait their turn under a starved update budget.

use super::scenes::{add_box, unlit_ground};
use super::{Score, flips, ground_probes, measure_at, misclassified, on_ground};
use crate::App;
use crate::components::{Camera, ShadowCaster, ShadowMap, SpotLight, Transform};
use crate::eval::measure::{CaseScene, MeasureError, Measured, Measurer, SubjectId, place_camera};
use crate::light::{Kind, light_list};
use crate::render::ShadowStats;
use crate::settings::{Settings, TileSizes};
use crate::shadow::MAX_STALE;
use glam::Vec3;

const TILE_SHRINK: SubjectId = SubjectId::Case(CaseScene::TileShrink);
const TILE_RESIZE: SubjectId = SubjectId::Case(CaseScene::TileResize);
const STARVED: SubjectId = SubjectId::Case(CaseScene::StarvedBudget);

/// The tile cases' spot: 4 m up, straight down, its cone's half angle in degrees.
pub const TILE_SPOT: (Vec3, f32) = (Vec3::new(0.0, 4.0, 0.0), 35.0);

/// Heights of the camera over the spot as it backs away: its tile shrinks from 1024² to 256²
/// at the default map size.
pub const SHRINK_HEIGHTS: [f32; 3] = [12.0, 24.0, 48.0];

/// A spot at `at` pointing down, and six posts round its axis (20 cm square, 1.2 m tall) whose
/// shadows run outwards.
fn spot_over_posts(app: &mut App, at: Vec3, outer_degrees: f32) {
    for home in post_homes(at) {
        add_box(app, home, Vec3::new(0.1, 0.6, 0.1));
    }
    let outer = outer_degrees.to_radians();
    let spot =
        SpotLight { range: 6.0, intensity: 4.0, inner_angle: outer - 0.1, outer_angle: outer, ..Default::default() };
    app.world.spawn((spot, Transform::from_translation(at).looking_to(Vec3::NEG_Y), ShadowMap::default()));
}

/// The centres of the six posts round a spot at `at`.
fn post_homes(at: Vec3) -> impl Iterator<Item = Vec3> {
    (0..6).map(move |k| {
        let (angle, r) = (k as f32 * 1.05, 0.9 + (k % 3) as f32 * 0.45);
        at.with_y(0.6) + Vec3::new(angle.cos() * r, 0.0, angle.sin() * r)
    })
}

/// The camera straight over `at`, `height` metres up.
fn over(at: Vec3, height: f32) -> (Vec3, Vec3) {
    (at.with_y(height) + Vec3::Z * 0.01, at.with_y(0.0))
}

/// The tile cases' scene: the spot over its posts on an open ground, seen from straight above.
pub fn tile_spot_scene(settings: &Settings) -> Result<App, crate::AppError> {
    let mut app = unlit_ground(settings, 120.0, false, over(TILE_SPOT.0, SHRINK_HEIGHTS[0]))?;
    spot_over_posts(&mut app, TILE_SPOT.0, TILE_SPOT.1);
    Ok(app)
}

/// The spot's misclassified share of the ground it reaches, worst of the camera's heights.
pub fn tile_shrink(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    m.subject(TILE_SHRINK, settings, tile_spot_scene)?;
    let mut worst = Score::default();
    for height in SHRINK_HEIGHTS {
        let (eye, target) = over(TILE_SPOT.0, height);
        let measured =
            measure_at(m, TILE_SHRINK, &format!("{height}"), |app| place_camera(&mut app.world, eye, target))?;
        let s = misclassified(&measured, 0, on_ground(&measured));
        if s.value() >= worst.value() {
            worst = s;
        }
    }
    Ok(worst)
}

/// One tile side of the shrink sweep: the misclassified share predicted and measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShrinkPoint {
    pub side: u32,
    pub predicted: f64,
    pub measured: f64,
}

/// The tile-shrink scene measured from the middle height with the spot's tile held at each of
/// `sides`, beside what [`predicted_share`] expects.
pub fn tile_shrink_sweep(
    m: &mut Measurer<'_>,
    settings: &Settings,
    sides: &[u32],
) -> Result<Vec<ShrinkPoint>, MeasureError> {
    let mut out = Vec::new();
    for &side in sides {
        let fixed = settings.clone().with(|s| {
            s.maps.tile_sizes = TileSizes::Fixed;
            s.maps.shadow_map_size = side;
        });
        m.subject(TILE_SHRINK, &fixed, tile_spot_scene)?;
        let (eye, target) = over(TILE_SPOT.0, SHRINK_HEIGHTS[1]);
        let measured = measure_at(m, TILE_SHRINK, "sweep", |app| place_camera(&mut app.world, eye, target))?;
        let texel = 2.0 * TILE_SPOT.0.y * TILE_SPOT.1.to_radians().tan() / side as f32;
        let measured_share = misclassified(&measured, 0, on_ground(&measured)).value();
        out.push(ShrinkPoint { side, predicted: predicted_share(&measured, texel), measured: measured_share });
    }
    Ok(out)
}

/// The misclassified share of the spot's ground if every true shadow edge were drawn up to half a
/// texel (`texel` metres on the ground) off, a quarter texel on average: the edges' length over
/// the ground the light reaches, from the truth of a frame seen from straight above (its edge
/// length from the pixel pairs it crosses, π/4 of a pixel each on average).
#[must_use]
pub fn predicted_share(measured: &Measured, texel: f32) -> f64 {
    let (frame, truth) = (&measured.frame, &measured.truth[0]);
    let width = frame.width as usize;
    let ground = on_ground(measured);
    let lit = |i: usize| truth.get(i).copied().flatten().filter(|_| ground(i)).map(|t| t.lit);
    let (mut crossings, mut reached, mut pixel) = (0usize, 0usize, 0.0f32);
    for i in 0..truth.len() {
        let Some(here) = lit(i) else { continue };
        reached += 1;
        for next in [(i % width + 1 < width).then_some(i + 1), Some(i + width)].into_iter().flatten() {
            if let Some(there) = lit(next) {
                crossings += usize::from(here != there);
                pixel = pixel.max(frame.position[i].distance(frame.position[next]));
            }
        }
    }
    let edge = crossings as f64 * std::f64::consts::FRAC_PI_4 * f64::from(pixel);
    let area = reached as f64 * f64::from(pixel).powi(2);
    if area > 0.0 { edge * f64::from(texel) / 4.0 / area } else { 0.0 }
}

/// The smallest side from which every larger side of `points` (in order) is within `threshold`;
/// and the side the prediction crosses it at (the share falls as one over the side).
#[must_use]
pub fn threshold_sides(points: &[ShrinkPoint], threshold: f64) -> (Option<u32>, Option<f64>) {
    let measured = points.iter().rev().take_while(|p| p.measured <= threshold).last().map(|p| p.side);
    let predicted = points.last().map(|p| f64::from(p.side) * p.predicted / threshold);
    (measured, predicted)
}

/// Frames the tile-resize camera creeps, and how far it swings either way (octaves of the
/// spot's wanted tile side round the edge between two classes).
const RESIZE_FRAMES: u32 = 16;
const RESIZE_SWING: f32 = 0.2;

/// The camera's height over the tile spot at which it wants a tile of `side` texels, out of
/// `largest` (by bisection over the coverage the atlas sizes tiles by).
fn height_wanting(app: &mut App, side: f32, largest: u32) -> f32 {
    let Some(light) = light_list(&app.world).into_iter().next() else { return SHRINK_HEIGHTS[0] };
    let tan = (Camera::default().fov_y * 0.5).tan();
    let want = side / largest as f32;
    let (mut low, mut high) = (TILE_SPOT.0.y + 0.5, 1000.0f32);
    for _ in 0..40 {
        let mid = 0.5 * (low + high);
        let (eye, target) = over(TILE_SPOT.0, mid);
        let covered = crate::systems::coverage(light.kind.reach(), (eye, (target - eye).normalize()), tan);
        if covered > want { low = mid } else { high = mid }
    }
    0.5 * (low + high)
}

/// Share of fixed ground points round the spot (every 3 cm) that flip lit/shadowed per frame as
/// the camera creeps up and down across the height where the spot's tile would change class.
pub fn tile_resize(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    m.subject(TILE_RESIZE, settings, tile_spot_scene)?;
    let points = ground_probes(
        (-95..=95)
            .flat_map(|i| (-95..=95).map(move |j| Vec3::new(i as f32 * 0.03, 0.0, j as f32 * 0.03)))
            .filter(|p| (0.6..2.8).contains(&p.length()))
            .map(|p| p + TILE_SPOT.0.with_y(0.0)),
    );
    let largest = settings.maps.shadow_map_size.max(1);
    // The edge between two classes, half an octave under the largest side.
    let edge = largest as f32 / 2f32.powf(1.5);
    flips(m, TILE_RESIZE, &points, RESIZE_FRAMES, |app, frame| {
        let swing = RESIZE_SWING * (frame as f32 * std::f32::consts::TAU / 6.0).sin();
        let height = height_wanting(app, edge * 2f32.powf(swing), largest);
        let (eye, target) = over(TILE_SPOT.0, height);
        place_camera(&mut app.world, eye, target);
    })
}

/// Spots (each over its own posts) sharing the starved budget, and the frames they are watched.
const STARVED_SPOTS: usize = 3;
const STARVED_FRAMES: u32 = 16;
/// Frames of sliding, after the first, whose redrawn texels make the budget.
const SHARE_FRAMES: u32 = 3;
/// How far the posts slide each frame, metres.
const STARVED_STEP: f32 = 0.04;

/// Three spots in a row, each over posts, seen from above between the first two (so each
/// shows a different share of the screen).
pub fn starved_scene(settings: &Settings) -> Result<App, crate::AppError> {
    let mut app = unlit_ground(settings, 120.0, false, over(Vec3::X * 3.5, 16.0))?;
    for k in 0..STARVED_SPOTS {
        spot_over_posts(&mut app, spot_at(k), 30.0);
    }
    Ok(app)
}

/// Puts the posts `steps` slides along +X from where the scene stood them (posts in the order
/// they were made, which is their homes' order).
fn slide_posts(app: &mut App, steps: u32) {
    let homes: Vec<Vec3> = (0..STARVED_SPOTS).flat_map(|k| post_homes(spot_at(k))).collect();
    let mut posts =
        app.world.query_filtered::<(bevy_ecs::entity::Entity, &mut Transform), bevy_ecs::query::With<ShadowCaster>>();
    let mut all: Vec<_> = posts.iter_mut(&mut app.world).collect();
    all.sort_by_key(|(e, _)| *e);
    for ((_, mut t), home) in all.into_iter().zip(homes) {
        t.translation = home + Vec3::X * STARVED_STEP * steps as f32;
    }
}

/// The starved scene's spot `k`.
fn spot_at(k: usize) -> Vec3 {
    Vec3::new(k as f32 * 5.5, 4.0, 0.0)
}

/// The misclassified share of the spots' ground while a budget of a third of what a slide
/// draws a frame (one spot's share) serves three spots whose posts all slide every frame; a spot
/// left waiting longer than [`MAX_STALE`] frames and a turn of the budget is garbage (the promise
/// broken).
pub fn starved_budget(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    // Everything drawn where the posts start, then the texels a slide redraws with no budget once
    // the first has placed what it needs: three spots' tiles of the atlas, or the pages the posts
    // cross however small pages are.
    let unlimited = settings.clone().with(|s| s.maps.shadow_updates = 0);
    let app = &mut m.subject(STARVED, &unlimited, starved_scene)?.app;
    slide_posts(app, 0);
    measure_at(m, STARVED, "start", |_| {})?;
    measure_at(m, STARVED, "1", |app| slide_posts(app, 1))?;
    let mut slid = 0;
    for frame in 2..=SHARE_FRAMES + 1 {
        measure_at(m, STARVED, &format!("{frame}"), |app| slide_posts(app, frame))?;
        slid += m.parts(STARVED)?.0.world.resource::<ShadowStats>().texels;
    }
    let share = slid / u64::from(SHARE_FRAMES) / STARVED_SPOTS as u64;
    let budget = u32::try_from(share).unwrap_or(u32::MAX).max(crate::settings::MIN_SHADOW_UPDATES);
    let starved = settings.clone().with(|s| s.maps.shadow_updates = budget);
    m.subject(STARVED, &starved, starved_scene)?;
    let mut score = Score::default();
    for frame in 1..=STARVED_FRAMES {
        let measured = measure_at(m, STARVED, &format!("{frame}"), |app| slide_posts(app, frame))?;
        for light in 0..STARVED_SPOTS {
            score.add(misclassified(&measured, light, on_ground(&measured)));
        }
        let (app, _) = m.parts(STARVED)?;
        let waited = app.world.resource::<ShadowStats>().waited();
        score.garbage += u64::from(waited > MAX_STALE + STARVED_SPOTS as u32);
    }
    Ok(score)
}
