//! The bare depth pass: what drawing a frame's shadow casters into its layers costs with nothing
//! else. One rigid pipeline with no fragment stage; every caster of a layer drawn at its
//! placement (a skinned one unposed), one instanced call per mesh and layer; no culling of its
//! own (it takes the frame's lists as given), no cache, no cut-outs, no bookkeeping.
//! `umbra bench --shadow-pass` times umbra's shadow pass against it, drawing the same casters
//! into tiles of the same size, place and format.

use super::frame::FrameData;
use super::growing::GrowingBuffer;
use super::instances::{LayerCalls, layer_calls};
use super::mesh::{AlphaClass, GpuMesh, Variant};
use super::shaders::{BARE_DEPTH, Composed};
use super::shadow_atlas::array_layers;
use super::texture::LayeredTarget;
use super::uniform_array::UniformArray;
use crate::assets::Vertex;
use crate::shadow::AtlasShape;
use glam::Mat4;

/// The bare pass's pipeline, its layer matrices and its own depth maps.
pub struct BareDepth {
    pipeline: wgpu::RenderPipeline,
    layers: UniformArray,
    /// Each instance's world_from_local, in batch order.
    placements: GrowingBuffer,
    /// The maps drawn into, with their size, layer count and format.
    maps: Option<(LayeredTarget, (u32, u32, wgpu::TextureFormat))>,
    format: wgpu::TextureFormat,
}

impl BareDepth {
    /// The pipeline for depth maps of `format`.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Self {
        let layers = UniformArray::new(device, "bare layers", size_of::<Mat4>() as u64, wgpu::ShaderStages::VERTEX);
        let module = Composed::new(&[BARE_DEPTH]).module(device);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("bare depth"),
            bind_group_layouts: &[Some(&layers.layout)],
            immediate_size: 0,
        });
        const POSITION: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![0 => Float32x3];
        // Each instance's world_from_local, by columns.
        const PLACEMENT: [wgpu::VertexAttribute; 4] =
            wgpu::vertex_attr_array![6 => Float32x4, 7 => Float32x4, 8 => Float32x4, 9 => Float32x4];
        let buffers = [
            Some(wgpu::VertexBufferLayout {
                array_stride: size_of::<Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &POSITION,
            }),
            Some(wgpu::VertexBufferLayout {
                array_stride: size_of::<Mat4>() as u64,
                step_mode: wgpu::VertexStepMode::Instance,
                attributes: &PLACEMENT,
            }),
        ];
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("bare depth"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_bare"),
                compilation_options: Default::default(),
                buffers: &buffers,
            },
            primitive: Default::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::LessEqual),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: None,
            multiview_mask: None,
            cache: None,
        });
        let placements = GrowingBuffer::new(device, "bare placements", wgpu::BufferUsages::VERTEX);
        BareDepth { pipeline, layers, placements, maps: None, format }
    }

    /// The depth format it draws.
    pub fn format(&self) -> wgpu::TextureFormat {
        self.format
    }

    /// Draws every layer of `data` with its casters into its tile of an atlas of `shape`: per
    /// page one pass, cleared whole, each tile drawn with the viewport on it.
    pub fn encode(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        encoder: &mut wgpu::CommandEncoder,
        data: &FrameData,
        meshes: &[Option<GpuMesh>],
        shape: AtlasShape,
    ) {
        let key = (shape.page, array_layers(shape.pages), self.format);
        if self.maps.as_ref().is_none_or(|(_, s)| *s != key) {
            self.maps = Some((LayeredTarget::new(device, "bare depth", self.format, key.0, key.1), key));
        }
        let matrices: Vec<Mat4> = data.draws.iter().map(|d| d.clip_from_world).collect();
        self.layers.write(device, queue, &matrices);
        // Every caster taken as rigid and opaque: one batch per mesh and layer.
        let bare = |_: &_| Variant {
            skinned: false,
            cull: None,
            alpha: AlphaClass::Opaque,
            textured: false,
            methods: 0,
            instanced: false,
        };
        let mut instances = Vec::new();
        let calls: Vec<LayerCalls> =
            data.draws.iter().map(|l| layer_calls(&data.items, &l.casters, bare, true, &mut instances)).collect();
        let placements: Vec<Mat4> = instances.iter().map(|&i| data.items[i as usize].object.world_from_local).collect();
        self.placements.write(device, queue, bytemuck::cast_slice(&placements));
        let (maps, _) = self.maps.as_ref().expect("made above");
        let mut pages: Vec<u32> = data.draws.iter().filter_map(|d| d.tile.map(|t| t.page)).collect();
        pages.sort_unstable();
        pages.dedup();
        for page in pages {
            let Some(view) = maps.layer_views.get(page as usize) else { continue };
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("bare depth"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_vertex_buffer(1, self.placements.buffer.slice(..));
            for (k, (draw, layer_calls)) in data.draws.iter().zip(&calls).enumerate() {
                let Some(tile) = draw.tile.filter(|t| t.page == page) else { continue };
                let side = draw.resolution as f32;
                pass.set_viewport(tile.x as f32, tile.y as f32, side, side, 0.0, 1.0);
                pass.set_bind_group(0, &self.layers.bind_group, &[self.layers.offset(k)]);
                for batch in &layer_calls.batches {
                    let Some(Some(mesh)) = meshes.get(batch.mesh) else { continue };
                    let (vertices, indices, count) = mesh.buffers();
                    pass.set_vertex_buffer(0, vertices.slice(..));
                    pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
                    pass.draw_indexed(0..count, 0, batch.instances.clone());
                }
            }
        }
    }
}
