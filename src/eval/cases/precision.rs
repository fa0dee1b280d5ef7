//! The precision case: walls facing a spot light at 1 m to 32 m, each a receiver whose depth the
//! map must hold to within the bias. A depth format's rounding grows with distance (a 16-bit
//! fixed-point perspective depth's with its square, a half float's in proportion), and where it
//! outgrows the bias the lit walls shadow themselves.
//!
//! For `Depth16Unorm` the distance is predicted: a perspective depth `z = f/(f-n)·(1 - n/d)`
//! kept in steps of 1/65535 is off by up to `d² / (2·65535·n)` metres (f much larger than n),
//! while the default bias (half a texel constant and half a texel along the normal, which here
//! faces the light) is one texel, `d · 2·tan(outer) / size`. Acne starts where the first
//! outgrows the second: [`d16_acne_distance`].

use super::scenes::add_block;
use super::{Score, measure_at};
use crate::App;
use crate::components::{ShadowMap, SpotLight, Transform};
use crate::eval::measure::{CaseScene, MeasureError, Measurer, SubjectId};
use crate::eval::metrics::rendered;
use crate::scene::camera_looking;
use crate::settings::Settings;
use glam::Vec3;

const PRECISION: SubjectId = SubjectId::Case(CaseScene::Precision);

/// Where the spot hangs; it shines along -Z.
const LAMP: Vec3 = Vec3::new(0.0, 1.0, 0.0);
/// The spot's outer half angle.
const OUTER: f32 = 0.5;
/// The spot's range (its map's far plane).
const RANGE: f32 = 60.0;
/// Distances of the walls from the lamp, in metres.
pub const WALL_DISTANCES: [f32; 6] = [1.0, 2.0, 4.0, 8.0, 16.0, 32.0];
/// Half the angle each wall covers as the lamp sees it, and the angle between neighbours' centres.
const WALL_HALF_ANGLE: f32 = 0.06;
const WALL_SPACING: f32 = 0.16;

/// The map's near plane for a spot of `RANGE`.
fn near() -> f32 {
    crate::shadow::near_plane(crate::shadow::light_range(RANGE))
}

/// The distance beyond which a `Depth16Unorm` map of `size` texels rounds a wall's depth by more
/// than the default bias (see the module's notes).
#[must_use]
pub fn d16_acne_distance(size: u32) -> f32 {
    let texel_per_metre = 2.0 * OUTER.tan() / size as f32;
    2.0 * 65535.0 * near() * texel_per_metre
}

/// The unit direction from the lamp to wall `i`'s centre: the walls fan out across the cone.
fn wall_direction(i: usize) -> Vec3 {
    let a = (i as f32 - (WALL_DISTANCES.len() - 1) as f32 / 2.0) * WALL_SPACING;
    Vec3::new(a.sin(), 0.0, -a.cos())
}

/// The walls, each square to the light, none hiding another, and the spot; seen from just
/// behind and above the lamp.
fn precision_scene(settings: &Settings) -> Result<App, crate::AppError> {
    let mut app = App::empty(settings.clone())?;
    for (i, &d) in WALL_DISTANCES.iter().enumerate() {
        let dir = wall_direction(i);
        let half = d * WALL_HALF_ANGLE.tan();
        // A slab 0.1 half-widths thick whose near face lies d from the lamp.
        let at = Transform::from_translation(LAMP + dir * (d + 0.05 * half)).looking_to(dir);
        add_block(&mut app, at.with_scale(Vec3::new(2.0 * half, 2.0 * half, 0.1 * half)));
    }
    let spot =
        SpotLight { range: RANGE, intensity: 4.0, inner_angle: OUTER - 0.05, outer_angle: OUTER, ..Default::default() };
    app.world.spawn((spot, Transform::from_translation(LAMP).looking_to(Vec3::NEG_Z), ShadowMap::default()));
    app.world.spawn(camera_looking(LAMP + Vec3::new(0.0, 0.3, 0.5), LAMP + Vec3::new(0.0, 0.0, -10.0)));
    Ok(app)
}

/// The wall a surface point at `p` with normal `n` lies on the lit face of, if any.
fn wall_of(p: Vec3, n: Vec3) -> Option<usize> {
    (0..WALL_DISTANCES.len()).find(|&i| {
        let dir = wall_direction(i);
        let d = WALL_DISTANCES[i];
        n.dot(-dir) > 0.99 && ((p - LAMP).dot(dir) - d).abs() < 0.01 * d
    })
}

/// Per wall (nearest first), how much of its lit face the spot's map shadows: every pixel of it
/// is truly lit, so `hits` counts false shadow (and any false lit, which nothing here can cause).
pub fn precision_by_distance(m: &mut Measurer<'_>, settings: &Settings) -> Result<Vec<Score>, MeasureError> {
    m.subject(PRECISION, settings, precision_scene)?;
    let measured = measure_at(m, PRECISION, "walls", |_| {})?;
    let mut scores = vec![Score::default(); WALL_DISTANCES.len()];
    for (i, t) in measured.truth[0].iter().enumerate() {
        let (p, n) = (measured.frame.position[i].truncate(), measured.frame.normal[i].truncate());
        if let (Some(t), Some(r), Some(wall)) = (t, rendered(&measured.frame, 0, i), wall_of(p, n)) {
            scores[wall].of += 1;
            scores[wall].hits += ((r < 0.5) == t.lit) as u64;
        }
    }
    Ok(scores)
}

/// The precision case: the worst wall's share (a format fails at its far end, so the share of
/// all walls would hide it).
pub fn precision(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    let scores = precision_by_distance(m, settings)?;
    Ok(scores.into_iter().max_by(|a, b| a.value().total_cmp(&b.value())).unwrap_or_default())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_walls_fit_the_cone_and_do_not_overlap() {
        let last = wall_direction(WALL_DISTANCES.len() - 1);
        assert!(last.x.atan2(-last.z) + WALL_HALF_ANGLE < OUTER);
        const { assert!(2.0 * WALL_HALF_ANGLE < WALL_SPACING) };
    }

    #[test]
    fn d16_acne_starts_between_the_two_farthest_walls_at_2048() {
        let d = d16_acne_distance(2048);
        assert!(d > 16.0 && d < 32.0, "{d}");
    }
}
