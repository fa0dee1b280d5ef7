//! Axis-aligned boxes and frustum corners.

use glam::{Mat4, Vec3, Vec4};

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
        // Three comparisons that each fail on NaN: -extent <= min <= max <= extent.
        let extent = Vec3::splat(MAX_WORLD_EXTENT);
        self.min.cmpge(-extent).all() && self.min.cmple(self.max).all() && self.max.cmple(extent).all()
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

    /// The box around this box after an affine transform: its centre carried over, and its
    /// half extent through the absolute values of the matrix (two products, not eight corners).
    #[must_use]
    pub fn transformed(&self, m: &Mat4) -> Aabb {
        if self.is_empty() {
            return Aabb::EMPTY;
        }
        // In the matrix's four-wide columns, so that each line is one SIMD operation.
        let (c, half) = (self.center(), (self.max - self.min) * 0.5);
        let centre = m.x_axis * c.x + m.y_axis * c.y + m.z_axis * c.z + m.w_axis;
        let reach = m.x_axis.abs() * half.x + m.y_axis.abs() * half.y + m.z_axis.abs() * half.z;
        Aabb { min: (centre - reach).truncate(), max: (centre + reach).truncate() }
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
#[must_use]
pub fn intersects_clip_volume(view_proj: &Mat4, b: &Aabb) -> bool {
    ClipVolume::new(view_proj).intersects(b)
}

/// The six planes of a clip volume (x and y in -w..w, depth in 0..w) carried back into world
/// space, for testing many boxes against one volume: each plane costs two dot products per box
/// (its farthest corner along the plane's normal), where carrying the box's eight corners into
/// clip space costs eight matrix products.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClipVolume {
    /// Each plane as (normal, offset): a world point p is on the inside where normal·p + offset ≥ 0.
    planes: [Vec4; 6],
}

impl ClipVolume {
    /// The planes of the clip volume of `clip_from_world`.
    #[must_use]
    pub fn new(clip_from_world: &Mat4) -> Self {
        let [x, y, z, w] = [0, 1, 2, 3].map(|i| clip_from_world.row(i));
        ClipVolume { planes: [w - x, w + x, w - y, w + y, z, w - z] }
    }

    /// True unless `b` lies wholly outside one of the planes (false for an empty box).
    #[must_use]
    pub fn intersects(&self, b: &Aabb) -> bool {
        if b.is_empty() {
            return false;
        }
        let (centre, half) = (b.center(), (b.max - b.min) * 0.5);
        self.planes.iter().all(|p| {
            let n = p.truncate();
            n.dot(centre) + n.abs().dot(half) + p.w >= 0.0
        })
    }
}

