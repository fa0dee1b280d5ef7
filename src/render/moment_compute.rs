//! Moment maps made from depth in one compute dispatch (`cs_resolve` in moment_compute.wgsl):
//! each workgroup resolves a block of a tile's moments and the blur's reach around it into shared
//! memory, blurs them along rows and columns there and stores the block into the moment atlas,
//! which it writes once. The full-screen passes of [`super::moments::MomentBlur`] stay for what
//! this cannot do: a device without compute shaders, a format it cannot store into (half-float
//! pairs, unless the adapter says otherwise), a blur wider than [`RESOLVE_MAX_RADIUS`], and moments
//! drawn as colour targets.

use super::gpu_types::{RESOLVE_BLOCK, RESOLVE_MAX_RADIUS};
use super::shaders::{BLUR, Composed, MOMENT_COMPUTE, MOMENTS};
use super::timing::Stamps;
use super::uniform_array::UniformArray;

/// Bytes of shared memory a workgroup of `cs_resolve` takes: a span of moments (four floats) the
/// block's side plus the widest blur's reach each side.
pub const WORKGROUP_BYTES: u32 = (RESOLVE_BLOCK + 2 * RESOLVE_MAX_RADIUS).pow(2) * 16;

// Each invocation keeps at most two texels of the rows' blur (`rows` in `cs_resolve`).
const _: () = assert!((RESOLVE_BLOCK + 2 * RESOLVE_MAX_RADIUS) * RESOLVE_BLOCK <= 2 * RESOLVE_BLOCK * RESOLVE_BLOCK);

/// The moment formats compute may store into, with their WGSL names.
const STORED: [(wgpu::TextureFormat, &str); 4] = [
    (wgpu::TextureFormat::Rgba16Float, "rgba16float"),
    (wgpu::TextureFormat::Rgba32Float, "rgba32float"),
    (wgpu::TextureFormat::Rg16Float, "rg16float"),
    (wgpu::TextureFormat::Rg32Float, "rg32float"),
];

/// The WGSL name of `format` as a storage texture's, for the moment formats compute may store.
#[must_use]
pub fn storage_name(format: wgpu::TextureFormat) -> Option<&'static str> {
    STORED.iter().find(|(f, _)| *f == format).map(|(_, name)| *name)
}

/// True when a device with `limits` that runs compute shaders (`computes`) and allows `usages`
/// of `format` can make moment maps of that format in compute: it stores into the format and
/// gives a workgroup the shared memory it needs.
#[must_use]
pub fn stores(format: wgpu::TextureFormat, usages: wgpu::TextureUsages, computes: bool, limits: &wgpu::Limits) -> bool {
    computes
        && storage_name(format).is_some()
        && usages.contains(wgpu::TextureUsages::STORAGE_BINDING)
        && limits.max_compute_workgroup_storage_size >= WORKGROUP_BYTES
        && limits.max_compute_invocations_per_workgroup >= RESOLVE_BLOCK * RESOLVE_BLOCK
}

/// The moment formats a device makes in compute.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ComputeStores(u8);

impl ComputeStores {
    /// What `adapter` and its `device` allow ([`stores`]): WebGPU guarantees storage for four
    /// channels and for two 32-bit floats; half-float pairs where the device has
    /// `TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES` and the adapter says so.
    pub fn of(adapter: &wgpu::Adapter, device: &wgpu::Device) -> Self {
        let computes = super::depth_reduction::computes(adapter);
        let features = device.features();
        let usages = |f: wgpu::TextureFormat| {
            if features.contains(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES) {
                adapter.get_texture_format_features(f).allowed_usages
            } else {
                f.guaranteed_format_features(features).allowed_usages
            }
        };
        let limits = device.limits();
        let bits = STORED.iter().enumerate().filter(|(_, (f, _))| stores(*f, usages(*f), computes, &limits));
        ComputeStores(bits.fold(0, |b, (i, _)| b | 1 << i))
    }

