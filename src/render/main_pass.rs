//! The main pass: Phong lighting from the camera, each light's share scaled by its shadow test,
//! then the planar shadows drawn over the ground ([`super::planar`]).

use super::RenderError;
use super::frame::{DrawItem, FrameData};
use super::gpu_types::{Frame, LIST_WIDTH};
use super::growing::{GrowingBuffer, GrowingRows};
use super::mesh::{AlphaClass, Drawables, JointPalette, Pipelines, Recipe, Variant};
use super::parts::Part;
use super::planar::{PlanarPass, PlanarTargets};
use super::shaders::{Composed, MAIN_MODULE, PLANAR_MODULE};
use super::shadow_atlas::ShadowMaps;
use super::texture::MaterialTextures;
use super::timing::PassTimer;
use crate::assets::{COOKIE_SIZE, cookie_image};
use crate::components::{AlphaMode, Cookie};

/// The feature that gives the camera's depth buffer 32-bit float depth beside its stencil.
pub const DEPTH_STENCIL_FEATURES: wgpu::Features = wgpu::Features::DEPTH32FLOAT_STENCIL8;

/// Format of the camera's depth buffer: depth with a stencil (planar shadows count with it),
/// 32-bit float depth where the device has it.
pub fn depth_format(features: wgpu::Features) -> wgpu::TextureFormat {
    if features.contains(DEPTH_STENCIL_FEATURES) {
        wgpu::TextureFormat::Depth32FloatStencil8
    } else {
        wgpu::TextureFormat::Depth24PlusStencil8
    }
}
/// Sky colour behind the scene (linear).
const SKY: wgpu::Color = wgpu::Color { r: 0.38, g: 0.55, b: 0.78, a: 1.0 };

/// Pipeline, frame uniform and the bind group that ties in the shadow maps.
pub struct MainPass {
    pipelines: Pipelines,
    /// The measuring pipelines (world position, normal, visibility), built on first use.
    debug: Option<Pipelines>,
    /// The probe pipelines (shadow tests at given points), one for each set of shadow methods
    /// a frame of probes used, built on first use.
    probe: std::collections::HashMap<u32, wgpu::RenderPipeline>,
    module: wgpu::ShaderModule,
    object_layout: wgpu::BindGroupLayout,
    frame: FrameResources,
    bind_group: wgpu::BindGroup,
    planar: PlanarPass,
    /// Format of the camera's depth-stencil buffer.
    pub depth_format: wgpu::TextureFormat,
    /// Keep the depth the pass draws (the SDSM reduction reads it after); else it is dropped.
    pub keep_depth: bool,
}

/// Where one main pass draws: its colour targets with their clear colours, the depth buffer,
/// the pipelines (the picture's, or the measuring view's), and the timer to stamp it with.
struct Pass<'a> {
    colors: &'a [(&'a wgpu::TextureView, wgpu::Color)],
    depth: &'a wgpu::TextureView,
    pipelines: &'a Pipelines,
    measuring: bool,
    timer: Option<&'a PassTimer>,
    part: &'a Part,
}

/// How an object is drawn in the main pass: with the sampling code of the shadow methods in
/// use (`methods`), back faces culled unless its material is double sided; in the measuring view (integer targets, which cannot blend) a blended surface counts
/// as masked at its cutoff, as it does in the shadow maps and the truth.
fn main_variant(item: &DrawItem, methods: u32, measuring: bool) -> Variant {
    let alpha = match item.alpha {
        AlphaMode::Opaque => AlphaClass::Opaque,
        AlphaMode::Mask { .. } => AlphaClass::Mask,
        AlphaMode::Blend if measuring => AlphaClass::Mask,
        AlphaMode::Blend => AlphaClass::Blend,
    };
    let cull = (!item.double_sided).then_some(wgpu::Face::Back);
    Variant { skinned: item.skinned, cull, alpha, textured: item.texture.is_some(), methods, instanced: false }
}

