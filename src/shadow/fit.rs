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

/// Widest spot cone a shadow map can cover (half angle); wider cones are clamped.
pub const MAX_SPOT_HALF_ANGLE: f32 = 85.0 * std::f32::consts::PI / 180.0;
/// Narrowest spot cone (half angle); narrower cones are clamped.
pub const MIN_SPOT_HALF_ANGLE: f32 = 0.5 * std::f32::consts::PI / 180.0;

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

/// A spot light's perspective projection: the cone's outer angle, near/far from its range.
///
/// The half angle is clamped to what one map can cover; the near plane is a small fraction of the
/// range so depth precision is spent where the light reaches.
pub fn spot_projection(
    position: Vec3,
    direction: Vec3,
    outer_half_angle: f32,
    range: f32,
    resolution: u32,
) -> LightProjection {
    let half = if outer_half_angle.is_finite() {
        outer_half_angle.clamp(MIN_SPOT_HALF_ANGLE, MAX_SPOT_HALF_ANGLE)
    } else {
        MAX_SPOT_HALF_ANGLE
    };
    let far = if range.is_finite() { range.max(0.1) } else { 1000.0 };
    let near = (far * 0.005).max(0.02);
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
    fn spot_projection_survives_nonsense_angles() {
        for a in [0.0, -1.0, 3.0, f32::NAN, f32::INFINITY] {
            let fit = spot_projection(Vec3::ZERO, Vec3::X, a, f32::NAN, 256);
            assert!(fit.view_proj.is_finite(), "angle {a}");
        }
    }
}