    /// Moments of `format` are made in compute here.
    #[must_use]
    pub fn stores(self, format: wgpu::TextureFormat) -> bool {
        STORED.iter().position(|(f, _)| *f == format).is_some_and(|i| self.0 & 1 << i != 0)
    }

    /// Some moments are.
    #[must_use]
    pub fn any(self) -> bool {
        self.0 != 0
    }
}

/// The composed module of `cs_resolve` storing into `format`, reading depth from the atlas or
/// (with `multisampled`) from one layer's multisampled depth: the moments and the blur's
/// functions, the dispatch's own file, and the declarations of the atlas it stores into and of
/// where its moments come from.
#[must_use]
pub fn module_text(format: wgpu::TextureFormat, multisampled: bool) -> Option<Composed> {
    let name = storage_name(format)?;
    let source = if multisampled { "resolved_samples" } else { "resolved" };
    let out = format!(
        "@group(1) @binding(4) var moments_out: texture_storage_2d_array<{name}, write>;\n\
         fn resolved_here(q: vec2<i32>) -> vec4<f32> {{ return {source}(q); }}\n"
    );
    Some(Composed::new(&[MOMENTS, BLUR, MOMENT_COMPUTE]).then("the moment atlas (src/render/moment_compute.rs)", &out))
}

/// One tile `cs_resolve` makes: its uniform in the blur's array, its layer's in the shadow pass's,
/// and its side in moment texels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ComputeTile {
    /// Index of its `Blur` block.
    pub blur: usize,
    /// Index of its layer's `GpuLayer` block.
    pub layer: usize,
    /// Its side in texels of the moment map.
    pub size: u32,
}

/// What one dispatch of `cs_resolve` reads and writes.
pub struct ComputeWork<'a> {
    /// The depth atlas, its whole array; or, when `multisampled`, one layer's multisampled depth.
    pub depth: &'a wgpu::TextureView,
    /// `depth` is multisampled.
    pub multisampled: bool,
    /// The moment atlas, its whole array (made with storage use).
    pub moments: &'a wgpu::TextureView,
    /// The tiles' `Blur` blocks.
    pub blur: &'a UniformArray,
    /// The shadow pass's layers.
    pub layers: &'a UniformArray,
    /// The tiles to make.
    pub tiles: &'a [ComputeTile],
}

/// Workgroups along each side of a tile of `size` texels.
#[must_use]
pub fn groups(size: u32) -> u32 {
    size.div_ceil(RESOLVE_BLOCK)
}

/// The compute pipelines and the layouts of what they read (the depth atlas, or one layer's
/// multisampled depth) and write (the moment atlas), indexed by whether depth is multisampled.
pub struct MomentCompute {
    pipelines: [wgpu::ComputePipeline; 2],
    io_layouts: [wgpu::BindGroupLayout; 2],
}

impl MomentCompute {
    /// The pipeline storing into `format` (one [`stores`] allows), reading each tile's `Blur`
    /// from `blur` and its layer from `layers` (both visible to compute).
    pub fn new(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        blur: &wgpu::BindGroupLayout,
        layers: &wgpu::BindGroupLayout,
    ) -> Option<Self> {
        let both = [false, true].map(|multisampled| Self::pipeline(device, format, [blur, layers], multisampled));
        let [Some((plain, plain_io)), Some((samples, samples_io))] = both else { return None };
        Some(MomentCompute { pipelines: [plain, samples], io_layouts: [plain_io, samples_io] })
    }

