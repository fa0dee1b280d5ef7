//! Drawing meshes: their GPU buffers, the joint palette that skinned meshes read, and every
//! pipeline built twice, once for rigid meshes and once for skinned ones.

use super::extract::DrawItem;
use super::uniform_array::UniformArray;
use crate::assets::{MeshData, SkinVertex, Vertex};
use glam::Mat4;
use wgpu::util::DeviceExt;

/// A mesh in GPU memory; a skinned mesh has a second vertex stream of joint influences.
pub struct GpuMesh {
    vertices: wgpu::Buffer,
    skin: Option<wgpu::Buffer>,
    indices: wgpu::Buffer,
    index_count: u32,
}

impl GpuMesh {
    /// Uploads `mesh`; `None` for a mesh with nothing to draw.
    pub fn upload(device: &wgpu::Device, mesh: &MeshData) -> Option<GpuMesh> {
        if mesh.vertices.is_empty() || mesh.indices.is_empty() {
            return None;
        }
        let buffer = |label, contents, usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        Some(GpuMesh {
            vertices: buffer("vertices", bytemuck::cast_slice(&mesh.vertices), wgpu::BufferUsages::VERTEX),
            skin: mesh.skin.as_ref().map(|s| buffer("skin", bytemuck::cast_slice(s), wgpu::BufferUsages::VERTEX)),
            indices: buffer("indices", bytemuck::cast_slice(&mesh.indices), wgpu::BufferUsages::INDEX),
            index_count: mesh.indices.len() as u32,
        })
    }
}

/// How the shaders read a [`Vertex`] (locations 0, 1) and a [`SkinVertex`] (locations 2, 3).
fn vertex_layouts(skinned: bool) -> Vec<Option<wgpu::VertexBufferLayout<'static>>> {
    const VERTEX: [wgpu::VertexAttribute; 2] = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
    const SKIN: [wgpu::VertexAttribute; 2] = wgpu::vertex_attr_array![2 => Uint16x4, 3 => Float32x4];
    let layout = |stride, attributes| {
        Some(wgpu::VertexBufferLayout { array_stride: stride, step_mode: wgpu::VertexStepMode::Vertex, attributes })
    };
    let mut layouts = vec![layout(size_of::<Vertex>() as u64, &VERTEX[..])];
    if skinned {
        layouts.push(layout(size_of::<SkinVertex>() as u64, &SKIN[..]));
    }
    layouts
}

/// Every skinned object's joint matrices in one storage buffer; an object finds its own from
/// the first index in its uniform.
pub struct JointPalette {
    /// Layout of bind group 2 of the skinned pipelines.
    pub layout: wgpu::BindGroupLayout,
    buffer: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    capacity: usize,
}

impl JointPalette {
    /// An empty palette with room for a few skeletons.
    pub fn new(device: &wgpu::Device) -> Self {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("joints"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: true },
                    has_dynamic_offset: false,
                    min_binding_size: wgpu::BufferSize::new(size_of::<Mat4>() as u64),
                },
                count: None,
            }],
        });
        let (buffer, bind_group) = Self::allocate(device, &layout, 64);
        JointPalette { layout, buffer, bind_group, capacity: 64 }
    }

    fn allocate(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        capacity: usize,
    ) -> (wgpu::Buffer, wgpu::BindGroup) {
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("joints"),
            size: (capacity * size_of::<Mat4>()) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("joints"),
            layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() }],
        });
        (buffer, bind_group)
    }

    /// Uploads this frame's joint matrices, growing the buffer when they do not fit.
    pub fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, joints: &[Mat4]) {
        if joints.len() > self.capacity {
            self.capacity = joints.len().next_power_of_two();
            (self.buffer, self.bind_group) = Self::allocate(device, &self.layout, self.capacity);
        }
        if !joints.is_empty() {
            queue.write_buffer(&self.buffer, 0, bytemuck::cast_slice(joints));
        }
    }
}

