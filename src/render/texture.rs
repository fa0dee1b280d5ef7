//! Base-colour textures on the GPU: each image uploaded once with its mipmaps (sRGB), each
//! texture a bind group of its image and a sampler made from its glTF sampler, and a white
//! texture for untextured materials.

use crate::assets::{Filter, ImageData, Sampling, TextureLibrary, Wrap};
use crate::components::Texture;
use std::collections::HashMap;
use std::sync::Arc;

/// Bind group 2 of every pipeline: the texture of the object's material.
pub struct MaterialTextures {
    /// Layout of bind group 2.
    pub layout: wgpu::BindGroupLayout,
    white: wgpu::BindGroup,
    /// One bind group per texture of the library, in its order.
    textures: Vec<wgpu::BindGroup>,
    uploads: Uploads,
}

/// Images and samplers made so far.
#[derive(Default)]
struct Uploads {
    /// Uploaded images, by the address of their data (each held, so no other image can take its
    /// address): textures that share an image share it.
    images: HashMap<*const ImageData, (Arc<ImageData>, wgpu::TextureView)>,
    samplers: HashMap<Sampling, wgpu::Sampler>,
}

impl MaterialTextures {
    /// The layout and the white texture.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Self {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("material texture"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let mut uploads = Uploads::default();
        let white = Arc::new(ImageData::new("white", 1, 1, vec![255; 4]));
        let white = uploads.bind(device, queue, &layout, &white, Sampling::default());
        MaterialTextures { layout, white, textures: Vec::new(), uploads }
    }

    /// Uploads the textures added to `library` since the last call.
    pub fn upload_new(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, library: &TextureLibrary) {
        for texture in &library.all()[self.textures.len().min(library.all().len())..] {
            let group = self.uploads.bind(device, queue, &self.layout, &texture.image, texture.sampling);
            self.textures.push(group);
        }
    }

    /// The bind group of `texture` (white for none, or one not uploaded).
    pub fn bind_group(&self, texture: Option<Texture>) -> &wgpu::BindGroup {
        texture.and_then(|t| self.textures.get(t.0)).unwrap_or(&self.white)
    }
}

impl Uploads {
    /// A bind group of `image` (uploaded the first time) and a sampler for `sampling`.
    fn bind(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        layout: &wgpu::BindGroupLayout,
        image: &Arc<ImageData>,
        sampling: Sampling,
    ) -> wgpu::BindGroup {
        let (_, view) =
            self.images.entry(Arc::as_ptr(image)).or_insert_with(|| (image.clone(), upload(device, queue, image)));
        let view = view.clone();
        let sampler = self.samplers.entry(sampling).or_insert_with(|| sampler(device, sampling)).clone();
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(&image.name),
            layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&view) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::Sampler(&sampler) },
            ],
        })
    }
}

/// The image and its mipmaps as an sRGB texture; levels larger than the device allows are left
/// out, so the largest level that fits becomes level 0.
fn upload(device: &wgpu::Device, queue: &wgpu::Queue, image: &ImageData) -> wgpu::TextureView {
    let max = device.limits().max_texture_dimension_2d;
    let first = (0..image.levels.len()).find(|&l| {
        let (w, h) = image.level_size(l);
        w <= max && h <= max
    });
    let first = first.unwrap_or(image.levels.len().saturating_sub(1));
    let (width, height) = image.level_size(first);
    let levels = (image.levels.len() - first).max(1) as u32;
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(&image.name),
        size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        mip_level_count: levels,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8UnormSrgb,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (mip, level) in image.levels.iter().skip(first).enumerate() {
        let (w, h) = image.level_size(first + mip);
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: mip as u32,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            level,
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(4 * w), rows_per_image: Some(h) },
            wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
        );
    }
    texture.create_view(&Default::default())
}

/// A sampler as the glTF sampler asks: without mipmap filtering only level 0 is read.
fn sampler(device: &wgpu::Device, s: Sampling) -> wgpu::Sampler {
    let filter = |f| match f {
        Filter::Nearest => wgpu::FilterMode::Nearest,
        Filter::Linear => wgpu::FilterMode::Linear,
    };
    let address = |w| match w {
        Wrap::Repeat => wgpu::AddressMode::Repeat,
        Wrap::MirroredRepeat => wgpu::AddressMode::MirrorRepeat,
        Wrap::ClampToEdge => wgpu::AddressMode::ClampToEdge,
    };
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("material"),
        address_mode_u: address(s.wrap[0]),
        address_mode_v: address(s.wrap[1]),
        mag_filter: filter(s.mag),
        min_filter: filter(s.min),
        mipmap_filter: match s.mipmap {
            Some(Filter::Linear) => wgpu::MipmapFilterMode::Linear,
            _ => wgpu::MipmapFilterMode::Nearest,
        },
        lod_max_clamp: if s.mipmap.is_some() { 32.0 } else { 0.0 },
        ..Default::default()
    })
}

/// A texture array both drawn into (one view per layer) and sampled (one view of all of them):
/// the shadow atlas's pages, the static atlas's and the colour atlas's.
pub struct LayeredTarget {
    /// One render view per layer.
    pub layer_views: Vec<wgpu::TextureView>,
    /// The whole array, for sampling.
    pub array_view: wgpu::TextureView,
}

/// A texture of `size`² texels and `layers` layers in `format`, drawn into and sampled (and used
/// as `extra` says too).
pub fn render_target(
    device: &wgpu::Device,
    label: &str,
    format: wgpu::TextureFormat,
    size: u32,
    layers: u32,
    extra: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width: size, height: size, depth_or_array_layers: layers },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING | extra,
        view_formats: &[],
    })
}

impl LayeredTarget {
    /// `layers` layers of `size`² texels in `format` (the views keep the texture alive).
    pub fn new(device: &wgpu::Device, label: &str, format: wgpu::TextureFormat, size: u32, layers: u32) -> Self {
        Self::of(&render_target(device, label, format, size, layers, wgpu::TextureUsages::empty()), label)
    }

    /// The views of `texture`, a [`render_target`] (one per layer, and the whole array).
    pub fn of(texture: &wgpu::Texture, label: &str) -> Self {
        let layer_views = (0..texture.depth_or_array_layers())
            .map(|layer| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    label: Some(label),
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: layer,
                    array_layer_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let array_view = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some(label),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        LayeredTarget { layer_views, array_view }
    }
}