    fn pipeline(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        [blur, layers]: [&wgpu::BindGroupLayout; 2],
        multisampled: bool,
    ) -> Option<(wgpu::ComputePipeline, wgpu::BindGroupLayout)> {
        let module = module_text(format, multisampled)?.module(device);
        let (binding, view_dimension) =
            if multisampled { (3, wgpu::TextureViewDimension::D2) } else { (2, wgpu::TextureViewDimension::D2Array) };
        let io_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("moment compute io"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension,
                        multisampled,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 4,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::WriteOnly,
                        format,
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                    },
                    count: None,
                },
            ],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("moment compute"),
            bind_group_layouts: &[Some(blur), Some(&io_layout), Some(layers)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("cs_resolve"),
            layout: Some(&layout),
            module: &module,
            entry_point: Some("cs_resolve"),
            compilation_options: Default::default(),
            cache: None,
        });
        Some((pipeline, io_layout))
    }

    /// Makes `work`'s tiles in one compute pass, stamped as the frame's next shadow pass.
    pub(super) fn encode(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        work: ComputeWork<'_>,
        stamps: &mut Stamps<'_>,
    ) {
        let ComputeWork { depth, multisampled, moments, blur, layers, tiles } = work;
        let which = usize::from(multisampled);
        let io = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("moment compute io"),
            layout: &self.io_layouts[which],
            entries: &[
                wgpu::BindGroupEntry {
                    binding: if multisampled { 3 } else { 2 },
                    resource: wgpu::BindingResource::TextureView(depth),
                },
                wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::TextureView(moments) },
            ],
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("moments from depth"),
            timestamp_writes: stamps.next_compute(),
        });
        pass.set_pipeline(&self.pipelines[which]);
        pass.set_bind_group(1, &io, &[]);
        for t in tiles {
            pass.set_bind_group(0, &blur.bind_group, &[blur.offset(t.blur)]);
            pass.set_bind_group(2, &layers.bind_group, &[layers.offset(t.layer)]);
            pass.dispatch_workgroups(groups(t.size), groups(t.size), 1);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_workgroup_fits_what_every_webgpu_device_allows() {
        let least = wgpu::Limits::downlevel_defaults();
        assert!(WORKGROUP_BYTES <= least.max_compute_workgroup_storage_size);
        assert!(RESOLVE_BLOCK * RESOLVE_BLOCK <= least.max_compute_invocations_per_workgroup);
    }

    #[test]
    fn only_what_the_device_stores_is_made_in_compute() {
        let limits = wgpu::Limits::default();
        let guaranteed = |f: wgpu::TextureFormat| f.guaranteed_format_features(wgpu::Features::empty()).allowed_usages;
        let made = |f: wgpu::TextureFormat| stores(f, guaranteed(f), true, &limits);
        assert!(made(wgpu::TextureFormat::Rgba16Float) && made(wgpu::TextureFormat::Rg32Float));
        // Half-float pairs are not a storage format WebGPU guarantees; an adapter may allow them.
        assert!(!made(wgpu::TextureFormat::Rg16Float));
        let adapter_says = guaranteed(wgpu::TextureFormat::Rg16Float) | wgpu::TextureUsages::STORAGE_BINDING;
        assert!(stores(wgpu::TextureFormat::Rg16Float, adapter_says, true, &limits));
        // Not without compute, not a depth-in-colour format, not without the shared memory.
        assert!(!stores(
            wgpu::TextureFormat::Rgba16Float,
            guaranteed(wgpu::TextureFormat::Rgba16Float),
            false,
            &limits
        ));
        assert!(!made(wgpu::TextureFormat::R32Float));
        let small = wgpu::Limits { max_compute_workgroup_storage_size: WORKGROUP_BYTES - 1, ..limits };
        let f = wgpu::TextureFormat::Rgba32Float;
        assert!(!stores(f, guaranteed(f), true, &small));
        // The mask answers per format.
        let some = ComputeStores(0b0001);
        assert!(some.stores(wgpu::TextureFormat::Rgba16Float) && some.any());
        assert!(!some.stores(wgpu::TextureFormat::Rg32Float) && !some.stores(wgpu::TextureFormat::R16Float));
        assert!(!ComputeStores::default().any());
    }

    #[test]
    fn groups_cover_every_texel_of_a_tile() {
        assert_eq!(groups(1), 1);
        assert_eq!(groups(RESOLVE_BLOCK), 1);
        assert_eq!(groups(RESOLVE_BLOCK + 1), 2);
        assert_eq!(groups(2048), 2048 / RESOLVE_BLOCK);
    }
}
