//! Light views and the spot light's projection (the sun's cascades are in `cascade`).

use glam::camera::rh::{proj::directx, view::look_to_mat4};
use glam::{Mat4, Vec3};

/// A light's view and projection, with the size of one shadow-map texel in world units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightProjection {
    /// World to light view space.
    pub view: Mat4,
    /// Light view space to clip space (depth 0..1).
    pub proj: Mat4,
    /// `proj * view`.
    pub view_proj: Mat4,
    /// World size of one texel: `texel.x + texel.y * distance from the light`.
    pub texel: glam::Vec2,
}

/// How a projection (right-handed, depth 0..1) turns distance along the view axis into depth:
/// `(z_axis.z, w_axis.z)` of its matrix, with which [`view_distance`] undoes it.
#[must_use]
pub fn depth_terms(proj: &Mat4) -> glam::Vec2 {
    glam::Vec2::new(proj.z_axis.z, proj.w_axis.z)
}

/// The distance along the view axis of depth `z` (0..1) of a projection with [`depth_terms`]
/// `terms`: an orthographic one maps it linearly, a perspective one by its reciprocal. The WGSL
/// twin is `view_distance` in shadow_sampling.wgsl.
#[must_use]
pub fn view_distance(terms: glam::Vec2, z: f32, perspective: bool) -> f32 {
    if perspective { terms.y / (z + terms.x) } else { (terms.y - z) / terms.x }
}

/// Widest spot cone (half angle), as glTF allows: a hemisphere.
pub const MAX_SPOT_HALF_ANGLE: f32 = std::f32::consts::FRAC_PI_2;
/// Narrowest spot cone (half angle).
pub const MIN_SPOT_HALF_ANGLE: f32 = 0.5 * std::f32::consts::PI / 180.0;
/// Widest spot cone (half angle) one perspective shadow map holds; a wider spot is shadowed
/// through a cube, as a point light is. At 60° a texel at the rim of the map is already four
/// times the size of one at its centre (1 / cos² 60°).
pub const MAX_MAP_HALF_ANGLE: f32 = 60.0 * std::f32::consts::PI / 180.0;

/// A spot's cone as every part of umbra uses it (lighting, shadows, cookie and truth alike):
/// the outer half angle clamped to [`MIN_SPOT_HALF_ANGLE`]..[`MAX_SPOT_HALF_ANGLE`] (a
/// non-number takes the widest) and the inner one to 0..outer. Returns (inner, outer).
#[must_use]
pub fn spot_cone(inner: f32, outer: f32) -> (f32, f32) {
    let outer =
        if outer.is_nan() { MAX_SPOT_HALF_ANGLE } else { outer.clamp(MIN_SPOT_HALF_ANGLE, MAX_SPOT_HALF_ANGLE) };
    let inner = if inner.is_nan() { 0.0 } else { inner.clamp(0.0, outer) };
    (inner, outer)
}

/// Distance at which a light of range `range` is cut off (a non-number or nonsense range takes
/// 1 km; a tiny one 10 cm).
#[must_use]
pub fn light_range(range: f32) -> f32 {
    if range.is_finite() { range.max(0.1) } else { 1000.0 }
}

/// Directions of the six cube faces, in the order of a cube's layers: +X, -X, +Y, -Y, +Z, -Z.
pub const CUBE_FACES: [Vec3; 6] = [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z];

/// The cube face (index into [`CUBE_FACES`]) that holds direction `d`: its largest axis.
#[must_use]
pub fn cube_face(d: Vec3) -> usize {
    let a = d.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    axis * 2 + (d[axis] < 0.0) as usize
}

/// The six faces of a point light's shadow cube (or a wide spot's): perspective projections from
/// `position` along [`CUBE_FACES`], out to `range`. Each face reaches `margin` texels past the
/// 90° edge, so a filter sampling next to a seam still finds texels on the face it looks in.
#[must_use]
pub fn cube_projections(position: Vec3, range: f32, resolution: u32, margin: u32) -> [LightProjection; 6] {
    std::array::from_fn(|face| cube_face_projection(position, range, resolution, margin, face))
}