/// Format of the measuring pass's three targets (world position, normal, visibility): 32-bit
/// floats carried as their bits, since GL cannot render to float targets of that size.
pub const DEBUG_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;

fn depth_test(format: wgpu::TextureFormat) -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format,
        depth_write_enabled: Some(true),
        depth_compare: Some(wgpu::CompareFunction::Less),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// What bind group 0 holds besides the shadow maps, which are re-created when they grow; the
/// lights, their layers and their clusters grow too, with the scene.
struct FrameResources {
    layout: wgpu::BindGroupLayout,
    buffer: wgpu::Buffer,
    shadow_sampler: wgpu::Sampler,
    moment_sampler: wgpu::Sampler,
    cookies: wgpu::Buffer,
    lights: GrowingBuffer,
    layers: GrowingBuffer,
    cluster_lists: GrowingRows,
    /// The paged lights' page tables.
    page_tables: GrowingRows,
    /// The camera's depth drawn before the pass (a 1x1 stand-in until contact shadows need it).
    camera_depth: wgpu::TextureView,
}

/// A read-only storage buffer at `binding`, seen by the fragment stage.
fn storage_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A uniform buffer of `size` bytes at `binding`, seen by `stages`.
fn uniform_entry(binding: u32, stages: wgpu::ShaderStages, size: usize) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: stages,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: wgpu::BufferSize::new(size as u64),
        },
        count: None,
    }
}

/// Words of an integer texture at `binding`, seen by the fragment stage (the clusters' light
/// lists, the page tables).
fn words_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Uint,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

fn uniform_buffer(device: &wgpu::Device, label: &str, size: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// Bind group 0 of the main pass: the frame, the shadow maps and their samplers, the cookies,
/// the lights and the layers, the colour maps and their sampler, the clusters' light lists, the
/// camera's depth (for contact shadows), the page tables.
fn layout_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
    let fragment = wgpu::ShaderStages::FRAGMENT;
    let cookie_bytes = Cookie::ALL.len() * (COOKIE_SIZE * COOKIE_SIZE) as usize;
    vec![
        uniform_entry(0, wgpu::ShaderStages::VERTEX_FRAGMENT, size_of::<Frame>()),
        wgpu::BindGroupLayoutEntry {
            binding: 1,
            visibility: fragment,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Depth,
                view_dimension: wgpu::TextureViewDimension::D2Array,
                multisampled: false,
            },
            count: None,
        },
        wgpu::BindGroupLayoutEntry {
            binding: 2,
            visibility: fragment,
            ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
            count: None,
        },
        uniform_entry(3, fragment, cookie_bytes),
        storage_entry(4),
        storage_entry(5),
        wgpu::BindGroupLayoutEntry {
            binding: 6,
            visibility: fragment,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: true },
                view_dimension: wgpu::TextureViewDimension::D2Array,
                multisampled: false,
            },
            count: None,
        },
        wgpu::BindGroupLayoutEntry {
            binding: 7,
            visibility: fragment,
            ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            count: None,
        },
        words_entry(9),
        words_entry(11),
        // The camera's depth, read as floats (GLSL cannot load from a depth texture).
        wgpu::BindGroupLayoutEntry {
            binding: 10,
            visibility: fragment,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        },
    ]
}

