//! The colour maps beside the depth maps: moment shadow maps (VSM, EVSM, MSM) and depth in
//! colour targets (R32F, R16F radial). Their format and the terms each method reads, and the
//! array they live in, slot for slot with the depth maps.
//!
//! A moment layer is made from its depth map once that is drawn ([`super::moment_blur`]: the
//! depth turned into moments, at the depth map's size or smaller, and blurred). Depth in colour,
//! and moments with [`MomentSource::Colour`], are drawn by the shadow pass as a colour target
//! instead (`fs_moments` in shadow.wgsl: where the depth is known, so what a method stores is
//! made there), and moments are then blurred alone.

use super::gpu_types::GpuLayer;
use super::texture::{LayeredTarget, render_target};
use crate::components::ShadowMethod;
use crate::settings::{MomentBits, MomentSource};

/// The colour maps' format: four channels for four moments, two for two, one for depth in
/// colour, in 16- or 32-bit floats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColourFormat {
    /// `Rgba16Float`.
    Half = 0,
    /// `Rgba32Float` (needs a device that renders into and filters it).
    Full = 1,
    /// `R16Float`: one half float.
    R16 = 2,
    /// `R32Float` (needs what `Full` needs).
    R32 = 3,
    /// `Rg16Float`: two moments in half floats.
    Rg16 = 4,
    /// `Rg32Float` (needs what `Full` needs).
    Rg32 = 5,
}

impl ColourFormat {
    /// Every format, in the order of their numbers.
    pub const ALL: [ColourFormat; 6] = [
        ColourFormat::Half,
        ColourFormat::Full,
        ColourFormat::R16,
        ColourFormat::R32,
        ColourFormat::Rg16,
        ColourFormat::Rg32,
    ];

    /// The texture format.
    pub fn texture(self) -> wgpu::TextureFormat {
        match self {
            ColourFormat::Half => wgpu::TextureFormat::Rgba16Float,
            ColourFormat::Full => wgpu::TextureFormat::Rgba32Float,
            ColourFormat::R16 => wgpu::TextureFormat::R16Float,
            ColourFormat::R32 => wgpu::TextureFormat::R32Float,
            ColourFormat::Rg16 => wgpu::TextureFormat::Rg16Float,
            ColourFormat::Rg32 => wgpu::TextureFormat::Rg32Float,
        }
    }

    /// Bits per channel.
    pub fn bits(self) -> u32 {
        match self {
            ColourFormat::Half | ColourFormat::R16 | ColourFormat::Rg16 => 16,
            ColourFormat::Full | ColourFormat::R32 | ColourFormat::Rg32 => 32,
        }
    }

    /// It holds moments (else one depth).
    pub fn moments(self) -> bool {
        !matches!(self, ColourFormat::R16 | ColourFormat::R32)
    }
}

/// The features a device needs for 32-bit moment maps: filtering them (rendering into them is
/// checked on the adapter, see [`full_supported`]).
pub const FULL_FEATURES: wgpu::Features = wgpu::Features::FLOAT32_FILTERABLE;

/// True when `adapter` can render into 32-bit float moment maps (of two and of four channels)
/// and filter them.
pub fn full_supported(adapter: &wgpu::Adapter, features: wgpu::Features) -> bool {
    let renders =
        |f| adapter.get_texture_format_features(f).allowed_usages.contains(wgpu::TextureUsages::RENDER_ATTACHMENT);
    features.contains(FULL_FEATURES)
        && renders(wgpu::TextureFormat::Rgba32Float)
        && renders(wgpu::TextureFormat::Rg32Float)
}