/// Face `face` (an index into [`CUBE_FACES`]; past the last, the last) of
/// [`cube_projections`].
#[must_use]
pub fn cube_face_projection(position: Vec3, range: f32, resolution: u32, margin: u32, face: usize) -> LightProjection {
    let res = resolution.max(1) as f32;
    let tan_half = 1.0 + 2.0 * margin as f32 / res;
    let far = light_range(range);
    let near = near_plane(far);
    let proj = directx::perspective(2.0 * tan_half.atan(), 1.0, near, far);
    let texel = glam::Vec2::new(0.0, 2.0 * tan_half / res);
    let view = light_view(position, CUBE_FACES[face.min(CUBE_FACES.len() - 1)]);
    LightProjection { view, proj, view_proj: proj * view, texel }
}

/// A view matrix at `eye` looking along `dir`, valid for every direction.
///
/// A look-at with a fixed up vector breaks when the direction is parallel to it (a sun straight
/// overhead), so the up vector is chosen from the direction: world Y unless the light looks
/// (nearly) straight up or down, then world Z. A zero or non-finite direction means straight down.
pub fn light_view(eye: Vec3, dir: Vec3) -> Mat4 {
    let dir = dir.try_normalize().unwrap_or(Vec3::NEG_Y);
    let up = if dir.y.abs() > 0.9 { Vec3::Z } else { Vec3::Y };
    look_to_mat4(eye, dir, up)
}

/// The near plane of a spot's or a cube face's projection whose far plane is `far`: a small
/// fraction of it, so depth precision goes where the receivers are, but never nearer than 2 cm.
#[must_use]
pub fn near_plane(far: f32) -> f32 {
    (far * 0.005).max(0.02)
}

