//! The shadow-map viewer: the shadow atlas as it is laid out, page by page, every layer drawn in
//! its own tile with its depth remapped to grey, for the window's panel to show and label.

use super::gpu_types::{GpuLayer, MAX_LAYERS};
use super::shaders::{Composed, MAP_VIEW};
use crate::shadow::view_distance;

/// Side of one atlas page in the picture, in pixels.
pub const PAGE: u32 = 512;
/// Pages across the picture.
pub const COLUMNS: u32 = 2;
/// The atlas's format, as egui shows textures.
pub const ATLAS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// The bytes of one chunk of the shader's layers: three vectors a layer (a multiple of 256, the
/// most any device asks a dynamic offset to be aligned to).
const CHUNK_BYTES: u64 = (MAX_LAYERS * 3 * 16) as u64;
const _: () = assert!(CHUNK_BYTES.is_multiple_of(256));

/// A buffer of the layers' terms for `chunks` chunks of [`MAX_LAYERS`].
fn terms_buffer(device: &wgpu::Device, chunks: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("map view terms"),
        size: chunks as u64 * CHUNK_BYTES,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// What the shader needs of layer `layer` to find its tile and turn what it keeps back into
/// distance spread over grey: its depth terms, its near and far distances, whether it is a
/// perspective one, its light's method (which says which map to read), EVSM's positive
/// exponent, and its tile (corner and side as shares of the page) and page.
#[must_use]
pub fn view_terms(layer: &GpuLayer) -> [[f32; 4]; 3] {
    let terms = glam::Vec2::from(layer.depth_terms);
    let perspective = layer.perspective == 1;
    let (near, far) = (view_distance(terms, 0.0, perspective), view_distance(terms, 1.0, perspective));
    let [x, y, side, _] = layer.tile;
    [
        [terms.x, terms.y, near, far],
        [perspective as u32 as f32, layer.method as f32, layer.warp[0], 0.0],
        [x, y, side, layer.page as f32],
    ]
}

/// The size of the picture of `pages` atlas pages, in pixels.
#[must_use]
pub fn atlas_size(pages: u32) -> (u32, u32) {
    let pages = pages.max(1);
    (COLUMNS.min(pages) * PAGE, pages.div_ceil(COLUMNS) * PAGE)
}

/// The pages `layers` take (one more than the last one's index).
#[must_use]
pub fn pages_of(layers: &[GpuLayer]) -> u32 {
    layers.iter().map(|l| l.page.saturating_add(1)).max().unwrap_or(1)
}

/// Where `layer`'s tile is in the picture: its corner and side, in pixels (at least one, never
/// past its page).
#[must_use]
pub fn tile_rect(layer: &GpuLayer) -> [f32; 3] {
    let (column, row) = (layer.page % COLUMNS, layer.page / COLUMNS);
    let [x, y, side, _] = layer.tile.map(|v| if v.is_finite() { v.clamp(0.0, 1.0) } else { 0.0 });
    let page = PAGE as f32;
    let side = (side * page).clamp(1.0, page);
    let at = |offset: u32, share: f32| offset as f32 * page + (share * page).min(page - side);
    [at(column, x), at(row, y), side]
}

/// The viewer's pipeline, its uniform and the atlas it draws.
pub struct MapView {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    terms: wgpu::Buffer,
    atlas: Option<(wgpu::Texture, wgpu::TextureView)>,
    /// Atlases made so far.
    generation: u64,
}

impl MapView {
    /// The viewer's pipeline.
    pub fn new(device: &wgpu::Device) -> MapView {
        let module = Composed::new(&[MAP_VIEW]).module(device);
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty,
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("map view"),
            entries: &[
                entry(
                    0,
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: true,
                        min_binding_size: std::num::NonZeroU64::new(CHUNK_BYTES),
                    },
                ),
                // The depth atlas, bound as unfilterable floats (GLSL cannot load from a depth
                // texture).
                entry(
                    1,
                    wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                ),
                entry(
                    2,
                    wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                ),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("map view"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("map view"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_tile"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_tile"),
                compilation_options: Default::default(),
                targets: &[Some(ATLAS_FORMAT.into())],
            }),
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            multiview_mask: None,
            cache: None,
        });
        let terms = terms_buffer(device, 1);
        MapView { pipeline, layout, terms, atlas: None, generation: 0 }
    }

    /// The atlas as last drawn, and how many atlases have been made (none before the first draw).
    pub fn atlas(&self) -> Option<(&wgpu::Texture, &wgpu::TextureView, u64)> {
        self.atlas.as_ref().map(|(texture, view)| (texture, view, self.generation))
    }

    /// Draws `layers` of `maps` (the depth array and the colour maps' array) into the atlas and
    /// gives it back.
    pub fn draw(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        (maps, colours): (&wgpu::TextureView, &wgpu::TextureView),
        layers: &[GpuLayer],
    ) -> &wgpu::TextureView {
        let (w, h) = atlas_size(pages_of(layers));
        if self.atlas.as_ref().is_none_or(|(t, _)| (t.width(), t.height()) != (w, h)) {
            let texture = device.create_texture(&wgpu::TextureDescriptor {
                label: Some("shadow-map atlas"),
                size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: ATLAS_FORMAT,
                // Copied from to read the picture back (`render::read_map_atlas`).
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            });
            let view = texture.create_view(&Default::default());
            self.atlas = Some((texture, view));
            self.generation += 1;
        }
        // The shader sees MAX_LAYERS layers at a time: the layers go in chunks of that many, each
        // drawn with its chunk bound (a virtual map's pages are layers too, hundreds of them).
        let chunks = layers.len().div_ceil(MAX_LAYERS).max(1);
        if self.terms.size() < chunks as u64 * CHUNK_BYTES {
            self.terms = terms_buffer(device, chunks);
        }
        let terms: Vec<[[f32; 4]; 3]> = layers.iter().map(view_terms).collect();
        queue.write_buffer(&self.terms, 0, bytemuck::cast_slice(&terms));
        let chunk =
            wgpu::BufferBinding { buffer: &self.terms, offset: 0, size: std::num::NonZeroU64::new(CHUNK_BYTES) };
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("map view"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::Buffer(chunk) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(maps) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(colours) },
            ],
        });
        let (_, view) = self.atlas.as_ref().expect("made above");
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("map view") });
        {
            let mut pass = super::colour_pass(&mut encoder, "map view", view, Some(wgpu::Color::BLACK));
            pass.set_pipeline(&self.pipeline);
            for (c, chunk) in layers.chunks(MAX_LAYERS).enumerate() {
                pass.set_bind_group(0, &bind, &[(c as u64 * CHUNK_BYTES) as u32]);
                for (i, layer) in (0..).zip(chunk) {
                    let [x, y, side] = tile_rect(layer);
                    pass.set_viewport(x, y, side, side, 0.0, 1.0);
                    pass.draw(0..3, i..i + 1);
                }
            }
        }
        queue.submit([encoder.finish()]);
        view
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::ShadowMethod;
    use bytemuck::Zeroable;

    #[test]
    fn the_picture_lays_the_pages_out_in_rows_of_two_and_each_tile_where_it_is() {
        assert_eq!(atlas_size(3), (2 * PAGE, 2 * PAGE));
        assert_eq!(atlas_size(1), (PAGE, PAGE));
        assert_eq!(atlas_size(0), (PAGE, PAGE), "an empty atlas still exists");
        let layer = |page, tile| GpuLayer { page, tile, ..GpuLayer::zeroed() };
        assert_eq!(pages_of(&[layer(0, [0.0; 4]), layer(2, [0.0; 4])]), 3);
        assert_eq!(tile_rect(&layer(0, [0.5, 0.25, 0.25, 0.0])), [256.0, 128.0, 128.0]);
        assert_eq!(tile_rect(&layer(3, [0.0, 0.0, 0.5, 0.0])), [512.0, 512.0, 256.0], "the fourth page, bottom right");
        // A tile too small to see still gets a pixel; nonsense stays on its page.
        assert_eq!(tile_rect(&layer(0, [0.999, 0.0, 1e-6, 0.0])), [511.0, 0.0, 1.0]);
        assert_eq!(tile_rect(&layer(0, [f32::NAN, 2.0, f32::INFINITY, 0.0])), [0.0, 511.0, 1.0]);
    }

    #[test]
    fn view_terms_give_the_layers_near_and_far() {
        let proj = glam::camera::rh::proj::directx::perspective(1.0, 1.0, 0.5, 20.0);
        let layer = GpuLayer {
            depth_terms: crate::shadow::depth_terms(&proj).to_array(),
            perspective: 1,
            ..GpuLayer::zeroed()
        };
        let [[_, _, near, far], [p, ..], _] = view_terms(&layer);
        assert!((near - 0.5).abs() < 1e-4 && (far - 20.0).abs() < 1e-2 && p == 1.0, "{near} {far}");
        let evsm = GpuLayer { method: ShadowMethod::Evsm as u32, warp: [5.0, 3.0], ..layer };
        assert_eq!(view_terms(&evsm)[1][1..3], [ShadowMethod::Evsm as u32 as f32, 5.0], "the method says which map");
    }
}
