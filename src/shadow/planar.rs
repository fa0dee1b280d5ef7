//! Planar projected shadows (Blinn 1988, "Me and my (fake) shadow"; seed 004 draws them with the
//! stencil buffer): every caster flattened onto one receiving plane along the rays from the
//! light, drawn over the plane as that light's shadow. Exact on the plane, absent everywhere else.

use glam::{Mat4, Vec4};

/// The plane planar shadows fall on, as (normal, d) with `normal · p + d = 0`: the ground, y = 0.
pub const GROUND_PLANE: Vec4 = Vec4::new(0.0, 1.0, 0.0, 0.0);

/// How far above the plane flattened casters are drawn, in metres: enough that the depth test
/// does not mix them up with the plane itself (z-fighting), too little to see.
pub const PLANAR_LIFT: f32 = 0.005;

/// True when `light` (homogeneous) lies on the lit side of `plane`: a lamp above the ground, a sun
/// shining down onto it. Otherwise it throws no planar shadow at all.
#[must_use]
pub fn lights_plane(plane: Vec4, light: Vec4) -> bool {
    plane.dot(light) > 1e-6
}

/// The planar projection ("shadow matrix") onto `plane` from `light`: `(plane · light) I - light
/// planeᵀ`. It takes a world point `p` (w = 1) to where the ray from the light through `p` meets
/// the plane, in homogeneous form; the result's w is `plane · light - (plane · p) light.w`, which
/// for a lamp is its height above the plane less the point's (negative for points above the lamp,
/// which cast nothing down) and for a sun a positive constant.
#[must_use]
pub fn flat_from_world(plane: Vec4, light: Vec4) -> Mat4 {
    let outer = Mat4::from_cols(light * plane.x, light * plane.y, light * plane.z, light * plane.w);
    Mat4::from_diagonal(Vec4::splat(plane.dot(light))) - outer
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn flatten(m: &Mat4, p: Vec3) -> (Vec3, f32) {
        let h = *m * p.extend(1.0);
        (h.truncate() / h.w, h.w)
    }

    #[test]
    fn a_lamp_flattens_points_onto_the_plane_along_its_rays() {
        let lamp = Vec3::new(1.0, 4.0, -2.0);
        let m = flat_from_world(GROUND_PLANE, lamp.extend(1.0));
        for p in [Vec3::new(0.0, 1.0, 0.0), Vec3::new(3.0, 2.5, 1.0), Vec3::new(-5.0, 0.01, 7.0)] {
            let (q, w) = flatten(&m, p);
            assert!(q.y.abs() < 1e-5, "{q} is on the plane");
            assert!((q - lamp).normalize().abs_diff_eq((p - lamp).normalize(), 1e-5), "{q} is on the ray through {p}");
            assert!((w - (lamp.y - p.y)).abs() < 1e-5);
        }
        // A point on the plane stays where it is; one above the lamp gets a negative w.
        assert!(flatten(&m, Vec3::new(2.0, 0.0, 3.0)).0.abs_diff_eq(Vec3::new(2.0, 0.0, 3.0), 1e-5));
        assert!(flatten(&m, Vec3::new(0.0, 5.0, 0.0)).1 < 0.0);
    }

    #[test]
    fn a_sun_flattens_every_point_along_its_direction() {
        let direction = Vec3::new(1.0, -2.0, 0.5).normalize();
        let m = flat_from_world(GROUND_PLANE, (-direction).extend(0.0));
        let p = Vec3::new(0.5, 3.0, -1.0);
        let (q, w) = flatten(&m, p);
        assert!(w > 0.0);
        assert!(q.y.abs() < 1e-5);
        assert!((q - p).normalize().abs_diff_eq(direction, 1e-5));
    }

    #[test]
    fn lights_below_the_plane_or_suns_shining_up_throw_none() {
        assert!(lights_plane(GROUND_PLANE, Vec3::new(0.0, 2.0, 0.0).extend(1.0)));
        assert!(!lights_plane(GROUND_PLANE, Vec3::new(0.0, -1.0, 0.0).extend(1.0)));
        assert!(!lights_plane(GROUND_PLANE, Vec3::ZERO.extend(1.0)));
        assert!(lights_plane(GROUND_PLANE, (-Vec3::NEG_Y).extend(0.0)));
        assert!(!lights_plane(GROUND_PLANE, (-Vec3::Y).extend(0.0)));
        assert!(!lights_plane(GROUND_PLANE, (-Vec3::X).extend(0.0)), "a grazing sun");
        assert!(!lights_plane(GROUND_PLANE, (-Vec3::NAN).extend(0.0)), "no number, no shadow");
    }
}
