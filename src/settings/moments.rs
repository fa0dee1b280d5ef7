//! How moment maps are kept and made: the bits a moment takes, and where the moments come from.

/// How many bits of float a moment map stores per moment.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum MomentBits {
    /// What each method does best with ([`crate::components::ShadowMethod::moment_bits`]); 16 where the device
    /// cannot render or filter 32-bit floats (GL).
    #[default]
    Auto,
    /// Half floats: half the memory and bandwidth.
    Half,
    /// Full floats (not on GL, which cannot render into them).
    Full,
}

/// How a moment map is made from its light's view.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum MomentSource {
    /// Resolved from the depth map the layer draws anyway (a pass that reads depth, turns it into
    /// moments and blurs them), one moment texel per depth texel. The default: on an NVIDIA H200
    /// a frame of VSM maps resolved in compute cost 5.8 ms against 25.0 ms drawn as colour
    /// (docs/bench-moments).
    #[default]
    Depth,
    /// The same at half the depth map's side: each moment texel is the mean of 2x2 depth
    /// texels' moments (a resolve of four samples), a quarter of the memory and blur.
    Half,
    /// The same at a quarter of its side, each moment texel the mean of 4x4.
    Quarter,
    /// Drawn by the shadow pass as a colour target beside the depth map (every caster's
    /// fragment writes its moments), then blurred. Cheaper on a software rasterizer, which shades
    /// only the texels casters cover (lavapipe: 695 ms against 904 ms a frame with six 2048² VSM
    /// layers redrawn, `bench --cache`), dearer on a GPU.
    Colour,
}

impl MomentSource {
    /// Depth texels along a side per moment texel.
    #[must_use]
    pub fn scale(self) -> u32 {
        match self {
            MomentSource::Depth | MomentSource::Colour => 1,
            MomentSource::Half => 2,
            MomentSource::Quarter => 4,
        }
    }

    /// Depth texels along a side per texel of the colour atlas, which moment maps share with
    /// depth kept in colour: its own scale, but 1 while a light keeps `depth_in_colour`, which
    /// must keep every texel.
    #[must_use]
    pub fn colour_scale(self, depth_in_colour: bool) -> u32 {
        if depth_in_colour { 1 } else { self.scale() }
    }

    /// Moments are resolved from the depth map.
    #[must_use]
    pub fn from_depth(self) -> bool {
        self != MomentSource::Colour
    }
}

/// How moments resolved from depth are made.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum MomentResolve {
    /// By the compute dispatch on a GPU, by the full-screen passes on a software rasterizer
    /// (where lavapipe runs the dispatch 2 to 4 times slower than the passes: its compute
    /// invocations load and store texels one lane at a time).
    #[default]
    Auto,
    /// One compute dispatch resolves and blurs in shared memory, where the device can (compute
    /// shaders, a format it stores into, a blur of at most 7 texels; else the passes).
    Compute,
    /// Full-screen passes: the resolve, the blur's rows into a scratch page, its columns back.
    Passes,
}

impl MomentResolve {
    /// The compute dispatch is asked for on an adapter that is (`software`) or is not a
    /// software rasterizer.
    #[must_use]
    pub fn compute(self, software: bool) -> bool {
        match self {
            MomentResolve::Auto => !software,
            MomentResolve::Compute => true,
            MomentResolve::Passes => false,
        }
    }
}

named_choices!(MomentResolve, "a moment resolve", Auto = "auto", Compute = "compute", Passes = "passes");
named_choices!(MomentBits, "a moment-map precision", Auto = "auto", Half = "16", Full = "32");
named_choices!(
    MomentSource,
    "a moment-map source",
    Colour = "colour",
    Depth = "depth",
    Half = "depth/2",
    Quarter = "depth/4"
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_resolves_in_compute_on_a_gpu_only() {
        assert!(MomentResolve::Auto.compute(false));
        assert!(!MomentResolve::Auto.compute(true));
        for software in [false, true] {
            assert!(MomentResolve::Compute.compute(software));
            assert!(!MomentResolve::Passes.compute(software));
        }
        assert_eq!("passes".parse::<MomentResolve>(), Ok(MomentResolve::Passes));
        assert!("gpu".parse::<MomentResolve>().is_err());
    }
}
