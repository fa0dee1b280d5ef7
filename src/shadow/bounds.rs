//! Axis-aligned boxes and frustum corners.

use glam::{Mat4, Vec3};

/// Farthest from the origin, in metres, that a box may reach and still be fitted into shadow
/// maps: beyond it (or not finite at all) the box is a broken object, not part of the scene.
pub const MAX_WORLD_EXTENT: f32 = 1.0e5;

/// An axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Aabb {
    /// The empty box: growing it by any point gives that point.
    pub const EMPTY: Aabb = Aabb { min: Vec3::INFINITY, max: Vec3::NEG_INFINITY };

    /// A box from two corners given in any order.
    pub fn new(a: Vec3, b: Vec3) -> Aabb {
        Aabb { min: a.min(b), max: a.max(b) }
    }

    /// The smallest box holding all `points` (the empty box for none).
    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Aabb {
        points.into_iter().fold(Aabb::EMPTY, |b, p| b.grow(p))
    }

    /// This box grown to hold `p`.
    pub fn grow(self, p: Vec3) -> Aabb {
        Aabb { min: self.min.min(p), max: self.max.max(p) }
    }

    /// The smallest box holding both boxes.
    pub fn union(self, other: Aabb) -> Aabb {
        Aabb { min: self.min.min(other.min), max: self.max.max(other.max) }
    }

    /// True when the box holds points and lies within [`MAX_WORLD_EXTENT`] of the origin: a box
    /// light fitting can use.
    #[must_use]
    pub fn is_usable(&self) -> bool {
        let finite = self.min.is_finite() && self.max.is_finite();
        finite && !self.is_empty() && self.min.abs().max(self.max.abs()).max_element() <= MAX_WORLD_EXTENT
    }

    /// True when the box holds no point.
    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// Centre point.
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// The eight corners.
    pub fn corners(&self) -> [Vec3; 8] {
        let (a, b) = (self.min, self.max);
        [
            Vec3::new(a.x, a.y, a.z),
            Vec3::new(b.x, a.y, a.z),
            Vec3::new(a.x, b.y, a.z),
            Vec3::new(b.x, b.y, a.z),
            Vec3::new(a.x, a.y, b.z),
            Vec3::new(b.x, a.y, b.z),
            Vec3::new(a.x, b.y, b.z),
            Vec3::new(b.x, b.y, b.z),
        ]
    }

    /// The box around this box after an affine transform.
    pub fn transformed(&self, m: &Mat4) -> Aabb {
        Aabb::from_points(self.corners().map(|c| m.transform_point3(c)))
    }

    /// True when the two boxes share at least one point.
    pub fn intersects(&self, other: &Aabb) -> bool {
        self.min.cmple(other.max).all() && other.min.cmple(self.max).all()
    }
}

/// World-space corners of the volume that `view_proj` maps onto clip space (depth 0..1).
///
/// Near corners come first, in the same x/y order as the far ones.
pub fn frustum_corners(view_proj: &Mat4) -> [Vec3; 8] {
    let inv = view_proj.inverse();
    let mut out = [Vec3::ZERO; 8];
    for (i, corner) in out.iter_mut().enumerate() {
        let x = if i & 1 == 0 { -1.0 } else { 1.0 };
        let y = if i & 2 == 0 { -1.0 } else { 1.0 };
        let z = if i & 4 == 0 { 0.0 } else { 1.0 };
        *corner = inv.project_point3(Vec3::new(x, y, z));
    }
    out
}

