//! Clustered light lists (Olsson, Billeter and Assarsson 2012, "Clustered Deferred and Forward
//! Shading"): the camera's view cut into froxels, [`CLUSTER_X`] × [`CLUSTER_Y`] tiles of the
//! screen times [`CLUSTER_Z`] slices of view depth spaced evenly in its logarithm, each listing
//! the lights whose reach meets it. A pixel loops over its own cluster's lights, so what it costs
//! follows the lights that reach it, not the lights in the scene. Built on the CPU each frame,
//! so it needs no compute shaders (GL runs the same path).
//!
//! The shaders find a point's cluster as [`ClusterView::cluster_of`] does (`lights_at` in
//! lights.wgsl), from its clip position and its view depth, and read its list from
//! [`LightGrid::words`].

use glam::{Mat4, Vec3, Vec4Swizzles};

/// Tiles across the screen.
pub const CLUSTER_X: u32 = 16;
/// Tiles down the screen.
pub const CLUSTER_Y: u32 = 9;
/// Slices of view depth.
pub const CLUSTER_Z: u32 = 24;
/// Clusters in all.
pub const CLUSTERS: usize = (CLUSTER_X * CLUSTER_Y * CLUSTER_Z) as usize;

/// Where a light's light can arrive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reach {
    /// Anywhere (a light infinitely far away).
    Everywhere,
    /// Only inside a sphere.
    Sphere {
        /// Its centre.
        centre: Vec3,
        /// Its radius.
        radius: f32,
    },
}

/// The camera as the clusters cut its view: its clip space, where it is, which way it looks, and
/// the view depths the slices span.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClusterView {
    /// World to the camera's clip space.
    pub clip_from_world: Mat4,
    /// Where the camera is.
    pub eye: Vec3,
    /// Its unit forward axis.
    pub forward: Vec3,
    /// View depth where the first slice starts (the near plane).
    pub near: f32,
    /// View depth where the last slice ends.
    pub far: f32,
}

impl ClusterView {
    /// The view of a camera whose clip space is `clip_from_world` at `eye` looking along unit
    /// `forward`, from `near` to `far`, with slices that end where the farthest of `reaches`
    /// does (so every light reaching past the last slice reaches everywhere: a sun).
    #[must_use]
    pub fn new(
        clip_from_world: Mat4,
        (eye, forward): (Vec3, Vec3),
        (near, far): (f32, f32),
        reaches: &[Reach],
    ) -> Self {
        let near = if near.is_finite() && near > 0.0 { near } else { 0.1 };
        let reached = reaches
            .iter()
            .filter_map(|r| match *r {
                Reach::Sphere { centre, radius } => Some((centre - eye).dot(forward) + radius),
                Reach::Everywhere => None,
            })
            .filter(|d| d.is_finite())
            .fold(near * 2.0, f32::max);
        let far = if far.is_finite() { reached.min(far) } else { reached };
        ClusterView { clip_from_world, eye, forward, near, far: far.max(near * 2.0) }
    }

    /// The slice holding view depth `depth` (the first before it, the last past it).
    #[must_use]
    pub fn slice_of(&self, depth: f32) -> u32 {
        let t = (depth.max(self.near) / self.near).ln() / (self.far / self.near).ln();
        ((t * CLUSTER_Z as f32).max(0.0) as u32).min(CLUSTER_Z - 1)
    }

    /// The tile column or row holding normalised device coordinate `ndc` (-1..1) on an axis of
    /// `tiles` tiles, clamped to the screen.
    fn tile_of(ndc: f32, tiles: u32) -> u32 {
        (((ndc * 0.5 + 0.5) * tiles as f32).max(0.0) as u32).min(tiles - 1)
    }

    /// The cluster holding world point `p` (past the last slice, one of the last), or `None` when
    /// it is outside the camera's view (behind it or beside it): such a point has no list and
    /// must try every light.
    #[must_use]
    pub fn cluster_of(&self, p: Vec3) -> Option<usize> {
        let clip = self.clip_from_world * p.extend(1.0);
        let depth = (p - self.eye).dot(self.forward);
        let ndc = clip.xy() / clip.w;
        let inside = clip.w > 0.0 && ndc.abs().max_element() <= 1.0;
        inside.then(|| {
            let (x, y, z) = (Self::tile_of(ndc.x, CLUSTER_X), Self::tile_of(ndc.y, CLUSTER_Y), self.slice_of(depth));
            ((z * CLUSTER_Y + y) * CLUSTER_X + x) as usize
        })
    }

