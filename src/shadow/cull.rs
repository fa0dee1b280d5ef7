//! Per-layer culling that is not linear in the size of the scene: the casters' boxes in a
//! bounding volume hierarchy (obvhs's PLOC builder), walked once per shadow-map layer.
//!
//! A layer finds its casters in time that grows with the casters inside its volume and with the
//! log of those outside it: a subtree whose box lies wholly outside one clip plane is skipped
//! whole. The answer is exactly [`super::intersects_clip_volume`]'s for each box on its own (tested
//! against that brute force), in ascending order, so the draws it feeds do not change.
//!
//! Building the hierarchy costs more than walking it, so a frame whose objects are the ones the
//! last frame had only refits it: each node's box grows or shrinks to hold its objects' new
//! boxes. The answers stay exact (a node still holds all it holds); only the pruning can grow
//! worse as objects wander from where the hierarchy was built, so it is built afresh now and
//! then ([`REBUILD_AFTER`]).

use super::bounds::{Aabb, ClipVolume};
use glam::{Mat4, Vec3A};
use obvhs::bvh2::Bvh2;

/// The boxes of a frame's objects, indexed for culling against clip volumes.
pub struct CasterIndex {
    /// The hierarchy over the usable boxes; `None` when there are none.
    bvh: Option<Bvh2>,
    /// The object each of the hierarchy's primitives is.
    objects: Vec<u32>,
    /// Objects whose box is not usable (empty, not finite, out of the world), tested one by one.
    loose: Vec<u32>,
    /// Every object's box, by object index.
    bounds: Vec<Aabb>,
    /// Times it has been refitted since it was built.
    refits: u32,
}

/// Frames a hierarchy is refitted before it is built afresh.
pub const REBUILD_AFTER: u32 = 60;

/// A box as obvhs takes it.
fn to_bvh(b: &Aabb) -> obvhs::aabb::Aabb {
    obvhs::aabb::Aabb { min: Vec3A::from(b.min), max: Vec3A::from(b.max) }
}

/// A hierarchy node's box, widened by a hair so that rounding in the clip-space test can never
/// reject a node whose own test on a box inside it would pass (a wider node only prunes less).
fn node_box(b: &obvhs::aabb::Aabb) -> Aabb {
    let (min, max) = (glam::Vec3::from(b.min), glam::Vec3::from(b.max));
    let pad = (max - min).max_element() * 1e-5 + min.abs().max(max.abs()).max_element() * 1e-6 + 1e-6;
    Aabb { min: min - pad, max: max + pad }
}

impl CasterIndex {
    /// Indexes `bounds` (one box per object, by object index).
    #[must_use]
    pub fn new(bounds: &[Aabb]) -> Self {
        let (usable, loose): (Vec<u32>, Vec<u32>) =
            (0..bounds.len() as u32).partition(|&i| bounds[i as usize].is_usable());
        let boxes: Vec<obvhs::aabb::Aabb> = usable.iter().map(|&i| to_bvh(&bounds[i as usize])).collect();
        let bvh = (!boxes.is_empty()).then(|| {
            let mut build_time = std::time::Duration::ZERO;
            obvhs::bvh2::builder::build_bvh2(&boxes, obvhs::BvhBuildParams::very_fast_build(), &mut build_time)
        });
        CasterIndex { bvh, objects: usable, loose, bounds: bounds.to_vec(), refits: 0 }
    }

    /// This index with its objects' boxes replaced by `bounds`: refitted when they are the same
    /// objects as far as it can tell (as many, the same ones usable) and it is not due to be
    /// built afresh, else built afresh.
    #[must_use]
    pub fn refitted(mut self, bounds: &[Aabb]) -> Self {
        let same = bounds.len() == self.bounds.len()
            && self.objects.iter().all(|&i| bounds[i as usize].is_usable())
            && self.loose.iter().all(|&i| !bounds[i as usize].is_usable());
        let Some(bvh) = self.bvh.as_mut().filter(|_| same && self.refits < REBUILD_AFTER) else {
            return CasterIndex::new(bounds);
        };
        self.bounds.copy_from_slice(bounds);
        for n in 0..bvh.nodes.len() {
            let node = &bvh.nodes[n];
            if node.is_leaf() {
                let prims = &bvh.primitive_indices[node.first_index as usize..][..node.prim_count as usize];
                let b = prims.iter().fold(Aabb::EMPTY, |b, &p| b.union(bounds[self.objects[p as usize] as usize]));
                bvh.nodes[n].set_aabb(to_bvh(&b));
            }
        }
        bvh.refit_all();
        self.refits += 1;
        self
    }

    /// The objects whose box [`super::intersects_clip_volume`] of `clip_from_world`, in ascending order.
    #[must_use]
    pub fn inside(&self, clip_from_world: &Mat4) -> Vec<usize> {
        let volume = ClipVolume::new(clip_from_world);
        let hit = |i: u32| volume.intersects(&self.bounds[i as usize]);
        let mut found: Vec<usize> = self.loose.iter().copied().filter(|&i| hit(i)).map(|i| i as usize).collect();
        if let Some(bvh) = &self.bvh {
            let mut stack = vec![0u32];
            while let Some(n) = stack.pop() {
                let node = &bvh.nodes[n as usize];
                if !volume.intersects(&node_box(node.aabb())) {
                    continue;
                }
                if node.is_leaf() {
                    let prims = &bvh.primitive_indices[node.first_index as usize..][..node.prim_count as usize];
                    let objects = prims.iter().map(|&p| self.objects[p as usize]);
                    found.extend(objects.filter(|&i| hit(i)).map(|i| i as usize));
                } else {
                    stack.extend([node.first_index, node.first_index + 1]);
                }
            }
        }
        found.sort_unstable();
        found
    }