/// What every pass draws from: the uploaded meshes, the per-object uniforms and the joints.
#[derive(Clone, Copy)]
pub struct Drawables<'a> {
    /// Meshes by library index.
    pub meshes: &'a [Option<GpuMesh>],
    /// One uniform block per draw item.
    pub objects: &'a UniformArray,
    /// The joint palette of skinned items.
    pub joints: &'a JointPalette,
}

/// What a pipeline pair is made of: one shader module, a vertex entry point `vertex` (and
/// `{vertex}_skinned`), an optional fragment stage, bind groups 0 and 1, and the depth test.
pub struct PipelineDesc<'a> {
    /// Debug label.
    pub label: &'a str,
    /// The shader module holding every entry point.
    pub module: &'a wgpu::ShaderModule,
    /// The rigid vertex entry point.
    pub vertex: &'a str,
    /// Fragment entry point and colour targets, or none for depth only.
    pub fragment: Option<(&'a str, &'a [Option<wgpu::ColorTargetState>])>,
    /// Layouts of bind groups 0 and 1.
    pub groups: [&'a wgpu::BindGroupLayout; 2],
    /// Depth format and test.
    pub depth: wgpu::DepthStencilState,
    /// Which faces are not drawn.
    pub cull: Option<wgpu::Face>,
}

/// The same pipeline for rigid meshes and for skinned meshes.
pub struct PipelinePair {
    rigid: wgpu::RenderPipeline,
    skinned: wgpu::RenderPipeline,
}

impl PipelinePair {
    /// Builds both pipelines; the skinned one also binds `palette` as group 2.
    pub fn new(device: &wgpu::Device, desc: &PipelineDesc<'_>, palette: &JointPalette) -> Self {
        let build = |skinned: bool| {
            let groups: Vec<Option<&wgpu::BindGroupLayout>> = if skinned {
                vec![Some(desc.groups[0]), Some(desc.groups[1]), Some(&palette.layout)]
            } else {
                vec![Some(desc.groups[0]), Some(desc.groups[1])]
            };
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(desc.label),
                bind_group_layouts: &groups,
                immediate_size: 0,
            });
            let entry = if skinned { format!("{}_skinned", desc.vertex) } else { desc.vertex.to_string() };
            let buffers = vertex_layouts(skinned);
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(desc.label),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: desc.module,
                    entry_point: Some(&entry),
                    compilation_options: Default::default(),
                    buffers: &buffers,
                },
                primitive: wgpu::PrimitiveState { cull_mode: desc.cull, ..Default::default() },
                depth_stencil: Some(desc.depth.clone()),
                multisample: Default::default(),
                fragment: desc.fragment.map(|(entry, targets)| wgpu::FragmentState {
                    module: desc.module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        PipelinePair { rigid: build(false), skinned: build(true) }
    }

    /// Draws the objects `which` of `items`, switching to the skinned pipeline (and binding the
    /// joint palette) for skinned objects; bind group 0 must already be set.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        with: Drawables<'_>,
        items: &[DrawItem],
        which: impl IntoIterator<Item = usize>,
    ) {
        let Drawables { meshes, objects, joints: palette } = with;
        let mut bound: Option<bool> = None;
        for i in which {
            let Some((item, Some(mesh))) =
                items.get(i).map(|item| (item, meshes.get(item.mesh.0).and_then(Option::as_ref)))
            else {
                continue;
            };
            let skin = mesh.skin.as_ref().filter(|_| item.skinned);
            if bound != Some(skin.is_some()) {
                pass.set_pipeline(if skin.is_some() { &self.skinned } else { &self.rigid });
                if skin.is_some() {
                    pass.set_bind_group(2, &palette.bind_group, &[]);
                }
                bound = Some(skin.is_some());
            }
            pass.set_bind_group(1, &objects.bind_group, &[objects.offset(i)]);
            pass.set_vertex_buffer(0, mesh.vertices.slice(..));
            if let Some(skin) = skin {
                pass.set_vertex_buffer(1, skin.slice(..));
            }
            pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..mesh.index_count, 0, 0..1);
        }
    }
}