    /// The clusters a sphere may meet, as inclusive ranges of tiles and slices; none when it
    /// lies wholly behind the near plane or past the far one. Conservative: the sphere's world
    /// box is projected, and a box that crosses the near plane takes the whole screen.
    fn sphere_clusters(&self, centre: Vec3, radius: f32) -> Option<[(u32, u32); 3]> {
        let depth = (centre - self.eye).dot(self.forward);
        if !(depth + radius >= self.near && depth - radius <= self.far && radius.is_finite()) {
            return None;
        }
        let slices = (self.slice_of(depth - radius), self.slice_of(depth + radius));
        let corners = (0..8).map(|i| {
            let sign = Vec3::new([-1.0, 1.0][i & 1], [-1.0, 1.0][(i >> 1) & 1], [-1.0, 1.0][i >> 2]);
            self.clip_from_world * (centre + sign * radius).extend(1.0)
        });
        let mut lo = glam::Vec2::splat(f32::INFINITY);
        let mut hi = glam::Vec2::splat(f32::NEG_INFINITY);
        for clip in corners {
            if clip.w <= 0.0 {
                // Behind the eye: its projection wraps round, so take the whole screen.
                (lo, hi) = (glam::Vec2::splat(-1.0), glam::Vec2::splat(1.0));
                break;
            }
            lo = lo.min(clip.xy() / clip.w);
            hi = hi.max(clip.xy() / clip.w);
        }
        if lo.x > 1.0 || lo.y > 1.0 || hi.x < -1.0 || hi.y < -1.0 {
            return None;
        }
        let xs = (Self::tile_of(lo.x, CLUSTER_X), Self::tile_of(hi.x, CLUSTER_X));
        let ys = (Self::tile_of(lo.y, CLUSTER_Y), Self::tile_of(hi.y, CLUSTER_Y));
        Some([xs, ys, slices])
    }
}

/// Each cluster's lights: `ranges[c]` is the first index into `indices` and the count of
/// cluster `c`'s lights, which are listed in light order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LightGrid {
    /// Per cluster, its first entry in `indices` and how many it has.
    pub ranges: Vec<[u32; 2]>,
    /// Light indices, cluster after cluster.
    pub indices: Vec<u32>,
}

impl LightGrid {
    /// The lights of `reaches` (indexed in light order) listed in every cluster of `view` they
    /// may meet.
    #[must_use]
    pub fn build(view: &ClusterView, reaches: &[Reach]) -> LightGrid {
        let blocks: Vec<Option<[(u32, u32); 3]>> = reaches
            .iter()
            .map(|r| match *r {
                Reach::Everywhere => Some([(0, CLUSTER_X - 1), (0, CLUSTER_Y - 1), (0, CLUSTER_Z - 1)]),
                Reach::Sphere { centre, radius } => view.sphere_clusters(centre, radius),
            })
            .collect();
        let each = |f: &mut dyn FnMut(usize, u32)| {
            for (light, block) in blocks.iter().enumerate() {
                let Some([(x0, x1), (y0, y1), (z0, z1)]) = *block else { continue };
                for z in z0..=z1 {
                    for y in y0..=y1 {
                        for x in x0..=x1 {
                            f(((z * CLUSTER_Y + y) * CLUSTER_X + x) as usize, light as u32);
                        }
                    }
                }
            }
        };
        // Count, then place: each cluster's lights land together, in light order.
        let mut ranges = vec![[0u32; 2]; CLUSTERS];
        each(&mut |c, _| ranges[c][1] += 1);
        let mut next = 0;
        for r in &mut ranges {
            r[0] = next;
            next += r[1];
        }
        let mut indices = vec![0; next as usize];
        let mut filled = vec![0u32; CLUSTERS];
        each(&mut |c, light| {
            indices[(ranges[c][0] + filled[c]) as usize] = light;
            filled[c] += 1;
        });
        LightGrid { ranges, indices }
    }

    /// The lists as the shaders read them: each cluster's first entry and count (its first entry
    /// counted from the start of the words), then the indices.
    #[must_use]
    pub fn words(&self) -> Vec<u32> {
        let head = 2 * self.ranges.len() as u32;
        let ranges = self.ranges.iter().flat_map(|[first, count]| [head + first, *count]);
        ranges.chain(self.indices.iter().copied()).collect()
    }