/// True unless the box lies wholly outside one plane of the clip volume of `view_proj` (x and y in
/// -w..w, depth in 0..w): a conservative test, exact for boxes that are small against the volume.
///
/// Works in homogeneous coordinates, so corners behind a perspective light are handled without a
/// divide. Used to cull casters per shadow-map layer and to find which layers a moved caster dirties.
pub fn intersects_clip_volume(view_proj: &Mat4, b: &Aabb) -> bool {
    if b.is_empty() {
        return false;
    }
    let clip = b.corners().map(|c| *view_proj * c.extend(1.0));
    let planes: [fn(glam::Vec4) -> f32; 6] =
        [|c| c.w - c.x, |c| c.w + c.x, |c| c.w - c.y, |c| c.w + c.y, |c| c.z, |c| c.w - c.z];
    planes.iter().all(|plane| clip.iter().any(|c| plane(*c) >= 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_finite_boxes_within_the_world_are_usable() {
        assert!(Aabb::new(Vec3::splat(-1.0), Vec3::ONE).is_usable());
        assert!(Aabb::new(Vec3::ZERO, Vec3::ZERO).is_usable(), "a point is a box");
        assert!(!Aabb::EMPTY.is_usable());
        assert!(!Aabb::new(Vec3::ZERO, Vec3::new(f32::NAN, 1.0, 1.0)).is_usable());
        assert!(!Aabb { min: Vec3::splat(f32::NAN), max: Vec3::splat(f32::NAN) }.is_usable());
        assert!(!Aabb::new(Vec3::ZERO, Vec3::splat(f32::INFINITY)).is_usable());
        assert!(!Aabb::new(Vec3::ZERO, Vec3::new(0.0, 2.0 * MAX_WORLD_EXTENT, 0.0)).is_usable());
    }

    #[test]
    fn grow_and_union_hold_their_inputs() {
        let b = Aabb::from_points([Vec3::new(1.0, -2.0, 3.0), Vec3::new(-1.0, 4.0, 0.0)]);
        assert_eq!(b.min, Vec3::new(-1.0, -2.0, 0.0));
        assert_eq!(b.max, Vec3::new(1.0, 4.0, 3.0));
        assert!(Aabb::EMPTY.is_empty());
        assert!(!b.is_empty());
        assert_eq!(Aabb::EMPTY.union(b), b);
    }

    #[test]
    fn intersects_is_symmetric_and_touching_counts() {
        let a = Aabb::new(Vec3::ZERO, Vec3::ONE);
        let b = Aabb::new(Vec3::ONE, Vec3::splat(2.0));
        let c = Aabb::new(Vec3::splat(1.5), Vec3::splat(2.0));
        assert!(a.intersects(&b) && b.intersects(&a));
        assert!(!a.intersects(&c) && !c.intersects(&a));
    }

    #[test]
    fn transformed_box_holds_rotated_corners() {
        let a = Aabb::new(Vec3::splat(-1.0), Vec3::ONE);
        let m = Mat4::from_rotation_y(0.7) * Mat4::from_translation(Vec3::X * 3.0);
        let t = a.transformed(&m);
        for c in a.corners() {
            let p = m.transform_point3(c);
            assert!(p.cmpge(t.min - 1e-5).all() && p.cmple(t.max + 1e-5).all());
        }
    }

    #[test]
    fn clip_volume_test_keeps_what_is_inside_and_drops_what_is_beside_or_behind() {
        let ortho = glam::camera::rh::proj::directx::orthographic(-2.0, 2.0, -2.0, 2.0, 1.0, 10.0);
        let inside = Aabb::new(Vec3::new(-0.5, -0.5, -3.0), Vec3::new(0.5, 0.5, -2.0));
        let straddling = Aabb::new(Vec3::new(1.5, -0.5, -3.0), Vec3::new(4.0, 0.5, -2.0));
        let beside = Aabb::new(Vec3::new(2.5, -0.5, -3.0), Vec3::new(4.0, 0.5, -2.0));
        let behind = Aabb::new(Vec3::new(-0.5, -0.5, 1.0), Vec3::new(0.5, 0.5, 3.0));
        assert!(intersects_clip_volume(&ortho, &inside));
        assert!(intersects_clip_volume(&ortho, &straddling));
        assert!(!intersects_clip_volume(&ortho, &beside));
        assert!(!intersects_clip_volume(&ortho, &behind));
        assert!(!intersects_clip_volume(&ortho, &Aabb::EMPTY));
        let persp = glam::camera::rh::proj::directx::perspective(1.0, 1.0, 0.1, 10.0);
        assert!(intersects_clip_volume(&persp, &inside));
        assert!(!intersects_clip_volume(&persp, &behind), "behind a perspective light is outside");
    }

    #[test]
    fn frustum_corners_of_an_ortho_box_are_its_corners() {
        let proj = glam::camera::rh::proj::directx::orthographic(-2.0, 2.0, -1.0, 1.0, 0.5, 10.0);
        let c = frustum_corners(&proj);
        assert!((c[0] - Vec3::new(-2.0, -1.0, -0.5)).length() < 1e-5);
        assert!((c[7] - Vec3::new(2.0, 1.0, -10.0)).length() < 1e-4);
    }
}
