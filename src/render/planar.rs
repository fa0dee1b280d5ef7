//! Planar projected shadows, drawn at the end of the main pass (seed 004's technique): for each
//! light whose method is [`ShadowMethod::Planar`], every caster is flattened onto the ground by
//! the light's planar projection ([`crate::shadow::flat_from_world`]) and drawn over it, taking
//! away exactly what that light gave the ground there.
//!
//! The stencil buffer keeps a pixel from losing a light twice where flattened casters overlap:
//! light k's draws pass only where the stencil is not yet k + 1, and set it to k + 1. The depth
//! test against the scene, with the flattened casters lifted [`PLANAR_LIFT`] off the plane, hides
//! the shadow behind whatever stands on the ground (a box top under a floating cube stays lit).
//! In the measuring view the same draws write visibility 0 into the light's channel instead.

use super::frame::{DrawItem, FrameData, FrameLight, PlanarDraw};
use super::gpu_types::{GpuPlanar, MEASURED_PER_PASS};
use super::growing::GrowingBuffer;
use super::mesh::{AlphaClass, Drawables, JointPalette, Pipelines, Recipe, Variant};
use super::texture::MaterialTextures;
use crate::components::ShadowMethod;
use crate::light::{Kind, Light};
use crate::shadow::{Aabb, GROUND_PLANE, PLANAR_LIFT, flat_from_world, lights_plane};

/// How close to the plane (metres) a surface must lie to count as the ground, and how far above
/// it a caster must reach to be flattened.
const ON_PLANE: f32 = 1e-3;

/// The receiving plane's surface among `items`: the widest flat receiver lying on the plane.
pub fn ground(items: &[(DrawItem, Aabb)]) -> Option<usize> {
    let flat = |b: &Aabb| b.min.y.abs() < ON_PLANE && b.max.y.abs() < ON_PLANE;
    let area = |b: &Aabb| (b.max.x - b.min.x) * (b.max.z - b.min.z);
    (0..items.len())
        .filter(|&i| items[i].0.object.receives_shadows == 1 && flat(&items[i].1))
        .max_by(|&a, &b| area(&items[a].1).total_cmp(&area(&items[b].1)))
}

/// Draws planar shadows onto the ground: its method is planar, or it casts a shadow and
/// `ground_too` (the settings' planar_ground) gives every shadowed light planar shadows there.
pub fn draws_planar(light: &Light, ground_too: bool) -> bool {
    light.shadowed && (light.method == ShadowMethod::Planar || ground_too)
}

/// The planar shadows of `lights` (a light's index is its place in the list) over the ground of
/// `items`, for the lights [`draws_planar`] picks: none without a ground, and none from a light
/// below it or a sun shining up.
pub fn planar_draws(lights: &[FrameLight], items: &[(DrawItem, Aabb)], ground_too: bool) -> Vec<PlanarDraw> {
    let Some(ground) = ground(items) else { return Vec::new() };
    let g = &items[ground].0.object;
    let casters: Vec<usize> =
        (0..items.len()).filter(|&i| i != ground && items[i].0.caster && items[i].1.max.y > ON_PLANE).collect();
    lights
        .iter()
        .enumerate()
        .filter(|(_, l)| draws_planar(&l.light, ground_too))
        .filter_map(|(index, l)| {
            let point = l.light.kind.homogeneous();
            lights_plane(GROUND_PLANE, point).then(|| PlanarDraw {
                uniform: GpuPlanar {
                    flat_from_world: flat_from_world(GROUND_PLANE, point),
                    plane: GROUND_PLANE,
                    ground: g.base_color.truncate().extend(g.specular),
                    light: index as u32,
                    shininess: g.shininess,
                    lift: PLANAR_LIFT,
                    _pad0: 0,
                },
                casters: casters.clone(),
            })
        })
        .collect()
}

/// The stencil and depth test of the flattened casters: drawn where nothing stands in front of
/// the lifted plane, and only once per light and pixel (see the module's notes).
fn stencil_test(format: wgpu::TextureFormat) -> wgpu::DepthStencilState {
    let once = wgpu::StencilFaceState {
        compare: wgpu::CompareFunction::NotEqual,
        fail_op: wgpu::StencilOperation::Keep,
        depth_fail_op: wgpu::StencilOperation::Keep,
        pass_op: wgpu::StencilOperation::Replace,
    };
    wgpu::DepthStencilState {
        format,
        depth_write_enabled: Some(false),
        depth_compare: Some(wgpu::CompareFunction::LessEqual),
        stencil: wgpu::StencilState { front: once, back: once, read_mask: 0xff, write_mask: 0xff },
        bias: Default::default(),
    }
}

/// Takes a light's share away from what is drawn: destination minus source.
const SUBTRACT: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::ReverseSubtract,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::Zero,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
};

/// The planar pipelines (the picture's, and the measuring view's for each of the measured
/// lights' four channels), the lights' uniforms and bind group 0 with them added.
pub struct PlanarPass {
    picture: Pipelines,
    measure: [Pipelines; MEASURED_PER_PASS],
    layout: wgpu::BindGroupLayout,
    buffer: GrowingBuffer,
    stride: u64,
    /// Bind group 0 of the main pass with the planar uniforms as binding 8.
    pub bind_group: Option<wgpu::BindGroup>,
}

/// Where the planar pipelines draw: the picture's colour format, the measuring view's, and the
/// depth-stencil format.
pub struct PlanarTargets {
    /// The picture.
    pub color: wgpu::TextureFormat,
    /// The measuring view's three targets.
    pub measure: wgpu::TextureFormat,
    /// The camera's depth and stencil.
    pub depth: wgpu::TextureFormat,
}

