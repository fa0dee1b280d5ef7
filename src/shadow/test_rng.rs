//! A small deterministic generator (xorshift) for the shadow math's randomized tests, so a
//! failing case repeats.

use glam::Vec3;

/// Xorshift over a nonzero 64-bit state.
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in 0..1.
    pub fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in `lo..hi`.
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next()
    }

    /// Uniform in the cube of half side `half` round the origin.
    pub fn point(&mut self, half: f32) -> Vec3 {
        Vec3::new(self.range(-half, half), self.range(-half, half), self.range(-half, half))
    }
}