/// The format the colour maps of `methods` (a bit per [`ShadowMethod`]) take: `None` when no
/// light uses one. Moments take as many channels as the method that keeps the most (two or
/// four): with [`MomentBits::Auto`] as wide as any moment method prefers, halved where the
/// device has no full floats. Depth in colour takes one
/// channel, as wide as its method needs (R16F radial rounds its value to a half float itself, so
/// a wider map shared with others keeps its precision). An explicit 32, or R32F, on a device
/// without full floats is an error.
pub fn colour_format(methods: u32, bits: MomentBits, full: bool) -> Result<Option<ColourFormat>, &'static str> {
    let used: Vec<ShadowMethod> =
        ShadowMethod::ALL.iter().copied().filter(|m| m.colour_map() && methods & (1 << *m as u32) != 0).collect();
    let depth32 = used.iter().any(|m| m.colour_depth_bits() > 16);
    if depth32 && !full {
        return Err(
            "32-bit float colour targets (rendering into and filtering R32Float), which r32f writes depth into",
        );
    }
    let Some(widest) = used.iter().filter(|m| m.moments()).map(|m| m.moment_bits()).max() else {
        return Ok((!used.is_empty()).then_some(if depth32 { ColourFormat::R32 } else { ColourFormat::R16 }));
    };
    let four = match bits {
        _ if depth32 => ColourFormat::Full,
        MomentBits::Half => ColourFormat::Half,
        MomentBits::Full if !full => return Err("32-bit float moment maps (rendering into and filtering Rgba32Float)"),
        MomentBits::Full => ColourFormat::Full,
        MomentBits::Auto if widest > 16 && full => ColourFormat::Full,
        MomentBits::Auto => ColourFormat::Half,
    };
    let two = used.iter().all(|m| m.moment_count() <= 2);
    Ok(Some(match four {
        ColourFormat::Half if two => ColourFormat::Rg16,
        ColourFormat::Full if two => ColourFormat::Rg32,
        f => f,
    }))
}

/// EVSM's positive and negative exponents for `format`: the largest the format holds, since
/// a steeper warp bleeds less. The map stores e^(2c) at depth 1, so half floats (largest
/// 65504) allow c up to ln(65504) / 2 ≈ 5.54; full floats allow 44, and 40 and 5 are the
/// values commonly used (a steep negative warp loses precision near the light).
#[must_use]
pub fn evsm_warp(format: ColourFormat) -> [f32; 2] {
    if format.bits() > 16 { [40.0, 5.0] } else { [5.5, 5.5] }
}

/// What keeps `method`'s reconstruction stable in `format` (see `GpuLayer.moment_bias` in
/// moments.wgsl): a bound on the rounding of the stored moments. Half floats keep 11
/// significant bits (steps of 2⁻¹¹ ≈ 5·10⁻⁴ just below 1), full floats 24.
#[must_use]
pub fn moment_bias(method: ShadowMethod, format: ColourFormat) -> f32 {
    match (method, format) {
        // Least variance: about the square of a depth step.
        (ShadowMethod::Vsm, ColourFormat::Half | ColourFormat::Rg16 | ColourFormat::R16) => 1e-6,
        (ShadowMethod::Vsm, ColourFormat::Full | ColourFormat::Rg32) => 1e-9,
        // Least depth spread, turned into warped units by the warp's slope.
        (ShadowMethod::Evsm | ShadowMethod::Evsm2, ColourFormat::Half | ColourFormat::Rg16) => 1e-3,
        (ShadowMethod::Evsm | ShadowMethod::Evsm2, ColourFormat::Full | ColourFormat::Rg32) => 1e-4,
        // The share of the two-point distribution mixed in (Peters and Klein use 3·10⁻⁵ for
        // full floats).
        (ShadowMethod::Msm | ShadowMethod::MsmHausdorff, ColourFormat::Half) => 5e-3,
        (ShadowMethod::Msm | ShadowMethod::MsmHausdorff, ColourFormat::Full) => 3e-5,
        _ => 0.0,
    }
}

/// Gives every moment layer of `layers` the terms of `format`.
pub fn set_terms(layers: &mut [GpuLayer], format: ColourFormat) {
    for layer in layers {
        let method = ShadowMethod::ALL.iter().copied().find(|m| *m as u32 == layer.method).unwrap_or_default();
        if method.moments() {
            layer.warp = evsm_warp(format);
            layer.moment_bias = moment_bias(method, format);
        }
    }
}

/// Farthest distance a half float holds (R16F radial's clear value).
pub const HALF_MAX: f64 = 65504.0;