impl PlanarPass {
    /// Builds the pipelines from `module` (the main module with planar.wgsl), bind group 0 laid
    /// out as the main pass's `frame_entries` plus the planar uniform.
    pub fn new(
        device: &wgpu::Device,
        module: &wgpu::ShaderModule,
        (frame_entries, object_layout): (&[wgpu::BindGroupLayoutEntry], &wgpu::BindGroupLayout),
        (palette, textures): (&JointPalette, &MaterialTextures),
        targets: PlanarTargets,
    ) -> Self {
        let mut entries = frame_entries.to_vec();
        entries.push(wgpu::BindGroupLayoutEntry {
            binding: 8,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: true,
                min_binding_size: wgpu::BufferSize::new(size_of::<GpuPlanar>() as u64),
            },
            count: None,
        });
        let layout = device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("planar"), entries: &entries });
        let depth = stencil_test(targets.depth);
        let recipe = |fragment, targets| Recipe {
            label: "planar",
            module: module.clone(),
            vertex: "vs_planar",
            fragment,
            targets,
            depth: depth.clone(),
            samples_shadows: false,
            samples: 1,
        };
        let groups = [&layout, object_layout];
        let picture_target =
            wgpu::ColorTargetState { format: targets.color, blend: Some(SUBTRACT), write_mask: wgpu::ColorWrites::ALL };
        let picture =
            Pipelines::new(device, recipe("fs_planar", vec![Some(picture_target)]), groups, palette, textures);
        let channels =
            [wgpu::ColorWrites::RED, wgpu::ColorWrites::GREEN, wgpu::ColorWrites::BLUE, wgpu::ColorWrites::ALPHA];
        let measure = channels.map(|channel| {
            // Position and normal stay as the surface wrote them; only the light's visibility.
            let target = |write_mask| Some(wgpu::ColorTargetState { format: targets.measure, blend: None, write_mask });
            let targets = vec![target(wgpu::ColorWrites::empty()), target(wgpu::ColorWrites::empty()), target(channel)];
            Pipelines::new(device, recipe("fs_planar_measure", targets), groups, palette, textures)
        });
        let align = device.limits().min_uniform_buffer_offset_alignment as u64;
        let stride = (size_of::<GpuPlanar>() as u64).div_ceil(align) * align;
        let buffer = GrowingBuffer::new(device, "planar", wgpu::BufferUsages::UNIFORM);
        PlanarPass { picture, measure, layout, buffer, stride, bind_group: None }
    }

    /// Makes bind group 0 from the main pass's `entries` and the planar uniforms.
    pub fn bind(&mut self, device: &wgpu::Device, entries: &[wgpu::BindGroupEntry<'_>]) {
        let mut entries = entries.to_vec();
        entries.push(wgpu::BindGroupEntry {
            binding: 8,
            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: &self.buffer.buffer,
                offset: 0,
                size: wgpu::BufferSize::new(size_of::<GpuPlanar>() as u64),
            }),
        });
        self.bind_group = Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("planar"),
            layout: &self.layout,
            entries: &entries,
        }));
    }

    /// How a caster is drawn flattened: rigid or skinned, both faces (flattening turns some
    /// over), with no texture or cut-out.
    fn variant(item: &DrawItem) -> Variant {
        Variant {
            skinned: item.skinned,
            cull: None,
            alpha: AlphaClass::Opaque,
            textured: false,
            methods: 0,
            instanced: false,
        }
    }

    /// Uploads the planar uniforms of `data` and builds the pipelines its casters need (the
    /// measuring view's too when `measuring`); true when the uniforms' buffer had to grow (then
    /// bind group 0 must be made again).
    pub fn prepare(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, data: &FrameData, measuring: bool) -> bool {
        let grew = self.buffer.reserve(device, data.planar.len() as u64 * self.stride);
        for (k, p) in data.planar.iter().enumerate() {
            queue.write_buffer(&self.buffer.buffer, k as u64 * self.stride, bytemuck::bytes_of(&p.uniform));
        }
        let variants: Vec<Variant> =
            data.planar.iter().flat_map(|p| p.casters.iter().map(|&i| Self::variant(&data.items[i]))).collect();
        self.picture.prepare(device, variants.iter().copied());
        for m in self.measure.iter_mut().filter(|_| measuring) {
            m.prepare(device, variants.iter().copied());
        }
        grew
    }

    /// Draws every planar shadow of `data` into `pass` (after the scene, with the depth and
    /// stencil attachment it drew into): over the picture, or with `measured` (the first light
    /// the measuring view reports) as visibility 0 in the measured lights' channels.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        with: Drawables<'_>,
        data: &FrameData,
        measured: Option<usize>,
    ) {
        let Some(group) = &self.bind_group else { return };
        for (k, p) in data.planar.iter().enumerate() {
            let pipelines = match measured {
                None => &self.picture,
                Some(first) => match (p.uniform.light as usize).checked_sub(first) {
                    Some(channel) if channel < MEASURED_PER_PASS => &self.measure[channel],
                    _ => continue,
                },
            };
            pass.set_bind_group(0, group, &[(k as u64 * self.stride) as u32]);
            pass.set_stencil_reference(k as u32 + 1);
            pipelines.draw(pass, with, &data.items, p.casters.iter().map(|&i| (i, Self::variant(&data.items[i]))));
        }
    }
}