impl FrameResources {
    fn new(device: &wgpu::Device) -> Self {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame"),
            entries: &layout_entries(),
        });
        // Linear comparison filtering gives a 2x2 percentage-closer filter in hardware.
        let shadow_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("shadow compare"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        // Moment maps are filtered like any image: their moments average linearly.
        let moment_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("moments"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        FrameResources {
            layout,
            buffer: uniform_buffer(device, "frame", size_of::<Frame>()),
            shadow_sampler,
            moment_sampler,
            cookies: cookie_buffer(device),
            lights: GrowingBuffer::new(device, "lights", wgpu::BufferUsages::STORAGE),
            layers: GrowingBuffer::new(device, "layers", wgpu::BufferUsages::STORAGE),
            cluster_lists: GrowingRows::new(device, "cluster lists", LIST_WIDTH),
            page_tables: GrowingRows::new(device, "page tables", LIST_WIDTH),
            camera_depth: super::camera_depth::depth_texture(device, (1, 1)),
        }
    }

    /// What bind group 0 binds, for `maps`.
    fn entries<'a>(&'a self, maps: &'a ShadowMaps) -> Vec<wgpu::BindGroupEntry<'a>> {
        vec![
            wgpu::BindGroupEntry { binding: 0, resource: self.buffer.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&maps.pages.array_view) },
            wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::Sampler(&self.shadow_sampler) },
            wgpu::BindGroupEntry { binding: 3, resource: self.cookies.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 4, resource: self.lights.buffer.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 5, resource: self.layers.buffer.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 6, resource: wgpu::BindingResource::TextureView(&maps.moments.array_view) },
            wgpu::BindGroupEntry { binding: 7, resource: wgpu::BindingResource::Sampler(&self.moment_sampler) },
            wgpu::BindGroupEntry { binding: 9, resource: wgpu::BindingResource::TextureView(&self.cluster_lists.view) },
            wgpu::BindGroupEntry { binding: 10, resource: wgpu::BindingResource::TextureView(&self.camera_depth) },
            wgpu::BindGroupEntry { binding: 11, resource: wgpu::BindingResource::TextureView(&self.page_tables.view) },
        ]
    }

    fn bind(&self, device: &wgpu::Device, maps: &ShadowMaps) -> wgpu::BindGroup {
        let entries = self.entries(maps);
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame"),
            layout: &self.layout,
            entries: &entries,
        })
    }

    /// Uploads the frame's lights, their layers and their clusters (growing the buffers where
    /// they must: then true, and they must be bound again). A scene whose lights need more than
    /// one binding can hold on this device is refused, with the limit named.
    fn upload(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, data: &FrameData) -> Result<bool, RenderError> {
        let lights = data.gpu_lights();
        let lists = data.grid.words();
        let bytes = size_of_val(&lights[..]) as u64;
        fits_one_binding(lights.len(), bytes, device.limits().max_storage_buffer_binding_size)?;
        let rows = self.cluster_lists.rows_for(lists.len());
        let most = device.limits().max_texture_dimension_2d;
        if rows > most {
            return Err(RenderError::TooManyLists { lights: lights.len(), rows, most });
        }
        let mut grew = self.lights.write(device, queue, bytemuck::cast_slice(&lights));
        grew |= self.layers.write(device, queue, bytemuck::cast_slice(&data.layers));
        grew |= self.cluster_lists.write(device, queue, &lists);
        if self.page_tables.rows_for(data.page_words.len()) > most {
            return Err(RenderError::Unsupported("page tables taller than this device's largest texture"));
        }
        grew |= self.page_tables.write(device, queue, &data.page_words);
        Ok(grew)
    }

    /// Uploads the frame uniform.
    fn write(&self, queue: &wgpu::Queue, data: &FrameData) {
        queue.write_buffer(&self.buffer, 0, bytemuck::bytes_of(&data.frame));
    }
}

impl MainPass {
    /// Builds the lighting pipeline for colour format `format`.
    pub fn new(
        device: &wgpu::Device,
        object_layout: &wgpu::BindGroupLayout,
        palette: &JointPalette,
        textures: &MaterialTextures,
        format: wgpu::TextureFormat,
        maps: &ShadowMaps,
    ) -> Self {
        let frame = FrameResources::new(device);
        let module = Composed::new(MAIN_MODULE).module(device);
        let depth_format = depth_format(device.features());
        let recipe = Recipe {
            label: "main",
            module: module.clone(),
            vertex: "vs_main",
            fragment: "fs_main",
            targets: vec![Some(format.into())],
            depth: depth_test(depth_format),
            samples_shadows: true,
            samples: 1,
        };
        let pipelines = Pipelines::new(device, recipe, [&frame.layout, object_layout], palette, textures);
        let bind_group = frame.bind(device, maps);
        let planar_module = Composed::new(PLANAR_MODULE).module(device);
        let targets = PlanarTargets { color: format, measure: DEBUG_FORMAT, depth: depth_format };
        let groups = (&layout_entries()[..], object_layout);
        let mut planar = PlanarPass::new(device, &planar_module, groups, (palette, textures), targets);
        planar.bind(device, &frame.entries(maps));
        let object_layout = object_layout.clone();
        let keep_depth = false;
        MainPass {
            pipelines,
            debug: None,
            probe: std::collections::HashMap::new(),
            module,
            object_layout,
            frame,
            bind_group,
            planar,
            depth_format,
            keep_depth,
        }
    }

