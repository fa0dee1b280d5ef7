//! Drawing meshes: their GPU buffers, the joint palette that skinned meshes read, and the
//! pipelines of a pass, one for each variant (rigid or skinned, which faces, what alpha does)
//! the scene's objects need, each built the first time it is needed.

use super::frame::DrawItem;
use super::texture::MaterialTextures;
use super::uniform_array::UniformArray;
use crate::assets::{MeshData, SkinVertex, Vertex};
use glam::Mat4;
use std::collections::HashMap;
use std::ops::Range;
use wgpu::util::DeviceExt;

/// One call drawing `mesh` once for each placement in `instances` of the instance buffer.
#[derive(Clone, Debug, PartialEq)]
pub struct Batch {
    /// The pipeline variant (rigid, opaque, instanced).
    pub variant: Variant,
    /// The mesh's library index.
    pub mesh: usize,
    /// Its placements' range in the instance buffer.
    pub instances: Range<u32>,
}

/// A mesh in GPU memory; a skinned mesh has a second vertex stream of joint influences.
pub struct GpuMesh {
    vertices: wgpu::Buffer,
    skin: Option<wgpu::Buffer>,
    indices: wgpu::Buffer,
    index_count: u32,
}

impl GpuMesh {
    /// Its vertex and index buffers and the number of indices.
    pub fn buffers(&self) -> (&wgpu::Buffer, &wgpu::Buffer, u32) {
        (&self.vertices, &self.indices, self.index_count)
    }

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

/// An instance as the instanced shaders read it: the number of its object, whose placement is in
/// the storage buffer of bind group 3.
const INSTANCE: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![6 => Uint32];

/// How the shaders read a [`Vertex`] (locations 0, 1, 4, 5), a [`SkinVertex`] (locations 2, 3)
/// and an instance's object number (location 6), in buffer slot 1.
fn vertex_layouts(v: Variant) -> Vec<Option<wgpu::VertexBufferLayout<'static>>> {
    const VERTEX: [wgpu::VertexAttribute; 4] =
        wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 4 => Float32x2, 5 => Float32x4];
    const SKIN: [wgpu::VertexAttribute; 2] = wgpu::vertex_attr_array![2 => Uint16x4, 3 => Float32x4];
    let layout =
        |stride, step_mode, attributes| Some(wgpu::VertexBufferLayout { array_stride: stride, step_mode, attributes });
    let mut layouts = vec![layout(size_of::<Vertex>() as u64, wgpu::VertexStepMode::Vertex, &VERTEX[..])];
    if v.skinned {
        layouts.push(layout(size_of::<SkinVertex>() as u64, wgpu::VertexStepMode::Vertex, &SKIN[..]));
    } else if v.instanced {
        layouts.push(layout(size_of::<u32>() as u64, wgpu::VertexStepMode::Instance, &INSTANCE[..]));
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
        Self::with_layout(device, layout)
    }

    /// An empty palette bound with `layout` (another palette's: the instanced draws' placements
    /// are bound where a skinned draw's joints are).
    pub fn with_layout(device: &wgpu::Device, layout: wgpu::BindGroupLayout) -> Self {
        let (buffer, bind_group) = Self::allocate(device, &layout, 64);
        JointPalette { layout, buffer, bind_group, capacity: 64 }
    }

    /// The bind group over its matrices.
    pub fn bind_group(&self) -> &wgpu::BindGroup {
        &self.bind_group
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

/// What every pass draws from: the uploaded meshes, the per-object uniforms, the joints and the
/// material textures.
#[derive(Clone, Copy)]
pub struct Drawables<'a> {
    /// Meshes by library index.
    pub meshes: &'a [Option<GpuMesh>],
    /// One uniform block per draw item.
    pub objects: &'a UniformArray,
    /// The joint palette of skinned items.
    pub joints: &'a JointPalette,
    /// The base-colour textures.
    pub textures: &'a MaterialTextures,
}

/// How a pipeline treats a surface's alpha.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AlphaClass {
    /// Ignored.
    Opaque,
    /// Fragments below the object's cutoff are discarded.
    Mask,
    /// Blended over what is behind, without writing depth.
    Blend,
}

