//! Cascaded shadow maps for the sun: where the camera's view is split, and how each slice gets an
//! orthographic box (stable or tight) with a depth range fitted to the casters that can shade it.

use super::bounds::{Aabb, frustum_corners};
use super::fit::{LightProjection, light_view};
use glam::camera::rh::proj::directx;
use glam::{Mat4, Quat, Vec2, Vec3};

/// Most cascades one directional light may have.
pub const MAX_CASCADES: usize = 4;

/// How a cascade's box is fitted around its slice of the view.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FitMode {
    /// A bounding sphere of the slice, its origin snapped to whole texels: the box keeps its size
    /// whatever the camera's rotation and moves in texel steps, so the shadow does not shimmer.
    #[default]
    Stable,
    /// The stable sphere without the snapping: the texel size holds still, but the texel grid
    /// slides with the camera, so shadow edges crawl (here to show what snapping buys).
    Unsnapped,
    /// The smallest light-space box around the slice: more texels on screen, but it shimmers.
    Tight,
    /// Sample distribution shadow maps: the splits fitted to the view depths the camera saw in
    /// the last frame read back, and each box to the visible pixels of its slice (see
    /// [`super::VisibleSamples`]); stable where nothing was seen or nothing has been read back.
    Sdsm,
}

/// View depths that split `[near, far]` into `count` cascades by the practical scheme.
///
/// Each split is `lambda * logarithmic + (1 - lambda) * uniform`; the result holds `count + 1`
/// increasing depths from exactly `near` to exactly `far`. `count` is clamped to 1..=4.
pub fn split_depths(near: f32, far: f32, count: usize, lambda: f32) -> Vec<f32> {
    let count = count.clamp(1, MAX_CASCADES);
    let near = if near.is_finite() { near.max(1e-4) } else { 0.1 };
    let far = if far.is_finite() { far.max(near * 1.01) } else { near * 1000.0 };
    let lambda = if lambda.is_finite() { lambda.clamp(0.0, 1.0) } else { 0.0 };
    let mut depths: Vec<f32> = (0..=count)
        .map(|i| {
            let s = i as f32 / count as f32;
            lambda * near * (far / near).powf(s) + (1.0 - lambda) * (near + (far - near) * s)
        })
        .collect();
    (depths[0], depths[count]) = (near, far);
    depths
}

/// View depths that split `[near, far]` into `count` cascades geometrically from a first cascade
/// that ends at `first`: each ends `(far / first)^(1 / (count - 1))` times further than the one
/// before (the scheme Bevy's cascade builder uses). `first` is held between `near` and `far`; one
/// cascade covers everything.
#[must_use]
pub fn geometric_splits(near: f32, first: f32, far: f32, count: usize) -> Vec<f32> {
    let mut depths = split_depths(near, far, count, 0.0);
    let (near, far) = (depths[0], depths[depths.len() - 1]);
    let count = depths.len() - 1;
    let first = if first.is_finite() { first.clamp(near * 1.001, far) } else { far };
    for (i, d) in depths.iter_mut().enumerate().take(count).skip(1) {
        *d = first * (far / first).powf((i - 1) as f32 / (count - 1) as f32);
    }
    depths
}

/// Width of the band at the end of each cascade over which it blends into the next one:
/// `blend` (a fraction, 0..0.5) of the cascade's length, and none after the last.
pub fn blend_bands(depths: &[f32], blend: f32) -> Vec<f32> {
    let blend = if blend.is_finite() { blend.clamp(0.0, 0.5) } else { 0.0 };
    let n = depths.len().saturating_sub(1);
    (0..n).map(|i| if i + 1 < n { blend * (depths[i + 1] - depths[i]) } else { 0.0 }).collect()
}

/// The camera as cascade fitting sees it: a pose and a perspective frustum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewFrustum {
    /// Eye position.
    pub position: Vec3,
    /// Orientation; the camera looks along its -Z.
    pub rotation: Quat,
    /// Vertical field of view in radians.
    pub fov_y: f32,
    /// Width over height.
    pub aspect: f32,
}

impl ViewFrustum {
    /// World corners of the part of the view between view depths `a` and `b`.
    pub fn slice_corners(&self, a: f32, b: f32) -> [Vec3; 8] {
        let proj = directx::perspective(self.fov_y, self.aspect.max(1e-3), a, b.max(a * 1.0001));
        let view = Mat4::from_rotation_translation(self.rotation, self.position).inverse();
        frustum_corners(&(proj * view))
    }

