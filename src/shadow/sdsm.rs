//! Sample distribution shadow maps (Lauritzen, Salvi and Lefohn, "Sample Distribution Shadow
//! Maps", I3D 2011): cascades fitted to what the camera saw, not to its whole frustum.
//!
//! A reduction over the camera's depth buffer (on the GPU, `shaders/sdsm.wgsl`) finds the
//! nearest and farthest view depth of any visible pixel, and sorts the visible pixels into
//! [`SDSM_BINS`] bins of view depth, log-spaced between the camera's near plane and the shadow
//! distance, keeping each bin's box in the sun's light space. The splits are then fitted to the
//! depths seen, and each cascade's box to the union of the bins its slice overlaps: whatever the
//! splits, every pixel the reduction saw lies in its cascade's box (a bin that straddles a
//! split counts for both cascades). The result is read back a frame later.

use super::bounds::Aabb;
use glam::{Mat4, Vec3};

/// Bins of view depth the reduction sorts visible pixels into.
pub const SDSM_BINS: usize = 32;

/// Words the reduction writes: the nearest and farthest view depth, then per bin the smallest
/// and the largest light-space x, y and z, each as an [`order_key`].
pub const SDSM_WORDS: usize = 2 + 6 * SDSM_BINS;

/// A float as an unsigned integer that sorts as the float does (negative ones flipped whole,
/// positive ones with their sign bit set), so atomic min and max on integers find the float's.
#[must_use]
pub fn order_key(v: f32) -> u32 {
    let b = v.to_bits();
    if b & 0x8000_0000 != 0 { !b } else { b | 0x8000_0000 }
}

/// The float an [`order_key`] came from.
#[must_use]
pub fn from_order_key(k: u32) -> f32 {
    f32::from_bits(if k & 0x8000_0000 != 0 { k & 0x7fff_ffff } else { !k })
}

/// The words a reduction starts from: every smallest at the largest key, every largest at the
/// smallest, so an untouched bin decodes as empty.
#[must_use]
pub fn initial_words() -> Vec<u32> {
    let mut words = vec![0u32; SDSM_WORDS];
    words[0] = u32::MAX;
    for b in 0..SDSM_BINS {
        words[2 + 6 * b..][..3].fill(u32::MAX);
    }
    words
}

/// The view depth where bin `i` of `near..far` starts (`i` = [`SDSM_BINS`] gives `far`).
#[must_use]
pub fn bin_start(i: usize, (near, far): (f32, f32)) -> f32 {
    near * (far / near).powf(i as f32 / SDSM_BINS as f32)
}

/// The bin of view depth `depth` in `near..far` (none outside it).
#[must_use]
pub fn bin_of(depth: f32, (near, far): (f32, f32)) -> Option<usize> {
    let t = (depth / near).ln() / (far / near).ln();
    (depth >= near && depth < far).then(|| ((t * SDSM_BINS as f32) as usize).min(SDSM_BINS - 1))
}

/// What the camera saw in a frame, as the depth reduction found it.
#[derive(Clone, Debug, PartialEq)]
pub struct VisibleSamples {
    /// Nearest and farthest view depth of a visible pixel (`None` when nothing was visible).
    pub depths: Option<(f32, f32)>,
    /// The view depths the bins are spread over.
    pub range: (f32, f32),
    /// The light space the boxes are in.
    pub light_from_world: Mat4,
    /// Each bin's light-space box of the pixels in it (empty for a bin with none).
    pub bins: Vec<Aabb>,
}

impl VisibleSamples {
    /// Decodes the reduction's `words`, binned over `range` in `light_from_world`'s space.
    /// Anything not finite (a broken matrix) reads as nothing seen.
    #[must_use]
    pub fn from_words(words: &[u32], range: (f32, f32), light_from_world: Mat4) -> Self {
        let at = |i: usize| words.get(i).copied().map_or(f32::NAN, from_order_key);
        let (near, far) = (at(0), at(1));
        let depths = (near.is_finite() && far.is_finite() && near <= far).then_some((near, far));
        let bins = (0..SDSM_BINS)
            .map(|b| {
                let w = 2 + 6 * b;
                let b = Aabb {
                    min: Vec3::new(at(w), at(w + 1), at(w + 2)),
                    max: Vec3::new(at(w + 3), at(w + 4), at(w + 5)),
                };
                if b.is_usable() { b } else { Aabb::EMPTY }
            })
            .collect();
        VisibleSamples { depths, range, light_from_world, bins }
    }