/// What differs between the pipelines of one pass, chosen per object as it is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Variant {
    /// Deformed by joints (the `_skinned` vertex entry point and the joint palette).
    pub skinned: bool,
    /// Which faces are not drawn.
    pub cull: Option<wgpu::Face>,
    /// What alpha does.
    pub alpha: AlphaClass,
    /// Its material has a base-colour texture (without one, the lookup is skipped).
    pub textured: bool,
    /// The shadow methods the frame's lights use, a bit (1 << method) each: the pipeline holds
    /// only their sampling code (passes that look no shadows up leave it 0).
    pub methods: u32,
    /// Rigid, its placements read per instance (the `_instanced` vertex entry point and the
    /// instance buffer; see [`super::instances`]).
    pub instanced: bool,
}

/// What every pipeline of a pass shares: one shader module with a vertex entry point `vertex`
/// (and `{vertex}_skinned`) and a fragment entry point, its colour targets (none for depth
/// only, where opaque objects get no fragment stage at all), bind groups 0 and 1, and the depth
/// test. The fragment stage is told through the pipeline constants `TEXTURED`, `ALPHA_MASK`,
/// `ALPHA_BLEND` and `SHADOW_METHODS` whether to sample the texture, what alpha does and which
/// shadow methods to sample with.
pub struct Recipe {
    /// Debug label.
    pub label: &'static str,
    /// The shader module holding every entry point.
    pub module: wgpu::ShaderModule,
    /// The rigid vertex entry point.
    pub vertex: &'static str,
    /// The fragment entry point.
    pub fragment: &'static str,
    /// Colour targets; empty for a depth-only pass.
    pub targets: Vec<Option<wgpu::ColorTargetState>>,
    /// Depth format and test, and stencil (depth writes are turned off for blended objects).
    pub depth: wgpu::DepthStencilState,
    /// Its fragment stage looks shadows up (takes the `SHADOW_METHODS` constant).
    pub samples_shadows: bool,
    /// Samples per pixel of its targets (1: not multisampled).
    pub samples: u32,
}

/// The pipelines of one pass, built from one [`Recipe`] for each [`Variant`] the scene needs.
pub struct Pipelines {
    recipe: Recipe,
    /// Layouts for rigid and skinned objects.
    layouts: [wgpu::PipelineLayout; 2],
    built: HashMap<Variant, wgpu::RenderPipeline>,
}