    /// The smallest sphere around the slice between view depths `a` and `b`: its centre in the
    /// world and its radius. The radius depends only on the depths, field of view and aspect, so
    /// it is the same, bit for bit, however the camera is turned or moved.
    pub fn slice_sphere(&self, a: f32, b: f32) -> (Vec3, f32) {
        let t = (self.fov_y * 0.5).tan();
        // Squared half diagonal of the slice's cross-section per metre of depth.
        let k2 = t * t * (1.0 + self.aspect * self.aspect);
        let z = 0.5 * (a + b) * (1.0 + k2);
        let (z, r) = if z >= b { (b, b * k2.sqrt()) } else { (z, ((z - a) * (z - a) + a * a * k2).sqrt()) };
        (self.position + self.rotation * Vec3::NEG_Z * z, r)
    }
}

/// Shadow-casting and shadow-receiving boxes of the scene, in world space.
#[derive(Clone, Copy, Debug)]
pub struct SceneBounds<'a> {
    /// Boxes of everything drawn into shadow maps.
    pub casters: &'a [Aabb],
    /// Boxes of everything that can be seen (and so must lie inside the depth range).
    pub receivers: &'a [Aabb],
}

/// Depth steps a stable cascade's near and far planes are rounded out to: an eighth of its radius.
pub fn depth_step(radius: f32) -> f32 {
    (radius / 8.0).max(1e-3)
}

/// The sun's orthographic projection for the slice of `frustum` between view depths `a` and `b`.
///
/// The box covers the slice across (a snapped sphere in [`FitMode::Stable`], a tight box in
/// [`FitMode::Tight`]). Its depth range is fitted to the scene, not to fixed numbers: the near
/// plane is pulled towards the light just far enough to hold every caster whose light-space
/// footprint overlaps the box (a tall pillar behind the camera still shadows the view), and the
/// far plane stops at the slice or at the farthest overlapping object, whichever is nearer.
pub fn fit_cascade(
    direction: Vec3,
    frustum: &ViewFrustum,
    a: f32,
    b: f32,
    mode: FitMode,
    scene: SceneBounds<'_>,
    resolution: u32,
) -> LightProjection {
    fit_slice(&SunScene::new(direction, scene), frustum, (a, b), mode, resolution)
}

/// The scene's boxes carried once into a sun's light view, for fitting all of its cascades:
/// with ten thousand casters, carrying them for each cascade was most of a frame's update.
#[derive(Clone, Debug)]
pub struct SunScene {
    view: Mat4,
    /// One entry per box (empty ones left out), casters and receivers together, so that a
    /// cascade's depth range is one pass over them.
    boxes: Vec<LightBox>,
}

/// A box in the sun's light space, as fitting the depth range reads it.
#[derive(Clone, Copy, Debug)]
struct LightBox {
    /// Its footprint across the light.
    min: Vec2,
    max: Vec2,
    /// The light-space z of its far side (every box must lie in front of the far plane).
    bottom: f32,
    /// The light-space z of its near side if it casts a shadow (what the near plane must hold),
    /// minus infinity if it only receives one.
    top: f32,
}

impl SunScene {
    /// `scene` seen by a sun shining along `direction`.
    #[must_use]
    pub fn new(direction: Vec3, scene: SceneBounds<'_>) -> Self {
        let casters = scene.casters.iter().map(|b| (*b, true));
        SunScene::from_boxes(direction, casters.chain(scene.receivers.iter().map(|b| (*b, false))))
    }

    /// The world boxes of `boxes`, each with whether it casts a shadow, seen by a sun shining
    /// along `direction`: what [`SunScene::new`] makes of a caster list and a receiver list,
    /// without carrying a box that is both into light space twice.
    #[must_use]
    pub fn from_boxes(direction: Vec3, boxes: impl IntoIterator<Item = (Aabb, bool)>) -> Self {
        let view = light_view(Vec3::ZERO, direction);
        let carry = |(b, casts): (Aabb, bool)| {
            let l = b.transformed(&view);
            let top = if casts { l.max.z } else { f32::NEG_INFINITY };
            LightBox { min: l.min.truncate(), max: l.max.truncate(), bottom: l.min.z, top }
        };
        SunScene { view, boxes: boxes.into_iter().filter(|(b, _)| !b.is_empty()).map(carry).collect() }
    }

    /// The world to this sun's light space.
    #[must_use]
    pub fn light_from_world(&self) -> Mat4 {
        self.view
    }

    /// The light-space z of the highest caster's top and of the lowest box's bottom (z grows
    /// towards the light): the depths a map of the whole scene must hold. Infinite (and so
    /// unusable) with no caster.
    #[must_use]
    pub fn depth_extent(&self) -> (f32, f32) {
        let top = self.boxes.iter().map(|b| b.top).fold(f32::NEG_INFINITY, f32::max);
        let bottom = self.boxes.iter().map(|b| b.bottom).fold(f32::INFINITY, f32::min);
        (top, bottom)
    }
}