/// A spot light's perspective projection: the cone's outer angle, near/far from its range.
///
/// The half angle is the cone's ([`spot_cone`]), held to below 90° so the projection exists (a
/// spot wider than [`MAX_MAP_HALF_ANGLE`] is shadowed through a cube; this projection then only
/// carries its cookie). The near plane is a small fraction of the range so depth precision is
/// spent where the light reaches.
pub fn spot_projection(
    position: Vec3,
    direction: Vec3,
    outer_half_angle: f32,
    range: f32,
    resolution: u32,
) -> LightProjection {
    let half = spot_cone(0.0, outer_half_angle).1.min(89.0f32.to_radians());
    let far = light_range(range);
    let near = near_plane(far);
    let view = light_view(position, direction);
    let proj = directx::perspective(2.0 * half, 1.0, near, far);
    let texel = 2.0 * half.tan() / resolution.max(1) as f32;
    LightProjection { view, proj, view_proj: proj * view, texel: glam::Vec2::new(0.0, texel) }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn in_clip(m: &Mat4, p: Vec3) -> bool {
        let c = *m * p.extend(1.0);
        let n = c.truncate() / c.w;
        c.w > 0.0 && n.x.abs() <= 1.0 + 1e-4 && n.y.abs() <= 1.0 + 1e-4 && (-1e-4..=1.0 + 1e-4).contains(&n.z)
    }

    #[test]
    fn view_distance_undoes_both_kinds_of_projection() {
        let cases = [
            (directx::perspective(1.2, 1.0, 0.05, 20.0), true),
            (directx::orthographic(-5.0, 5.0, -5.0, 5.0, -3.0, 40.0), false),
        ];
        for (proj, perspective) in cases {
            for d in [0.05f32, 0.5, 3.0, 19.9] {
                let z = proj.project_point3(Vec3::new(0.3, -0.2, -d)).z;
                let back = view_distance(depth_terms(&proj), z, perspective);
                assert!((back - d).abs() < 1e-3 * d.max(1.0), "{perspective}: {d} came back as {back}");
            }
        }
    }

    #[test]
    fn light_view_is_finite_looking_straight_down_and_up() {
        for d in [Vec3::NEG_Y, Vec3::Y, Vec3::X, Vec3::NEG_X, Vec3::Z, Vec3::NEG_Z, Vec3::ZERO] {
            let v = light_view(Vec3::ZERO, d);
            assert!(v.is_finite() && v.determinant().abs() > 0.5, "{d:?}");
        }
    }

    #[test]
    fn light_view_forward_is_the_direction() {
        let d = Vec3::new(0.3, -0.8, 0.2).normalize();
        let v = light_view(Vec3::ZERO, d);
        // A point ahead along the direction sits on the -Z axis of light space.
        let p = v.transform_point3(d * 5.0);
        assert!((p - Vec3::new(0.0, 0.0, -5.0)).length() < 1e-5);
    }

    #[test]
    fn spot_projection_covers_its_cone_and_cuts_behind() {
        let pos = Vec3::new(0.0, 5.0, 0.0);
        let fit = spot_projection(pos, Vec3::NEG_Y, 0.5, 10.0, 512);
        // A point on the axis inside the range is inside; one behind the light is not.
        assert!(in_clip(&fit.view_proj, Vec3::new(0.0, 1.0, 0.0)));
        assert!(!in_clip(&fit.view_proj, Vec3::new(0.0, 7.0, 0.0)));
        // A point just inside the cone's edge is inside the map.
        let edge = pos + Vec3::new((0.49f32).tan() * 4.0, -4.0, 0.0);
        assert!(in_clip(&fit.view_proj, edge));
        assert!(fit.texel.y > 0.0 && fit.texel.x == 0.0);
    }

    #[test]
    fn one_clamp_holds_every_cone() {
        assert_eq!(spot_cone(0.2, 0.4), (0.2, 0.4));
        assert_eq!(spot_cone(0.5, 0.4), (0.4, 0.4), "inner never beyond outer");
        assert_eq!(spot_cone(0.1, 3.0).1, MAX_SPOT_HALF_ANGLE);
        assert_eq!(spot_cone(0.1, -1.0).1, MIN_SPOT_HALF_ANGLE);
        assert_eq!(spot_cone(f32::NAN, f32::NAN), (0.0, MAX_SPOT_HALF_ANGLE));
        assert_eq!(spot_cone(0.0, f32::INFINITY).1, MAX_SPOT_HALF_ANGLE);
    }

    #[test]
    fn every_direction_lands_inside_its_cube_face() {
        let faces = cube_projections(Vec3::new(1.0, 2.0, 3.0), 20.0, 64, 2);
        let mut state = 0x9e3779b97f4a7c15u64;
        for _ in 0..2000 {
            let mut next = || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 11) as f32 / (1u64 << 53) as f32 * 2.0 - 1.0
            };
            let d = Vec3::new(next(), next(), next());
            if d.length() < 1e-3 {
                continue;
            }
            let p = Vec3::new(1.0, 2.0, 3.0) + d.normalize() * 5.0;
            let face = cube_face(d);
            assert!(in_clip(&faces[face].view_proj, p), "{d:?} on face {face}");
            // With a margin, a point just past the face's edge is inside too.
        }
        assert_eq!(cube_face(Vec3::new(0.2, -0.9, 0.1)), 3);
        assert_eq!(cube_face(Vec3::new(0.0, 0.0, -1.0)), 5);
        // The margin reaches two texels past the 90° edge: a direction 1 texel beyond a face's
        // edge (towards the next face) is still inside it.
        let past = Vec3::new(1.0, 1.0 + 2.0 / 64.0, 0.0);
        assert!(in_clip(&faces[0].view_proj, Vec3::new(1.0, 2.0, 3.0) + past));
        assert!(faces.iter().all(|f| f.view_proj.is_finite()));
    }

    #[test]
    fn spot_projection_survives_nonsense_angles() {
        for a in [0.0, -1.0, 3.0, f32::NAN, f32::INFINITY] {
            let fit = spot_projection(Vec3::ZERO, Vec3::X, a, f32::NAN, 256);
            assert!(fit.view_proj.is_finite(), "angle {a}");
        }
    }
}