    /// The light-space box (in `light_from_world`'s space) of the pixels with view depth in
    /// `a..b`: the union of the bins that overlap it, carried from the space they were measured
    /// in; empty when none was seen there.
    #[must_use]
    pub fn slice_box(&self, (a, b): (f32, f32), light_from_world: &Mat4) -> Aabb {
        let seen = (0..self.bins.len())
            .filter(|&i| bin_start(i, self.range) < b && bin_start(i + 1, self.range) > a)
            .fold(Aabb::EMPTY, |u, i| u.union(self.bins[i]));
        if seen.is_empty() || *light_from_world == self.light_from_world {
            return seen;
        }
        // The sun turned since: the box in the new light space holds the old one.
        seen.transformed(&(*light_from_world * self.light_from_world.inverse()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn order_keys_sort_as_their_floats_and_decode_exactly() {
        let values = [f32::NEG_INFINITY, -1e30, -2.5, -1e-30, -0.0, 0.0, 1e-30, 0.5, 3.0, 1e30, f32::INFINITY];
        for w in values.windows(2) {
            assert!(order_key(w[0]) <= order_key(w[1]), "{} {}", w[0], w[1]);
        }
        for v in values {
            assert_eq!(from_order_key(order_key(v)).to_bits(), v.to_bits());
        }
        assert!(from_order_key(u32::MAX).is_nan() && from_order_key(0).is_nan(), "the start words are no depth");
    }

    #[test]
    fn bins_cover_the_range_in_order_and_nothing_outside() {
        let range = (0.1, 60.0);
        assert_eq!(bin_start(0, range), 0.1);
        assert!((bin_start(SDSM_BINS, range) - 60.0).abs() < 1e-3);
        for i in 0..SDSM_BINS {
            let (a, b) = (bin_start(i, range), bin_start(i + 1, range));
            assert_eq!(bin_of(a * 1.0001, range), Some(i), "bin {i} from {a}");
            assert_eq!(bin_of(b * 0.9999, range), Some(i), "bin {i} to {b}");
        }
        assert_eq!(bin_of(0.05, range), None);
        assert_eq!(bin_of(60.0, range), None);
        assert_eq!(bin_of(f32::NAN, range), None);
    }

    #[test]
    fn untouched_words_are_nothing_seen_and_a_slice_takes_every_bin_it_overlaps() {
        let none = VisibleSamples::from_words(&initial_words(), (0.1, 60.0), Mat4::IDENTITY);
        assert_eq!(none.depths, None);
        assert!(none.bins.iter().all(Aabb::is_empty));
        assert!(none.slice_box((0.1, 60.0), &Mat4::IDENTITY).is_empty());
        assert_eq!(VisibleSamples::from_words(&[], (0.1, 60.0), Mat4::IDENTITY).depths, None, "too short");

        let mut words = initial_words();
        let mut put = |depth: f32, p: Vec3| {
            let b = bin_of(depth, (0.1, 60.0)).unwrap();
            for (k, v) in p.to_array().into_iter().enumerate() {
                words[2 + 6 * b + k] = words[2 + 6 * b + k].min(order_key(v));
                words[2 + 6 * b + 3 + k] = words[2 + 6 * b + 3 + k].max(order_key(v));
            }
            words[0] = words[0].min(order_key(depth));
            words[1] = words[1].max(order_key(depth));
        };
        put(2.0, Vec3::new(1.0, 2.0, -3.0));
        put(2.01, Vec3::new(-1.0, 0.0, -2.0));
        put(30.0, Vec3::new(5.0, 5.0, -20.0));
        let seen = VisibleSamples::from_words(&words, (0.1, 60.0), Mat4::IDENTITY);
        assert_eq!(seen.depths, Some((2.0, 30.0)));
        let near = seen.slice_box((0.1, 10.0), &Mat4::IDENTITY);
        assert_eq!(near, Aabb::new(Vec3::new(-1.0, 0.0, -3.0), Vec3::new(1.0, 2.0, -2.0)));
        let all = seen.slice_box((0.1, 60.0), &Mat4::IDENTITY);
        assert_eq!(all.max, Vec3::new(5.0, 5.0, -2.0));
        assert!(seen.slice_box((40.0, 60.0), &Mat4::IDENTITY).is_empty());
        // Measured in one light space, asked for in another: the box holds the points still.
        let turned = Mat4::from_rotation_y(0.3);
        let moved = seen.slice_box((0.1, 60.0), &turned);
        for p in [Vec3::new(1.0, 2.0, -3.0), Vec3::new(5.0, 5.0, -20.0)] {
            let q = turned.transform_point3(p);
            assert!(q.cmpge(moved.min - 1e-4).all() && q.cmple(moved.max + 1e-4).all(), "{q} in {moved:?}");
        }
    }
}