    /// Builds the measuring pipelines if they are not built yet.
    pub fn ensure_debug(&mut self, device: &wgpu::Device, palette: &JointPalette, textures: &MaterialTextures) {
        if self.debug.is_some() {
            return;
        }
        let recipe = Recipe {
            label: "measure",
            module: self.module.clone(),
            vertex: "vs_main",
            fragment: "fs_debug",
            targets: vec![Some(DEBUG_FORMAT.into()); 3],
            depth: depth_test(self.depth_format),
            samples_shadows: true,
            samples: 1,
        };
        let groups = [&self.frame.layout, &self.object_layout];
        self.debug = Some(Pipelines::new(device, recipe, groups, palette, textures));
    }

    /// Builds the pipelines the objects of `data` need (measuring ones too, once those exist),
    /// uploads its lights, layers, clusters and planar shadows, and binds `maps` again if a
    /// buffer had to grow for them.
    pub fn prepare(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        data: &FrameData,
        maps: &ShadowMaps,
    ) -> Result<(), RenderError> {
        self.pipelines.prepare(device, data.items.iter().map(|i| main_variant(i, data.methods, false)));
        if let Some(debug) = &mut self.debug {
            debug.prepare(device, data.items.iter().map(|i| main_variant(i, data.methods, true)));
        }
        let grew =
            self.frame.upload(device, queue, data)? | self.planar.prepare(device, queue, data, self.debug.is_some());
        if grew {
            self.rebind(device, maps);
        }
        Ok(())
    }

    /// Points the pass at new shadow maps after they were re-created.
    pub fn rebind(&mut self, device: &wgpu::Device, maps: &ShadowMaps) {
        self.bind_group = self.frame.bind(device, maps);
        self.planar.bind(device, &self.frame.entries(maps));
    }

    /// Points the pass at a new camera depth (see [`super::camera_depth`]), with `maps`.
    pub fn set_camera_depth(&mut self, device: &wgpu::Device, view: wgpu::TextureView, maps: &ShadowMaps) {
        self.frame.camera_depth = view;
        self.rebind(device, maps);
    }

