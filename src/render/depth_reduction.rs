//! The depth reduction of sample distribution shadow maps (see [`crate::shadow::VisibleSamples`]
//! for what it finds and `shaders/sdsm.wgsl` for how): a compute pass over the camera's depth
//! buffer after the main pass, its words copied to a buffer that is read back without waiting,
//! so its result arrives a frame or two later.

use super::async_read::AsyncRead;
use super::depth_compute::DepthCompute;
use super::frame::FrameData;
use super::gpu_types::Reduce;
use super::shaders::SDSM;
use crate::components::{Camera, DirectionalLight};
use crate::settings::CascadeSettings;
use crate::shadow::{SDSM_WORDS, VisibleSamples, initial_words};
use bevy_ecs::world::World;

/// Where the reduction's words were binned: the range of view depths and the light space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Binning {
    /// The view depths the bins span.
    pub range: (f32, f32),
    /// The sun's light space the boxes are in.
    pub light_from_world: glam::Mat4,
}

/// What the reduction of frame `data`'s depth buffer (`size` pixels) reads and how it bins it:
/// the view depths up to the shadows' reach, and the first sun's light space. None without a
/// camera, a sun or cascade settings.
pub fn frame_reduction(world: &World, data: &FrameData, size: (u32, u32)) -> Option<(Reduce, Binning)> {
    let shadow_distance = world.get_resource::<CascadeSettings>()?.shadow_distance;
    let camera = world.try_query::<&Camera>().and_then(|mut q| q.iter(world).next().copied())?;
    let sun = world.try_query::<&DirectionalLight>().and_then(|mut q| q.iter(world).next().map(|s| s.direction))?;
    let far = camera.shadow_far(shadow_distance);
    let binning =
        Binning { range: (camera.near, far), light_from_world: crate::shadow::light_view(glam::Vec3::ZERO, sun) };
    let reduce = Reduce {
        world_from_clip: data.clip_from_world.inverse(),
        light_from_world: binning.light_from_world,
        eye: data.frame.camera_position,
        near: binning.range.0,
        forward: data.frame.camera_forward,
        far: binning.range.1,
        size: [size.0, size.1],
        _pad: [0; 2],
    };
    Some((reduce, binning))
}

/// The pipeline, its buffers and the reading in flight.
pub struct DepthReduction {
    pass: DepthCompute,
    uniform: wgpu::Buffer,
    words: wgpu::Buffer,
    /// The words read back, each reading with its binning.
    read: AsyncRead<Binning>,
}

impl DepthReduction {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device) -> Self {
        let buffer = |label, size, usage| {
            device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size, usage, mapped_at_creation: false })
        };
        let bytes = (SDSM_WORDS * 4) as u64;
        use wgpu::BufferUsages as U;
        DepthReduction {
            pass: DepthCompute::new(device, "depth reduction", &[SDSM], "reduce_depth", 0),
            uniform: buffer("reduce", size_of::<Reduce>() as u64, U::UNIFORM | U::COPY_DST),
            words: buffer("reduction words", bytes, U::STORAGE | U::COPY_DST | U::COPY_SRC),
            read: AsyncRead::new(device, "reduction read", bytes),
        }
    }

    /// Reduces `depth` (the camera's depth buffer, `reduce.size` texels, its depth aspect) into
    /// the words, binned as `binning` says, and copies them out to be read, unless a reading is
    /// still under way.
    pub fn encode(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        encoder: &mut wgpu::CommandEncoder,
        depth: &wgpu::TextureView,
        reduce: Reduce,
        binning: Binning,
    ) {
        if self.read.busy() {
            return;
        }
        queue.write_buffer(&self.uniform, 0, bytemuck::bytes_of(&reduce));
        queue.write_buffer(&self.words, 0, bytemuck::cast_slice(&initial_words()));
        let groups = (reduce.size[0].div_ceil(8), reduce.size[1].div_ceil(8));
        self.pass.dispatch(device, encoder, (&self.uniform, &self.words, &[]), depth, groups);
        self.read.copy(encoder, &self.words, binning);
    }

    /// What the last reduction read back found, once the GPU has it; never waits (with `wait`,
    /// waits for the one submitted last).
    pub fn poll(&mut self, device: &wgpu::Device, wait: bool) -> Option<VisibleSamples> {
        let (words, binning) = self.read.poll(device, wait)?;
        Some(VisibleSamples::from_words(&words, binning.range, binning.light_from_world))
    }
}

/// True when `adapter` runs compute shaders, which the reduction needs.
pub fn computes(adapter: &wgpu::Adapter) -> bool {
    adapter.get_downlevel_capabilities().flags.contains(wgpu::DownlevelFlags::COMPUTE_SHADERS)
}