    /// Number of objects indexed.
    #[must_use]
    pub fn len(&self) -> usize {
        self.bounds.len()
    }

    /// True when no object is indexed.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.bounds.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shadow::test_rng::Rng;
    use crate::shadow::{intersects_clip_volume, light_view, spot_projection};
    use glam::Vec3;

    fn brute_force(bounds: &[Aabb], clip: &Mat4) -> Vec<usize> {
        (0..bounds.len()).filter(|&i| intersects_clip_volume(clip, &bounds[i])).collect()
    }

    /// Clip volumes of every kind a layer has: sun boxes (orthographic) and spot cones
    /// (perspective), at random places and sizes, some holding the whole scene, some nothing.
    fn random_volume(rng: &mut Rng) -> Mat4 {
        let at = rng.point(150.0);
        let dir = (rng.point(1.0) + Vec3::new(0.0, -0.3, 0.0)).normalize_or(Vec3::NEG_Y);
        if rng.next() < 0.5 {
            let half = rng.range(0.5, 80.0);
            let view = light_view(at, dir);
            glam::camera::rh::proj::directx::orthographic(-half, half, -half, half, 0.0, rng.range(1.0, 200.0)) * view
        } else {
            spot_projection(at, dir, rng.range(0.05, 1.4), rng.range(1.0, 120.0), 1).view_proj
        }
    }

    #[test]
    fn culling_returns_exactly_what_brute_force_returns_for_ten_thousand_random_casters() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let bounds: Vec<Aabb> = (0..10_000)
            .map(|_| {
                let c = rng.point(100.0);
                Aabb::new(c, c + Vec3::new(rng.range(0.0, 3.0), rng.range(0.0, 3.0), rng.range(0.0, 3.0)))
            })
            .collect();
        let index = CasterIndex::new(&bounds);
        assert_eq!(index.len(), 10_000);
        let (mut some, mut none) = (0, 0);
        for _ in 0..200 {
            let clip = random_volume(&mut rng);
            let found = index.inside(&clip);
            assert_eq!(found, brute_force(&bounds, &clip), "{clip:?}");
            if found.is_empty() { none += 1 } else { some += 1 }
        }
        assert!(some > 50 && none > 5, "the volumes hold some casters and miss others: {some} / {none}");
    }

    #[test]
    fn broken_boxes_are_tested_one_by_one_and_an_empty_scene_finds_nothing() {
        let nan = Aabb { min: Vec3::splat(f32::NAN), max: Vec3::ONE };
        let huge = Aabb::new(Vec3::splat(-1e30), Vec3::splat(1e30));
        let inf = Aabb::new(Vec3::ZERO, Vec3::splat(f32::INFINITY));
        let ok = Aabb::new(Vec3::ZERO, Vec3::ONE);
        let bounds = [nan, Aabb::EMPTY, huge, ok, inf, ok];
        let index = CasterIndex::new(&bounds);
        let mut rng = Rng(7);
        for _ in 0..100 {
            let clip = random_volume(&mut rng);
            assert_eq!(index.inside(&clip), brute_force(&bounds, &clip));
        }
        let clip = glam::camera::rh::proj::directx::orthographic(-1.0, 1.0, -1.0, 1.0, 0.0, 10.0);
        assert!(CasterIndex::new(&[]).inside(&clip).is_empty());
        assert!(CasterIndex::new(&[]).is_empty());
        assert!(CasterIndex::new(&[Aabb::EMPTY, nan]).inside(&clip).is_empty());
        assert!(CasterIndex::new(&[ok]).inside(&Mat4::NAN).is_empty(), "a NaN volume holds nothing");
    }

    #[test]
    fn a_refitted_index_answers_as_a_new_one_does_as_the_boxes_wander() {
        let mut rng = Rng(0x51ab);
        let mut bounds: Vec<Aabb> = (0..3000)
            .map(|_| {
                let c = rng.point(40.0);
                Aabb::new(c, c + Vec3::ONE)
            })
            .collect();
        let mut index = CasterIndex::new(&bounds);
        for frame in 0..2 * REBUILD_AFTER {
            for b in bounds.iter_mut() {
                let step = rng.point(2.0);
                *b = Aabb::new(b.min + step, b.max + step);
            }
            // Now and then one box breaks and mends: the index is built afresh around it.
            bounds[7] = if frame % 25 == 3 { Aabb::EMPTY } else { Aabb::new(Vec3::ZERO, Vec3::ONE) };
            index = index.refitted(&bounds);
            let clip = random_volume(&mut rng);
            assert_eq!(index.inside(&clip), brute_force(&bounds, &clip), "frame {frame}");
        }
        let fewer = index.refitted(&bounds[..10]);
        assert_eq!(fewer.len(), 10, "other objects: built afresh");
    }

    #[test]
    fn many_boxes_on_one_spot_are_all_found() {
        // Equal boxes give the builder equal keys: every one must still be found, once.
        let b = Aabb::new(Vec3::new(1.0, 0.0, 1.0), Vec3::new(2.0, 1.0, 2.0));
        let bounds = vec![b; 1000];
        let clip = glam::camera::rh::proj::directx::orthographic(-5.0, 5.0, -5.0, 5.0, -50.0, 50.0);
        assert_eq!(CasterIndex::new(&bounds).inside(&clip), (0..1000).collect::<Vec<_>>());
    }
}