    /// Builds the probe pipeline that samples with `methods` (a bit each, as the main pass's
    /// `SHADOW_METHODS`) if it is not built yet.
    pub fn ensure_probe(&mut self, device: &wgpu::Device, methods: u32) {
        if self.probe.contains_key(&methods) {
            return;
        }
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("probe"),
            bind_group_layouts: &[Some(&self.frame.layout)],
            immediate_size: 0,
        });
        const POINT: [wgpu::VertexAttribute; 2] = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
        let constants = [("SHADOW_METHODS", methods as f64)];
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("probe"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &self.module,
                entry_point: Some("vs_probe"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: size_of::<crate::assets::Vertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &POINT,
                })],
            },
            primitive: wgpu::PrimitiveState { topology: wgpu::PrimitiveTopology::PointList, ..Default::default() },
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &self.module,
                entry_point: Some("fs_probe"),
                compilation_options: wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() },
                targets: &[Some(DEBUG_FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        self.probe.insert(methods, pipeline);
    }

    /// Draws `count` probe points from `points` into `target`, each into its own pixel, with the
    /// shadow tests the main pass would make there; needs [`MainPass::ensure_probe`] for the
    /// frame's methods first.
    pub fn encode_probes(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
        data: &FrameData,
        (points, count): (&wgpu::Buffer, u32),
    ) {
        let Some(pipeline) = self.probe.get(&data.methods) else { return };
        self.frame.write(queue, data);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("probes"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.set_vertex_buffer(0, points.slice(..));
        pass.draw(0..count, 0..1);
    }

    /// Draws every object into `color` (cleared to the sky) with depth testing against `depth`.
    pub fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (color, depth): (&wgpu::TextureView, &wgpu::TextureView),
        data: &FrameData,
        (with, timer, part): (Drawables<'_>, Option<&PassTimer>, &Part),
    ) {
        let pass = Pass { colors: &[(color, SKY)], depth, pipelines: &self.pipelines, measuring: false, timer, part };
        self.encode_into(queue, encoder, pass, data, with);
    }

    /// Draws every object's world position, normal and shadow visibilities into `targets`
    /// (cleared to zero), with the same lighting code as [`MainPass::encode`]; needs
    /// [`MainPass::ensure_debug`] first.
    pub fn encode_debug(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (targets, depth): (&[wgpu::TextureView; 3], &wgpu::TextureView),
        data: &FrameData,
        (with, timer, part): (Drawables<'_>, Option<&PassTimer>, &Part),
    ) {
        let Some(debug) = &self.debug else { return };
        let clear = targets.each_ref().map(|t| (t, wgpu::Color::TRANSPARENT));
        let pass = Pass { colors: &clear, depth, pipelines: debug, measuring: true, timer, part };
        self.encode_into(queue, encoder, pass, data, with);
    }

    fn encode_into(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        Pass { colors, depth, pipelines, measuring, timer, part }: Pass<'_>,
        data: &FrameData,
        with: Drawables<'_>,
    ) {
        self.frame.write(queue, data);
        let attachments: Vec<_> = colors
            .iter()
            .map(|(view, clear)| {
                Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load: part.load(*clear), store: wgpu::StoreOp::Store },
                })
            })
            .collect();
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("main pass"),
            color_attachments: &attachments,
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations { load: part.load(1.0), store: part.store(self.keep_depth) }),
                stencil_ops: Some(wgpu::Operations { load: part.load(0), store: part.store(false) }),
            }),
            timestamp_writes: timer.and_then(|t| t.main_writes(part.first, part.last)),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &self.bind_group, &[]);
        let order = data.draw_order.get(part.draws.clone()).unwrap_or_default();
        let order = order.iter().map(|&i| (i, main_variant(&data.items[i], data.methods, measuring)));
        pipelines.draw(&mut pass, with, &data.items, order);
        if part.last {
            let measured = measuring.then_some(data.frame.first_measured as usize);
            self.planar.draw(&mut pass, with, data, measured);
        }
    }
}

/// Refuses light data of `bytes` (for `lights` lights) that one storage binding of `limit` bytes
/// cannot hold.
fn fits_one_binding(lights: usize, bytes: u64, limit: u64) -> Result<(), RenderError> {
    if bytes > limit { Err(RenderError::TooManyLights { lights, bytes, limit }) } else { Ok(()) }
}

/// Every cookie image, a byte per texel, packed four to a word in one uniform buffer.
///
/// The images are small enough for a uniform buffer, which needs no sampler, and the shader
/// filters them itself.
fn cookie_buffer(device: &wgpu::Device) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    let bytes: Vec<u8> = Cookie::ALL.iter().flat_map(|c| cookie_image(*c, COOKIE_SIZE)).collect();
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("cookies"),
        contents: &bytes,
        usage: wgpu::BufferUsages::UNIFORM,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lights_past_one_binding_are_refused_with_the_limit_named() {
        assert!(fits_one_binding(1024, 180_224, 134_217_728).is_ok());
        let error = fits_one_binding(800_000, 140_800_000, 134_217_728).unwrap_err().to_string();
        assert!(error.contains("800000 lights") && error.contains("max_storage_buffer_binding_size"), "{error}");
    }
}