/// How near to the eye of a perspective projection (`clip_from_world`, whose clip w is the depth
/// along its axis) any of `boxes` comes: the least w of their corners, at least 0; `None` for no
/// box, and 0 for a box that is not usable (where it is is unknown). A blocker's penumbra is
/// widest the nearer it is to the light, so this bounds how wide any of theirs can be.
#[must_use]
pub fn nearest_depth<'a>(clip_from_world: &Mat4, boxes: impl IntoIterator<Item = &'a Aabb>) -> Option<f32> {
    boxes.into_iter().fold(None, |nearest: Option<f32>, b| {
        let depth = if b.is_usable() {
            b.corners().iter().map(|&c| (*clip_from_world * c.extend(1.0)).w).fold(f32::INFINITY, f32::min).max(0.0)
        } else {
            0.0
        };
        Some(nearest.map_or(depth, |n| n.min(depth)))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_nearest_depth_is_the_nearest_corner_along_the_axis() {
        use glam::camera::rh::{proj::directx, view::look_to_mat4};
        // Looking down -Z from the origin.
        let clip_from_world =
            directx::perspective(1.2, 1.0, 0.05, 20.0) * look_to_mat4(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y);
        let far = Aabb::new(Vec3::new(-0.5, -0.5, -6.0), Vec3::new(0.5, 0.5, -5.0));
        let near = Aabb::new(Vec3::new(2.0, 0.0, -3.0), Vec3::new(2.5, 0.5, -2.0));
        let depth = nearest_depth(&clip_from_world, [&far, &near]).unwrap();
        assert!((depth - 2.0).abs() < 1e-4, "{depth}");
        assert!((nearest_depth(&clip_from_world, [&far]).unwrap() - 5.0).abs() < 1e-4);
        assert_eq!(nearest_depth(&clip_from_world, []), None, "no box, no blocker");
        // Behind the eye, or round it: no nearer than the eye itself.
        let round = Aabb::new(Vec3::splat(-1.0), Vec3::ONE);
        assert_eq!(nearest_depth(&clip_from_world, [&far, &round]), Some(0.0));
        // A box whose place is unknown may be anywhere.
        let broken = Aabb::new(Vec3::ZERO, Vec3::new(f32::NAN, 1.0, 1.0));
        assert_eq!(nearest_depth(&clip_from_world, [&far, &broken]), Some(0.0));
        assert_eq!(nearest_depth(&clip_from_world, [&Aabb::EMPTY]), Some(0.0));
    }

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

    /// The test as its doc says it: the box's eight corners carried into clip space, one plane
    /// at a time; with the margin by which the deciding plane decided.
    fn by_corners(m: &Mat4, b: &Aabb) -> (bool, f32) {
        let clip = b.corners().map(|c| *m * c.extend(1.0));
        let planes: [fn(Vec4) -> f32; 6] =
            [|c| c.w - c.x, |c| c.w + c.x, |c| c.w - c.y, |c| c.w + c.y, |c| c.z, |c| c.w - c.z];
        let best = planes.map(|p| clip.iter().map(|c| p(*c)).fold(f32::NEG_INFINITY, f32::max));
        let worst = best.iter().copied().fold(f32::INFINITY, f32::min);
        (worst >= 0.0, worst.abs())
    }

    #[test]
    fn world_planes_decide_as_the_eight_corners_do() {
        let mut rng = crate::shadow::test_rng::Rng(0x2545_f491_4f6c_dd1d);
        let mut next = move || rng.range(-1.0, 1.0);
        let (mut inside, mut outside) = (0, 0);
        for _ in 0..20_000 {
            let eye = Vec3::new(next(), next(), next()) * 30.0;
            let view = crate::shadow::light_view(eye, Vec3::new(next(), next() - 0.5, next()));
            let proj = if next() > 0.0 {
                glam::camera::rh::proj::directx::perspective(1.0 + next() * 0.9, 1.0, 0.1, 40.0 + next() * 30.0)
            } else {
                let h = 5.0 + 20.0 * next().abs();
                glam::camera::rh::proj::directx::orthographic(-h, h, -h, h, -10.0, 60.0)
            };
            let m = proj * view;
            let c = Vec3::new(next(), next(), next()) * 50.0;
            let b = Aabb::new(c, c + Vec3::new(next(), next(), next()).abs() * 4.0);
            let (expected, margin) = by_corners(&m, &b);
            // Rounding may only decide a box that touches a plane to within a hair.
            if margin > 1e-3 {
                assert_eq!(intersects_clip_volume(&m, &b), expected, "{b:?} {m:?}");
                if expected { inside += 1 } else { outside += 1 }
            }
        }
        assert!(inside > 1000 && outside > 1000, "{inside} / {outside}");
    }

    #[test]
    fn frustum_corners_of_an_ortho_box_are_its_corners() {
        let proj = glam::camera::rh::proj::directx::orthographic(-2.0, 2.0, -1.0, 1.0, 0.5, 10.0);
        let c = frustum_corners(&proj);
        assert!((c[0] - Vec3::new(-2.0, -1.0, -0.5)).length() < 1e-5);
        assert!((c[7] - Vec3::new(2.0, 1.0, -10.0)).length() < 1e-4);
    }
}
