//! The shadow pass: depth only, one layer of a 2D array texture per shadowed light.

use super::extract::FrameData;
use super::renderer::{GpuMesh, vertex_layout};
use super::uniform_array::UniformArray;
use glam::Mat4;

/// Depth format of the shadow maps.
pub const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The shadow-map array and the views the two passes use.
pub struct ShadowMaps {
    /// Width and height of each layer.
    pub size: u32,
    /// Number of layers (at least 2: GL cannot view a single-layer texture as an array).
    pub layers: u32,
    /// One render view per layer.
    layer_views: Vec<wgpu::TextureView>,
    /// The whole array, for sampling.
    pub array_view: wgpu::TextureView,
}

/// Pipeline, per-layer matrices and the shadow-map array.
pub struct ShadowPass {
    pipeline: wgpu::RenderPipeline,
    layer_uniforms: UniformArray,
    /// The current shadow maps.
    pub maps: ShadowMaps,
}

impl ShadowPass {
    /// Builds the depth-only pipeline; `object_layout` is the per-object bind group layout.
    pub fn new(device: &wgpu::Device, object_layout: &wgpu::BindGroupLayout, size: u32) -> Self {
        let layer_uniforms = UniformArray::new(device, "shadow layers", 64, wgpu::ShaderStages::VERTEX);
        let source = concat!(include_str!("../../shaders/common.wgsl"), include_str!("../../shaders/shadow.wgsl"));
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("shadow.wgsl"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("shadow"),
            bind_group_layouts: &[Some(&layer_uniforms.layout), Some(object_layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("shadow"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_shadow"),
                compilation_options: Default::default(),
                buffers: &[Some(vertex_layout())],
            },
            primitive: wgpu::PrimitiveState { cull_mode: Some(wgpu::Face::Back), ..Default::default() },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: SHADOW_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::LessEqual),
                stencil: Default::default(),
                // Biasing is done when sampling, in texel units, so it works the same on every backend.
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: None,
            multiview_mask: None,
            cache: None,
        });
        let maps = ShadowMaps::new(device, size, 2);
        ShadowPass { pipeline, layer_uniforms, maps }
    }

    /// Makes sure the maps are `size` texels and hold `layers`; true if they were re-created.
    pub fn ensure_maps(&mut self, device: &wgpu::Device, size: u32, layers: usize) -> bool {
        let layers = (layers as u32).max(2);
        if self.maps.size == size && self.maps.layers >= layers {
            return false;
        }
        self.maps = ShadowMaps::new(device, size, layers);
        true
    }

    /// Renders every layer: cleared to far, then the casters drawn from the light.
    pub fn encode(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        data: &FrameData,
        meshes: &[Option<GpuMesh>],
        objects: &UniformArray,
    ) {
        self.layer_uniforms.write::<Mat4>(device, queue, &data.layers);
        for (layer, view) in self.maps.layer_views.iter().enumerate().take(data.layers.len()) {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("shadow pass"),
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
            pass.set_bind_group(0, &self.layer_uniforms.bind_group, &[self.layer_uniforms.offset(layer)]);
            for (i, item) in data.items.iter().enumerate().filter(|(_, item)| item.caster) {
                if let Some(Some(mesh)) = meshes.get(item.mesh.0) {
                    pass.set_bind_group(1, &objects.bind_group, &[objects.offset(i)]);
                    mesh.draw(&mut pass);
                }
            }
        }
    }
}

impl ShadowMaps {
    fn new(device: &wgpu::Device, size: u32, layers: u32) -> Self {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow maps"),
            size: wgpu::Extent3d { width: size, height: size, depth_or_array_layers: layers },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: SHADOW_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let layer_views = (0..layers)
            .map(|layer| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    label: Some("shadow layer"),
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: layer,
                    array_layer_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let array_view = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("shadow array"),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        ShadowMaps { size, layers, layer_views, array_view }
    }
}