impl Pipelines {
    /// The pipelines of `recipe`, bind groups 0 and 1 laid out as `groups`; group 2 holds the
    /// material texture and, for skinned objects, group 3 the joint palette.
    pub fn new(
        device: &wgpu::Device,
        recipe: Recipe,
        groups: [&wgpu::BindGroupLayout; 2],
        palette: &JointPalette,
        textures: &MaterialTextures,
    ) -> Self {
        let layout = |skinned: bool| {
            let mut all = vec![Some(groups[0]), Some(groups[1]), Some(&textures.layout)];
            if skinned {
                all.push(Some(&palette.layout));
            }
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(recipe.label),
                bind_group_layouts: &all,
                immediate_size: 0,
            })
        };
        let layouts = [layout(false), layout(true)];
        Pipelines { recipe, layouts, built: HashMap::new() }
    }

    /// Builds the pipelines of `variants` that are not built yet.
    pub fn prepare(&mut self, device: &wgpu::Device, variants: impl IntoIterator<Item = Variant>) {
        for v in variants {
            if !self.built.contains_key(&v) {
                let pipeline = self.build(device, v);
                self.built.insert(v, pipeline);
            }
        }
    }

    fn build(&self, device: &wgpu::Device, v: Variant) -> wgpu::RenderPipeline {
        let r = &self.recipe;
        let entry = match (v.skinned, v.instanced) {
            (true, _) => format!("{}_skinned", r.vertex),
            (false, true) => format!("{}_instanced", r.vertex),
            (false, false) => r.vertex.to_string(),
        };
        let blend = v.alpha == AlphaClass::Blend;
        let mut constants = vec![
            ("TEXTURED", v.textured as u32 as f64),
            ("ALPHA_MASK", (v.alpha == AlphaClass::Mask) as u32 as f64),
            ("ALPHA_BLEND", blend as u32 as f64),
        ];
        if r.samples_shadows {
            constants.push(("SHADOW_METHODS", v.methods as f64));
        }
        let targets: Vec<Option<wgpu::ColorTargetState>> = r
            .targets
            .iter()
            .map(|t| {
                t.clone().map(|t| wgpu::ColorTargetState {
                    blend: if blend {
                        Some(wgpu::BlendState {
                            color: wgpu::BlendState::ALPHA_BLENDING.color,
                            alpha: wgpu::BlendComponent::OVER,
                        })
                    } else {
                        t.blend
                    },
                    ..t
                })
            })
            .collect();
        let fragment = (!r.targets.is_empty() || v.alpha != AlphaClass::Opaque).then(|| wgpu::FragmentState {
            module: &r.module,
            entry_point: Some(r.fragment),
            compilation_options: wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() },
            targets: &targets,
        });
        let writes = r.depth.depth_write_enabled != Some(false) && !blend;
        let depth = wgpu::DepthStencilState { depth_write_enabled: Some(writes), ..r.depth.clone() };
        let buffers = vertex_layouts(v);
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(r.label),
            layout: Some(&self.layouts[(v.skinned || v.instanced) as usize]),
            vertex: wgpu::VertexState {
                module: &r.module,
                entry_point: Some(&entry),
                compilation_options: Default::default(),
                buffers: &buffers,
            },
            primitive: wgpu::PrimitiveState { cull_mode: v.cull, ..Default::default() },
            depth_stencil: Some(depth),
            multisample: wgpu::MultisampleState { count: r.samples, ..Default::default() },
            fragment,
            multiview_mask: None,
            cache: None,
        })
    }

    /// Draws the objects `which` of `items`, each with the pipeline of its variant (built by
    /// [`Pipelines::prepare`]; objects whose variant is not built are skipped), binding its
    /// uniform, texture and joints; bind group 0 must already be set.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        with: Drawables<'_>,
        items: &[DrawItem],
        which: impl IntoIterator<Item = (usize, Variant)>,
    ) {
        let Drawables { meshes, objects, joints: palette, textures } = with;
        let mut bound: Option<Variant> = None;
        let mut texture: Option<Option<crate::components::Texture>> = None;
        // Parts of a model that instance one mesh come one after another: their buffers are
        // bound once, which keeps a scene of 100,000 instances from recording 200,000 more
        // commands a pass.
        let mut buffers: Option<(usize, bool)> = None;
        for (i, variant) in which {
            let (Some(item), Some(pipeline)) = (items.get(i), self.built.get(&variant)) else { continue };
            let Some(mesh) = meshes.get(item.mesh.0).and_then(Option::as_ref) else { continue };
            let skin = mesh.skin.as_ref().filter(|_| variant.skinned);
            if variant.skinned && skin.is_none() {
                continue;
            }
            if bound != Some(variant) {
                pass.set_pipeline(pipeline);
                if variant.skinned {
                    pass.set_bind_group(3, &palette.bind_group, &[]);
                }
                bound = Some(variant);
            }
            if texture != Some(item.texture) {
                pass.set_bind_group(2, textures.bind_group(item.texture), &[]);
                texture = Some(item.texture);
            }
            pass.set_bind_group(1, &objects.bind_group, &[objects.offset(i)]);
            if buffers != Some((item.mesh.0, variant.skinned)) {
                pass.set_vertex_buffer(0, mesh.vertices.slice(..));
                if let Some(skin) = skin {
                    pass.set_vertex_buffer(1, skin.slice(..));
                }
                pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                buffers = Some((item.mesh.0, variant.skinned));
            }
            pass.draw_indexed(0..mesh.index_count, 0, 0..1);
        }
    }

    /// Draws `batches` (built by [`Pipelines::prepare`]), each one call for all its instances,
    /// their object numbers read from `instances` and their placements from `placements`; bind
    /// group 0 must already be set.
    pub fn draw_batches(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        with: Drawables<'_>,
        batches: &[Batch],
        (instances, placements): (&wgpu::Buffer, &wgpu::BindGroup),
    ) {
        if batches.is_empty() {
            return;
        }
        // The layout holds the per-object and texture groups; an instanced caster reads neither.
        pass.set_bind_group(1, &with.objects.bind_group, &[with.objects.offset(0)]);
        pass.set_bind_group(2, with.textures.bind_group(None), &[]);
        pass.set_bind_group(3, placements, &[]);
        pass.set_vertex_buffer(1, instances.slice(..));
        for b in batches {
            let (Some(pipeline), Some(Some(mesh))) = (self.built.get(&b.variant), with.meshes.get(b.mesh)) else {
                continue;
            };
            pass.set_pipeline(pipeline);
            pass.set_vertex_buffer(0, mesh.vertices.slice(..));
            pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..mesh.index_count, 0, b.instances.clone());
        }
    }
}
