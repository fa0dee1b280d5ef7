//! Filling an atlas tile before its casters are drawn (shaders/tile.wgsl): a triangle over the
//! tile at the far plane clears its depth (and writes its colour map's empty value), or puts
//! back the depth of its casters at rest from the static atlas. A render pass clears only whole
//! pages, and depth cannot be copied in part of a texture (WebGPU copies depth only whole), so
//! this is how one tile of a page is made afresh while the others keep theirs.

use super::gpu_types::Fill;
use super::shaders::{Composed, TILE};
use super::uniform_array::UniformArray;
use std::collections::HashMap;

/// What a fill does to its tile.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FillKind {
    /// Depth to the far plane, and a colour map (of that format, if any) to its empty value.
    Clear(Option<wgpu::TextureFormat>),
    /// Depth from the static atlas.
    Restore,
}

/// The fill pipelines, made as first needed, and each frame's fill uniforms.
pub struct TileFill {
    module: wgpu::ShaderModule,
    uniforms: UniformArray,
    statics_layout: wgpu::BindGroupLayout,
    pipelines: HashMap<(wgpu::TextureFormat, FillKind), wgpu::RenderPipeline>,
}

impl TileFill {
    /// No pipeline yet.
    pub fn new(device: &wgpu::Device) -> Self {
        let uniforms = UniformArray::new(device, "tile fill", size_of::<Fill>() as u64, wgpu::ShaderStages::FRAGMENT);
        let statics_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("static atlas"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Depth,
                    view_dimension: wgpu::TextureViewDimension::D2Array,
                    multisampled: false,
                },
                count: None,
            }],
        });
        let module = Composed::new(&[TILE]).module(device);
        TileFill { module, uniforms, statics_layout, pipelines: HashMap::new() }
    }

    /// A bind group of the static atlas's pages (`view`), for [`FillKind::Restore`].
    pub fn statics(&self, device: &wgpu::Device, view: &wgpu::TextureView) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("static atlas"),
            layout: &self.statics_layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(view) }],
        })
    }

    /// Makes the pipeline of `kind` into depth of `depth` unless it is made.
    pub fn prepare(&mut self, device: &wgpu::Device, depth: wgpu::TextureFormat, kind: FillKind) {
        if self.pipelines.contains_key(&(depth, kind)) {
            return;
        }
        let mut groups = vec![Some(&self.uniforms.layout)];
        if kind == FillKind::Restore {
            groups.push(Some(&self.statics_layout));
        }
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("tile fill"),
            bind_group_layouts: &groups,
            immediate_size: 0,
        });
        let colour = match kind {
            FillKind::Clear(colour) => colour,
            FillKind::Restore => None,
        };
        let targets = [colour.map(wgpu::ColorTargetState::from)];
        let entry = match kind {
            FillKind::Clear(Some(_)) => Some("fs_clear_colour"),
            FillKind::Clear(None) => None,
            FillKind::Restore => Some("fs_restore"),
        };
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("tile fill"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &self.module,
                entry_point: Some("vs_fill"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: depth,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: entry.map(|entry| wgpu::FragmentState {
                module: &self.module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                targets: if colour.is_some() { &targets } else { &[] },
            }),
            multiview_mask: None,
            cache: None,
        });
        self.pipelines.insert((depth, kind), pipeline);
    }

    /// Uploads this frame's fills, one per tile filled, in the order [`TileFill::draw`] takes.
    pub fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, fills: &[Fill]) {
        self.uniforms.write(device, queue, fills);
    }

    /// Fills the tile the pass's viewport is on with fill `index` (prepared for `depth` and
    /// `kind`; with `statics` bound for a restore). The caller binds its own group 0 after.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        (depth, kind): (wgpu::TextureFormat, FillKind),
        index: usize,
        statics: Option<&wgpu::BindGroup>,
    ) {
        let Some(pipeline) = self.pipelines.get(&(depth, kind)) else { return };
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &self.uniforms.bind_group, &[self.uniforms.offset(index)]);
        if let (FillKind::Restore, Some(group)) = (kind, statics) {
            pass.set_bind_group(1, group, &[]);
        }
        pass.draw(0..3, 0..1);
    }
}