    /// The lights listed in cluster `c`.
    #[must_use]
    pub fn lights_of(&self, c: usize) -> &[u32] {
        let [first, count] = self.ranges.get(c).copied().unwrap_or_default();
        &self.indices[first as usize..(first + count) as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shadow::test_rng::Rng;

    fn view(reaches: &[Reach]) -> ClusterView {
        let proj = glam::camera::rh::proj::directx::perspective(1.0, 16.0 / 9.0, 0.1, 100.0);
        let (eye, forward) = (Vec3::new(0.0, 2.0, 8.0), Vec3::new(0.0, -0.2, -1.0).normalize());
        let view = glam::camera::rh::view::look_to_mat4(eye, forward, Vec3::Y);
        ClusterView::new(proj * view, (eye, forward), (0.1, 100.0), reaches)
    }

    #[test]
    fn every_point_a_sphere_reaches_in_view_lies_in_a_cluster_that_lists_it() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let reaches: Vec<Reach> = (0..200)
            .map(|_| Reach::Sphere {
                centre: Vec3::new(rng.range(-20.0, 20.0), rng.range(-2.0, 6.0), rng.range(-50.0, 12.0)),
                radius: rng.range(0.2, 6.0),
            })
            .chain([Reach::Everywhere])
            .collect();
        let view = view(&reaches);
        assert!(view.far < 100.0, "the slices end where the farthest light does: {}", view.far);
        let grid = LightGrid::build(&view, &reaches);
        let mut checked = 0;
        for (light, reach) in reaches.iter().enumerate() {
            let Reach::Sphere { centre, radius } = *reach else { continue };
            for _ in 0..200 {
                let d = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
                let p = centre + d.normalize_or_zero() * radius * rng.range(0.0, 1.0);
                if let Some(c) = view.cluster_of(p) {
                    assert!(grid.lights_of(c).contains(&(light as u32)), "light {light} at {p} in cluster {c}");
                    checked += 1;
                }
            }
        }
        assert!(checked > 5000, "{checked} points were in view");
        let everywhere = reaches.len() as u32 - 1;
        assert!((0..CLUSTERS).all(|c| grid.lights_of(c).last() == Some(&everywhere)), "a sun is in every list");
    }

    #[test]
    fn a_small_light_is_listed_in_few_clusters_and_one_out_of_view_in_none() {
        let near = Reach::Sphere { centre: Vec3::new(0.0, 0.0, -4.0), radius: 0.5 };
        let behind = Reach::Sphere { centre: Vec3::new(0.0, 2.0, 20.0), radius: 3.0 };
        let far = Reach::Sphere { centre: Vec3::new(0.0, 0.0, -120.0), radius: 3.0 };
        let view = view(&[near, behind, far]);
        let grid = LightGrid::build(&view, &[near, behind, far]);
        let listed = |l: u32| (0..CLUSTERS).filter(|&c| grid.lights_of(c).contains(&l)).count();
        assert!((1..=60).contains(&listed(0)), "{} clusters", listed(0));
        assert_eq!((listed(1), listed(2)), (0, 0));
    }

    #[test]
    fn odd_spheres_and_points_are_turned_away_not_panicked_on() {
        let odd = [
            Reach::Sphere { centre: Vec3::NAN, radius: 1.0 },
            Reach::Sphere { centre: Vec3::ZERO, radius: f32::INFINITY },
            Reach::Sphere { centre: Vec3::splat(1e30), radius: 1e30 },
            Reach::Sphere { centre: Vec3::ZERO, radius: 0.0 },
        ];
        let view = view(&odd);
        assert!(view.far.is_finite() && view.far > view.near, "{view:?}");
        let grid = LightGrid::build(&view, &odd);
        assert_eq!(grid.ranges.len(), CLUSTERS);
        assert!(grid.indices.len() <= CLUSTERS * odd.len());
        assert_eq!(view.cluster_of(Vec3::NAN), None);
        assert_eq!(view.cluster_of(view.eye - view.forward), None, "behind the eye");
        assert_eq!(view.slice_of(f32::NAN), 0);
        assert_eq!(view.slice_of(1e30), CLUSTER_Z - 1);
    }
}