/// [`fit_cascade`] for the slice between view depths `a..b`, from the scene as `sun` sees it.
#[must_use]
pub fn fit_slice(
    sun: &SunScene,
    frustum: &ViewFrustum,
    (a, b): (f32, f32),
    mode: FitMode,
    resolution: u32,
) -> LightProjection {
    let view = sun.view;
    let res = resolution.max(1) as f32;
    let (min, max, slice_far, texel, step) = match mode {
        // Without samples (see `fit_seen`), SDSM falls back to the stable fit.
        FitMode::Stable | FitMode::Unsnapped | FitMode::Sdsm => {
            let (center, r) = frustum.slice_sphere(a, b);
            let texel = 2.0 * r / res;
            let c = view.transform_point3(center);
            // Whole-texel steps keep every texel on the same world grid from frame to frame.
            let origin = if mode == FitMode::Unsnapped { c.truncate() } else { (c.truncate() / texel).round() * texel };
            (origin - r, origin + r, c.z - r, texel, Some(depth_step(r)))
        }
        FitMode::Tight => {
            let slice = Aabb::from_points(frustum.slice_corners(a, b).map(|p| view.transform_point3(p)));
            let extent = (slice.max - slice.min).truncate().max(Vec2::splat(1e-3));
            let (min, max) = (slice.min.truncate(), slice.min.truncate() + extent);
            (min, max, slice.min.z, extent.max_element() / res, None)
        }
    };
    let (near_z, far_z) = depth_range(sun, min, max, slice_far, step);
    let proj = directx::orthographic(min.x, max.x, min.y, max.y, -near_z, -far_z);
    LightProjection { view, proj, view_proj: proj * view, texel: Vec2::new(texel, 0.0) }
}

/// The sun's orthographic projection around `seen`, the light-space box of the visible pixels of
/// a cascade's slice (sample distribution shadow maps), its depth range fitted to the scene as
/// [`fit_cascade`]'s is. The box is widened by a hair so that the pixels on its edge stay inside
/// after rounding; it is not snapped, so it shimmers as the view changes, as a tight box does.
#[must_use]
pub fn fit_seen(sun: &SunScene, seen: &Aabb, resolution: u32) -> LightProjection {
    let res = resolution.max(1) as f32;
    let size = (seen.max - seen.min).truncate();
    let pad = size.max_element() * 1e-3 + 1e-3;
    let min = seen.min.truncate() - pad;
    let extent = (size + 2.0 * pad).max(Vec2::splat(1e-3));
    let max = min + extent;
    let (near_z, far_z) = depth_range(sun, min, max, seen.min.z, None);
    let proj = directx::orthographic(min.x, max.x, min.y, max.y, -near_z, -far_z);
    LightProjection {
        view: sun.view,
        proj,
        view_proj: proj * sun.view,
        texel: Vec2::new(extent.max_element() / res, 0.0),
    }
}