/// What a colour layer is cleared to: the moments of depth 1 (nothing drawn, fully lit), as
/// `encode_moments` in moments.wgsl makes them; for depth in colour the farthest value.
#[must_use]
pub fn far_moments(layer: &GpuLayer) -> wgpu::Color {
    let (r, g, b, a) = if layer.method == ShadowMethod::RadialR16f as u32 {
        (HALF_MAX, 0.0, 0.0, 0.0)
    } else if layer.method == ShadowMethod::DepthR32f as u32 {
        (1.0, 0.0, 0.0, 0.0)
    } else if layer.method == ShadowMethod::Evsm as u32 {
        // Depth 1 is 1 after the -1..1 remap.
        let (p, n) = ((layer.warp[0] as f64).exp(), -(-layer.warp[1] as f64).exp());
        (p, p * p, n, n * n)
    } else if layer.method == ShadowMethod::Evsm2 as u32 {
        let p = (layer.warp[0] as f64).exp();
        (p, p * p, 0.0, 0.0)
    } else if layer.method == ShadowMethod::Msm as u32 || layer.method == ShadowMethod::MsmHausdorff as u32 {
        (1.0, 1.0, 1.0, 1.0)
    } else {
        (1.0, 1.0, 0.0, 0.0)
    };
    wgpu::Color { r, g, b, a }
}

/// What the colour atlas is: its format (`None`: no light uses one), the depth texels along a
/// side per colour texel, and whether compute stores moments into it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ColourLayout {
    /// The format.
    pub format: Option<ColourFormat>,
    /// Depth texels along a side per colour texel.
    pub scale: u32,
    /// Moments resolved from depth are made by a compute dispatch, which stores into the atlas
    /// (see [`super::moment_compute`]).
    pub storage: bool,
}

impl ColourLayout {
    /// No colour maps.
    pub const NONE: ColourLayout = ColourLayout { format: None, scale: 1, storage: false };
}

/// The colour maps: an array page for page with the depth maps, tile for tile at `1 / scale`
/// of their side (a tile's corner and side are the same shares of its page), and a scratch page
/// for the blur. Without colour-map lights it is a 1x1 stand-in the main pass can bind.
pub struct ColourMaps {
    /// Its format, `None` for the stand-in.
    pub format: Option<ColourFormat>,
    /// Depth texels along a side per colour texel.
    pub scale: u32,
    /// Compute stores into it.
    pub storage: bool,
    /// One render view per layer.
    pub layer_views: Vec<wgpu::TextureView>,
    /// The whole array, for sampling.
    pub array_view: wgpu::TextureView,
    pub(super) scratch_view: wgpu::TextureView,
}

impl ColourMaps {
    /// `layers` layers of `(page / scale)`² texels in the layout's format, or the stand-in when
    /// it has none.
    pub fn new(device: &wgpu::Device, layout: ColourLayout, page: u32, layers: u32) -> Self {
        let ColourLayout { format, scale, storage } = layout;
        let scale = scale.clamp(1, page.max(1));
        let (size, layers) = if format.is_some() { (page / scale, layers) } else { (1, 2) };
        let tex_format = format.unwrap_or(ColourFormat::Half).texture();
        let storage = storage && format.is_some();
        let extra = if storage { wgpu::TextureUsages::STORAGE_BINDING } else { wgpu::TextureUsages::empty() };
        let LayeredTarget { layer_views, array_view, .. } =
            LayeredTarget::of(&render_target(device, "moment maps", tex_format, size, layers, extra), "moment maps");
        let scratch_view = render_target(device, "moment scratch", tex_format, size, 1, wgpu::TextureUsages::empty())
            .create_view(&Default::default());
        ColourMaps { format, scale, storage, layer_views, array_view, scratch_view }
    }

    /// Its layout.
    pub fn layout(&self) -> ColourLayout {
        ColourLayout { format: self.format, scale: self.scale, storage: self.storage }
    }
}

/// Depth texels along a side per texel of the colour atlas for `methods` (a bit per
/// [`ShadowMethod`]) with moments made from `source` ([`MomentSource::colour_scale`]).
#[must_use]
pub fn colour_scale(methods: u32, source: MomentSource) -> u32 {
    let depth_in_colour =
        ShadowMethod::ALL.iter().any(|m| m.colour_depth_bits() > 0 && methods & (1 << *m as u32) != 0);
    source.colour_scale(depth_in_colour)
}

