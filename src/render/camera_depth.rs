//! The camera's depth drawn before the main pass, for screen-space contact shadows
//! (`contact_visibility` in contact.wgsl): every opaque or cut-out surface, depth only, into a
//! texture of the frame's size that the main pass then reads. (The main pass cannot read its own
//! depth attachment while it draws into it.) It draws with the shadow pass's depth-only shaders,
//! the camera's projection taking the place of a layer's, so it costs what one more shadow layer
//! of the frame's size costs. Without contact shadows it is not drawn, and the main pass reads a
//! stand-in of its own.

use super::frame::{DrawItem, FrameData};
use super::gpu_types::GpuLayer;
use super::instances::{InstanceBuffer, layer_calls};
use super::mesh::{AlphaClass, Drawables, JointPalette, Pipelines, Recipe, Variant};
use super::shaders::{Composed, SHADOW_MODULE};
use super::texture::MaterialTextures;
use super::timing::PassTimer;
use super::uniform_array::UniformArray;
use crate::components::AlphaMode;
use bytemuck::Zeroable;

/// Its format: read back as floats by the main pass on every backend.
pub const CAMERA_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The pipelines, the camera's uniform and the texture.
pub struct CameraDepth {
    pipelines: Pipelines,
    camera: UniformArray,
    instances: InstanceBuffer,
    /// The texture's view and size, once drawn.
    target: Option<(wgpu::TextureView, (u32, u32))>,
}

/// A depth texture of `size` that the main pass can read.
pub fn depth_texture(device: &wgpu::Device, (width, height): (u32, u32)) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("camera depth"),
            size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: CAMERA_DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
        .create_view(&Default::default())
}

/// A blended surface is left out of the camera's depth: it does not hide what is behind it.
fn hides(item: &DrawItem) -> bool {
    item.alpha != AlphaMode::Blend
}

/// How a surface is drawn into the camera's depth: as the camera sees it (its back faces culled
/// unless double-sided), cut out where masked.
fn camera_variant(item: &DrawItem) -> Variant {
    let alpha = if item.alpha == AlphaMode::Opaque { AlphaClass::Opaque } else { AlphaClass::Mask };
    let cull = (!item.double_sided).then_some(wgpu::Face::Back);
    let textured = alpha == AlphaClass::Mask && item.texture.is_some();
    Variant { skinned: item.skinned, cull, alpha, textured, methods: 0, instanced: false }
}

impl CameraDepth {
    /// The pipelines; `object_layout` is the per-object bind group layout.
    pub fn new(
        device: &wgpu::Device,
        object_layout: &wgpu::BindGroupLayout,
        palette: &JointPalette,
        textures: &MaterialTextures,
    ) -> Self {
        let camera = UniformArray::new(
            device,
            "camera layer",
            size_of::<GpuLayer>() as u64,
            wgpu::ShaderStages::VERTEX_FRAGMENT,
        );
        let recipe = Recipe {
            label: "camera depth",
            module: Composed::new(SHADOW_MODULE).module(device),
            vertex: "vs_shadow",
            fragment: "fs_shadow",
            targets: Vec::new(),
            depth: wgpu::DepthStencilState {
                format: CAMERA_DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::LessEqual),
                stencil: Default::default(),
                bias: Default::default(),
            },
            samples_shadows: false,
            samples: 1,
        };
        let pipelines = Pipelines::new(device, recipe, [&camera.layout, object_layout], palette, textures);
        CameraDepth { pipelines, camera, instances: InstanceBuffer::new(device, &palette.layout), target: None }
    }

    /// The texture last drawn, if any.
    pub fn view(&self) -> Option<&wgpu::TextureView> {
        self.target.as_ref().map(|(view, _)| view)
    }

    /// Draws `data`'s surfaces as its camera sees them into a texture of `size`; returns the
    /// texture when it was made anew (the main pass must bind it).
    pub fn encode(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        encoder: &mut wgpu::CommandEncoder,
        data: &FrameData,
        with: Drawables<'_>,
        size: (u32, u32),
        timer: Option<&mut PassTimer>,
    ) -> Option<wgpu::TextureView> {
        let made = match &self.target {
            Some((_, drawn)) if *drawn == size => None,
            _ => Some(depth_texture(device, size)),
        };
        if let Some(view) = &made {
            self.target = Some((view.clone(), size));
        }
        let Some((view, _)) = &self.target else { return None };
        let camera = GpuLayer { clip_from_world: data.clip_from_world, ..GpuLayer::zeroed() };
        self.camera.write(device, queue, &[camera]);
        let drawn: Vec<usize> = (0..data.items.len()).filter(|&i| hides(&data.items[i])).collect();
        let mut instances = Vec::new();
        let calls = layer_calls(&data.items, &drawn, camera_variant, true, &mut instances);
        self.instances.write((device, queue), &instances, &data.items);
        self.pipelines
            .prepare(device, calls.singles.iter().map(|s| s.1).chain(calls.batches.iter().map(|b| b.variant)));
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("camera depth"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: timer.map(PassTimer::camera_writes),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &self.camera.bind_group, &[self.camera.offset(0)]);
        self.pipelines.draw(&mut pass, with, &data.items, calls.singles.iter().copied());
        self.pipelines.draw_batches(&mut pass, with, &calls.batches, self.instances.bindings());
        made
    }
}
