//! The depth reduction of sample distribution shadow maps (see [`crate::shadow::VisibleSamples`]
//! for what it finds and `shaders/sdsm.wgsl` for how): a compute pass over the camera's depth
//! buffer after the main pass, its words copied to a buffer that is read back without waiting,
//! so its result arrives a frame or two later.

use super::gpu_types::Reduce;
use super::shaders::{Composed, SDSM};
use crate::shadow::{SDSM_WORDS, VisibleSamples, initial_words};
use std::sync::mpsc::{Receiver, TryRecvError};

/// Where the reduction's words were binned: the range of view depths and the light space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Binning {
    /// The view depths the bins span.
    pub range: (f32, f32),
    /// The sun's light space the boxes are in.
    pub light_from_world: glam::Mat4,
}

/// The pipeline, its buffers and the reading in flight.
pub struct DepthReduction {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    uniform: wgpu::Buffer,
    words: wgpu::Buffer,
    read: wgpu::Buffer,
    /// The binning of the words copied into `read` and not yet mapped.
    copied: Option<Binning>,
    /// The mapping under way, and the binning of what it maps.
    mapping: Option<(Receiver<Result<(), wgpu::BufferAsyncError>>, Binning)>,
    /// The bind group, and which depth buffer it binds (made again only for a new one).
    bound: Option<(u64, wgpu::BindGroup)>,
}

impl DepthReduction {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device) -> Self {
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty,
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("depth reduction"),
            entries: &[
                entry(
                    0,
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                ),
                entry(
                    1,
                    wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                ),
                entry(
                    2,
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: false },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                ),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("depth reduction"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let module = Composed::new(&[SDSM]).module(device);
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("depth reduction"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("reduce_depth"),
            compilation_options: Default::default(),
            cache: None,
        });
        let buffer = |label, size, usage| {
            device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size, usage, mapped_at_creation: false })
        };
        let bytes = (SDSM_WORDS * 4) as u64;
        use wgpu::BufferUsages as U;
        DepthReduction {
            pipeline,
            layout,
            uniform: buffer("reduce", size_of::<Reduce>() as u64, U::UNIFORM | U::COPY_DST),
            words: buffer("reduction words", bytes, U::STORAGE | U::COPY_DST | U::COPY_SRC),
            read: buffer("reduction read", bytes, U::MAP_READ | U::COPY_DST),
            copied: None,
            mapping: None,
            bound: None,
        }
    }

    /// Reduces `depth` (the camera's depth buffer, `reduce.size` texels, its depth aspect, with
    /// a number that changes whenever the buffer is made anew) into the words, binned as
    /// `binning` says, and copies them out to be read, unless a reading is still under way.
    pub fn encode(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        encoder: &mut wgpu::CommandEncoder,
        depth: &wgpu::TextureView,
        made: u64,
        reduce: Reduce,
        binning: Binning,
    ) {
        if self.mapping.is_some() || self.copied.is_some() {
            return;
        }
        queue.write_buffer(&self.uniform, 0, bytemuck::bytes_of(&reduce));
        queue.write_buffer(&self.words, 0, bytemuck::cast_slice(&initial_words()));
        if self.bound.as_ref().is_none_or(|(m, _)| *m != made) {
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("depth reduction"),
                layout: &self.layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: self.uniform.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(depth) },
                    wgpu::BindGroupEntry { binding: 2, resource: self.words.as_entire_binding() },
                ],
            });
            self.bound = Some((made, bind_group));
        }
        let (_, bind_group) = self.bound.as_ref().expect("made above");
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("depth reduction"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, bind_group, &[]);
            pass.dispatch_workgroups(reduce.size[0].div_ceil(8), reduce.size[1].div_ceil(8), 1);
        }
        encoder.copy_buffer_to_buffer(&self.words, 0, &self.read, 0, (SDSM_WORDS * 4) as u64);
        self.copied = Some(binning);
    }

    /// What the last reduction read back found, once the GPU has it; never waits (with `wait`,
    /// waits for the one submitted last).
    pub fn poll(&mut self, device: &wgpu::Device, wait: bool) -> Option<VisibleSamples> {
        if self.mapping.is_none()
            && let Some(binning) = self.copied.take()
        {
            let (tx, rx) = std::sync::mpsc::channel();
            self.read.map_async(wgpu::MapMode::Read, .., move |r| {
                let _ = tx.send(r);
            });
            self.mapping = Some((rx, binning));
        }
        let how = if wait { wgpu::PollType::wait_indefinitely() } else { wgpu::PollType::Poll };
        let _ = device.poll(how);
        let (rx, binning) = self.mapping.as_ref()?;
        match rx.try_recv() {
            Err(TryRecvError::Empty) => None,
            done => {
                let binning = *binning;
                self.mapping = None;
                done.ok()?.ok()?;
                let words: Vec<u32> = {
                    let mapped = self.read.get_mapped_range(..).ok()?;
                    bytemuck::cast_slice(&mapped[..]).to_vec()
                };
                self.read.unmap();
                Some(VisibleSamples::from_words(&words, binning.range, binning.light_from_world))
            }
        }
    }
}

/// True when `adapter` runs compute shaders, which the reduction needs.
pub fn computes(adapter: &wgpu::Adapter) -> bool {
    adapter.get_downlevel_capabilities().flags.contains(wgpu::DownlevelFlags::COMPUTE_SHADERS)
}