#[cfg(test)]
mod tests {
    use super::*;
    use bytemuck::Zeroable;

    fn bit(m: ShadowMethod) -> u32 {
        1 << m as u32
    }

    #[test]
    fn the_format_follows_the_methods_in_use_and_the_device() {
        let pcf = bit(ShadowMethod::Pcf3);
        assert_eq!(colour_format(pcf, MomentBits::Auto, true), Ok(None));
        assert_eq!(colour_format(pcf | bit(ShadowMethod::Msm), MomentBits::Half, true), Ok(Some(ColourFormat::Half)));
        assert_eq!(colour_format(bit(ShadowMethod::Msm), MomentBits::Full, true), Ok(Some(ColourFormat::Full)));
        assert!(colour_format(bit(ShadowMethod::Msm), MomentBits::Full, false).is_err());
        // Auto never asks for what the device cannot do.
        for m in ShadowMethod::ALL.iter().filter(|m| m.moments()) {
            let half = if m.moment_count() == 2 { ColourFormat::Rg16 } else { ColourFormat::Half };
            assert_eq!(colour_format(bit(*m), MomentBits::Auto, false), Ok(Some(half)));
            let auto = colour_format(bit(*m), MomentBits::Auto, true).unwrap().unwrap();
            assert_eq!(auto.bits(), m.moment_bits());
        }
        // Depth in colour: one channel as wide as the method, four when sharing with moments.
        let (r16, r32) = (bit(ShadowMethod::RadialR16f), bit(ShadowMethod::DepthR32f));
        assert_eq!(colour_format(r16, MomentBits::Auto, false), Ok(Some(ColourFormat::R16)));
        assert_eq!(colour_format(r16 | r32, MomentBits::Auto, true), Ok(Some(ColourFormat::R32)));
        assert!(colour_format(r32, MomentBits::Auto, false).is_err());
        let shared = colour_format(r32 | bit(ShadowMethod::Evsm), MomentBits::Half, true);
        assert_eq!(shared, Ok(Some(ColourFormat::Full)));
        // Two moments take two channels.
        assert_eq!(colour_format(r16 | bit(ShadowMethod::Vsm), MomentBits::Auto, false), Ok(Some(ColourFormat::Rg16)));
        assert_eq!(colour_format(bit(ShadowMethod::Vsm), MomentBits::Auto, true), Ok(Some(ColourFormat::Rg32)));
    }

    #[test]
    fn evsm_warps_fit_their_format() {
        // The square of the positive warp at depth 1 must be a finite number of the format.
        assert!((2.0 * evsm_warp(ColourFormat::Half)[0]).exp() < 65504.0);
        assert!((2.0 * evsm_warp(ColourFormat::Full)[0] as f64).exp() < f32::MAX as f64);
    }

    #[test]
    fn terms_reach_only_moment_layers() {
        let mut layers = [GpuLayer::zeroed(); 2];
        layers[0].method = ShadowMethod::Evsm as u32;
        layers[1].method = ShadowMethod::Pcss as u32;
        set_terms(&mut layers, ColourFormat::Full);
        assert_eq!(layers[0].warp, evsm_warp(ColourFormat::Full));
        assert!(layers[0].moment_bias > 0.0);
        assert_eq!((layers[1].warp, layers[1].moment_bias), ([0.0; 2], 0.0));
    }

    #[test]
    fn empty_layers_clear_to_the_moments_of_the_far_plane() {
        let mut layer = GpuLayer::zeroed();
        layer.method = ShadowMethod::Vsm as u32;
        assert_eq!(far_moments(&layer), wgpu::Color { r: 1.0, g: 1.0, b: 0.0, a: 0.0 });
        layer.method = ShadowMethod::Evsm as u32;
        layer.warp = [2.0, 3.0];
        let c = far_moments(&layer);
        assert!((c.r - 2f64.exp()).abs() < 1e-9 && (c.g - 4f64.exp()).abs() < 1e-9);
        assert!((c.b + (-3f64).exp()).abs() < 1e-9 && (c.a - (-6f64).exp()).abs() < 1e-9);
    }
}
