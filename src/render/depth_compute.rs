//! A compute pass over the camera's depth buffer: a uniform, the depth (its depth aspect, read as
//! unfilterable floats), a storage buffer of words it writes and any storage buffers it only
//! reads. The SDSM reduction and the marking of virtual pages are both one.

use super::shaders::{Composed, ShaderFile};

/// The pipeline, its layout and the bind group of the depth buffer it last read.
pub struct DepthCompute {
    label: &'static str,
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    /// The bind group, and the depth buffer it binds (made again only for another one).
    bound: Option<(wgpu::TextureView, wgpu::BindGroup)>,
}

impl DepthCompute {
    /// Builds entry point `entry` of `files`, reading `inputs` storage buffers (bindings 3 on).
    pub fn new(device: &wgpu::Device, label: &'static str, files: &[ShaderFile], entry: &str, inputs: u32) -> Self {
        let entry_of = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty,
            count: None,
        };
        let buffer = |ty| wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None };
        let depth = wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        };
        let mut entries = vec![
            entry_of(0, buffer(wgpu::BufferBindingType::Uniform)),
            entry_of(1, depth),
            entry_of(2, buffer(wgpu::BufferBindingType::Storage { read_only: false })),
        ];
        entries
            .extend((3..3 + inputs).map(|b| entry_of(b, buffer(wgpu::BufferBindingType::Storage { read_only: true }))));
        let layout =
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(label), entries: &entries });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let module = Composed::new(files).module(device);
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(label),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        });
        DepthCompute { label, pipeline, layout, bound: None }
    }

    /// Records `groups` workgroups reading `depth`, `uniform` and `inputs` (the same buffers
    /// every call), and writing `words`.
    pub fn dispatch(
        &mut self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        (uniform, words, inputs): (&wgpu::Buffer, &wgpu::Buffer, &[&wgpu::Buffer]),
        depth: &wgpu::TextureView,
        groups: (u32, u32),
    ) {
        if self.bound.as_ref().is_none_or(|(bound, _)| bound != depth) {
            let mut entries = vec![
                wgpu::BindGroupEntry { binding: 0, resource: uniform.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(depth) },
                wgpu::BindGroupEntry { binding: 2, resource: words.as_entire_binding() },
            ];
            let inputs = inputs.iter().enumerate();
            entries.extend(
                inputs.map(|(i, b)| wgpu::BindGroupEntry { binding: 3 + i as u32, resource: b.as_entire_binding() }),
            );
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(self.label),
                layout: &self.layout,
                entries: &entries,
            });
            self.bound = Some((depth.clone(), bind_group));
        }
        let (_, bind_group) = self.bound.as_ref().expect("made above");
        let mut pass = encoder
            .begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(self.label), timestamp_writes: None });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.dispatch_workgroups(groups.0, groups.1, 1);
    }
}
