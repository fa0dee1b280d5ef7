//! Moment maps resolved from multisampled depth (MSAA): a moment layer drawn depth-only into a
//! multisampled scratch texture at the moment map's size, then resolved from it into the moment
//! atlas (`resolved_samples` in blur.wgsl), one layer after another. WebGPU has no multisampled
//! arrays, so the layers take turns in the one scratch texture; every device allows 4 samples a
//! texel of a depth format, some 2 and 8 ([`sample_counts`]).

/// The sample counts above one that moment maps may be resolved from on `adapter` (a bit per
/// count: 2, 4, 8), with the device's `features`: what depth maps of every shadow-depth format
/// take, 4 always, 2 and 8 where the adapter says so and the device has
/// `TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES`. None on GL: there (llvmpipe, wgpu 30) a shader
/// reading multisampled depth got zeros, every texel at the light, everything shadowed.
#[must_use]
pub fn sample_counts(adapter: &wgpu::Adapter, features: wgpu::Features) -> u32 {
    if adapter.get_info().backend == wgpu::Backend::Gl {
        return 0;
    }
    let specific = features.contains(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES);
    let formats = [wgpu::TextureFormat::Depth32Float, wgpu::TextureFormat::Depth16Unorm];
    [2, 4, 8]
        .into_iter()
        .filter(|&n| {
            n == 4
                || specific
                    && formats.iter().all(|&f| adapter.get_texture_format_features(f).flags.sample_count_supported(n))
        })
        .fold(0, |mask, n| mask | n)
}

/// The samples a texel moment maps get when `wanted` are asked for where `counts` are allowed
/// ([`sample_counts`]): the most allowed up to `wanted`, and 1 (no MSAA) at least.
#[must_use]
pub fn usable(counts: u32, wanted: u32) -> u32 {
    [8, 4, 2].into_iter().find(|&n| n <= wanted && counts & n != 0).unwrap_or(1)
}

/// The multisampled depth a moment layer is drawn into before its resolve, made anew only when
/// a layer needs more room, other samples or another format.
pub struct SampleScratch {
    samples: u32,
    side: u32,
    format: wgpu::TextureFormat,
    /// The whole texture, to draw into and to resolve from.
    pub view: wgpu::TextureView,
}

impl SampleScratch {
    /// A scratch of `side`² texels of `samples` samples of `format`.
    pub fn new(device: &wgpu::Device, samples: u32, side: u32, format: wgpu::TextureFormat) -> Self {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("multisampled moment depth"),
            size: wgpu::Extent3d { width: side, height: side, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: samples,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        SampleScratch { samples, side, format, view: texture.create_view(&Default::default()) }
    }

    /// It holds a layer of `side` texels of `samples` samples of `format`.
    #[must_use]
    pub fn fits(&self, samples: u32, side: u32, format: wgpu::TextureFormat) -> bool {
        self.samples == samples && self.side >= side && self.format == format
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_samples_used_are_the_most_allowed_up_to_those_asked() {
        let four = 4;
        assert_eq!([1, 2, 4, 8].map(|n| usable(four, n)), [1, 1, 4, 4]);
        let all = 2 | 4 | 8;
        assert_eq!([1, 2, 4, 8].map(|n| usable(all, n)), [1, 2, 4, 8]);
        assert_eq!(usable(all, 0), 1);
        assert_eq!(usable(all, u32::MAX), 8);
        assert_eq!(usable(0, 8), 1);
    }
}