/// Light-space z of the near and far planes (z grows towards the light) for the footprint
/// `min..max`; with a `step`, both are rounded outwards to whole steps so they do not creep.
fn depth_range(sun: &SunScene, min: Vec2, max: Vec2, slice_far: f32, step: Option<f32>) -> (f32, f32) {
    let (mut top, mut bottom) = (f32::NEG_INFINITY, f32::INFINITY);
    for b in &sun.boxes {
        if b.min.x <= max.x && b.max.x >= min.x && b.min.y <= max.y && b.max.y >= min.y {
            top = top.max(b.top);
            bottom = bottom.min(b.bottom);
        }
    }
    let mut far_z = if bottom.is_finite() { slice_far.max(bottom) } else { slice_far };
    let mut near_z = if top.is_finite() { top } else { far_z };
    // A little slack so geometry lying exactly on a plane is not clipped by rounding.
    let slack = 1e-3 * (max - min).max_element() + 1e-3;
    near_z = near_z.max(far_z) + slack;
    far_z -= slack;
    if let Some(step) = step {
        near_z = (near_z / step).ceil() * step;
        far_z = (far_z / step).floor() * step;
    }
    (near_z, far_z)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frustum() -> ViewFrustum {
        ViewFrustum {
            position: Vec3::new(1.0, 2.0, 3.0),
            rotation: Quat::from_rotation_y(0.4),
            fov_y: 1.0,
            aspect: 1.6,
        }
    }

    #[test]
    fn splits_blend_log_and_uniform() {
        let uniform = split_depths(1.0, 9.0, 2, 0.0);
        assert_eq!(uniform, vec![1.0, 5.0, 9.0]);
        let log = split_depths(1.0, 9.0, 2, 1.0);
        assert!((log[1] - 3.0).abs() < 1e-5);
        let half = split_depths(1.0, 9.0, 2, 0.5);
        let bevy = geometric_splits(0.1, 10.0, 150.0, 4);
        let want = [0.1, 10.0, 24.662, 60.822, 150.0];
        assert!(bevy.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-2), "{bevy:?}");
        assert_eq!(geometric_splits(0.1, 10.0, 150.0, 1), vec![0.1, 150.0]);
        for odd in [f32::NAN, -5.0, 0.0, 1e9] {
            let d = geometric_splits(0.1, odd, 60.0, 4);
            assert!(d.windows(2).all(|w| w[0] <= w[1]) && d.iter().all(|x| x.is_finite()), "{odd}: {d:?}");
        }
        assert!((half[1] - 4.0).abs() < 1e-5);
    }

    #[test]
    fn bands_are_a_fraction_of_each_cascade_and_none_after_the_last() {
        assert_eq!(blend_bands(&[0.0, 10.0, 30.0], 0.1), vec![1.0, 0.0]);
        assert_eq!(blend_bands(&[0.0, 10.0], 0.3), vec![0.0]);
    }

    #[test]
    fn the_slice_sphere_holds_every_corner_and_touches_one() {
        let f = frustum();
        for (a, b) in [(0.1, 4.0), (4.0, 20.0), (20.0, 60.0), (0.1, 0.2)] {
            let (c, r) = f.slice_sphere(a, b);
            let d: Vec<f32> = f.slice_corners(a, b).iter().map(|p| p.distance(c)).collect();
            assert!(d.iter().all(|d| *d <= r * (1.0 + 1e-4)), "{a}..{b}: {d:?} vs {r}");
            assert!(d.iter().any(|d| *d >= r * (1.0 - 1e-3)), "{a}..{b}: the sphere is not the smallest");
        }
    }

    #[test]
    fn a_caster_between_light_and_slice_stays_in_depth_range_and_one_beside_it_does_not_matter() {
        let f = ViewFrustum { position: Vec3::new(0.0, 2.0, 6.0), rotation: Quat::IDENTITY, fov_y: 1.0, aspect: 1.0 };
        let ground = [Aabb::new(Vec3::new(-50.0, -0.1, -50.0), Vec3::new(50.0, 0.0, 50.0))];
        let tall = Aabb::new(Vec3::new(-0.5, 0.0, 1.5), Vec3::new(0.5, 40.0, 2.5));
        for mode in [FitMode::Stable, FitMode::Tight] {
            let scene = SceneBounds { casters: &[tall], receivers: &ground };
            let fit = fit_cascade(Vec3::NEG_Y, &f, 0.1, 8.0, mode, scene, 1024);
            for c in tall.corners() {
                let n = fit.view_proj.project_point3(c);
                assert!((-1e-4..=1.0 + 1e-4).contains(&n.z), "{mode:?}: {c:?} -> {n:?}");
            }
            let far_away = [Aabb::new(Vec3::new(80.0, 0.0, 80.0), Vec3::new(81.0, 100.0, 81.0))];
            let with = fit_cascade(
                Vec3::NEG_Y,
                &f,
                0.1,
                8.0,
                mode,
                SceneBounds { casters: &far_away, receivers: &ground },
                1024,
            );
            let without =
                fit_cascade(Vec3::NEG_Y, &f, 0.1, 8.0, mode, SceneBounds { casters: &[], receivers: &ground }, 1024);
            assert_eq!(with.view_proj, without.view_proj, "{mode:?}");
        }
    }

    #[test]
    fn only_the_stable_fit_snaps_to_whole_texels() {
        let f = frustum();
        let scene = SceneBounds { casters: &[], receivers: &[] };
        let dir = Vec3::new(-0.4, -1.0, -0.3);
        let fit = |mode, nudge: f32| {
            let moved = ViewFrustum { position: f.position + Vec3::new(nudge, 0.0, 0.0), ..f };
            fit_cascade(dir, &moved, 0.1, 10.0, mode, scene, 1024).view_proj
        };
        // A thousandth of a texel to the side: the snapped box stays, the unsnapped one moves.
        assert_eq!(fit(FitMode::Stable, 0.0), fit(FitMode::Stable, 1e-5));
        assert_ne!(fit(FitMode::Unsnapped, 0.0), fit(FitMode::Unsnapped, 1e-5));
    }
}
