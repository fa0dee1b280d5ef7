//! The marking of virtual pages (see `shaders/page_marks.wgsl`): after the main pass, a compute
//! pass over the camera's depth buffer sets a bit for each page a visible pixel of a paged light
//! needs; the bits are read back without waiting and reach the app a frame or two later, which
//! gives the pages slots ([`crate::components::MarkedPages`]). With several paged lights they take
//! turns, a light a marking.

use super::async_read::AsyncRead;
use super::depth_compute::DepthCompute;
use super::frame::FrameData;
use super::gpu_types::Marking;
use super::shaders::PAGE_MARKS;
use crate::light::Kind;
use crate::light::clusters::Reach;
use crate::shadow::{MARK_WORDS, MAX_PAGE_LEVELS, PageMarks, PageSpace, Window};

/// What a marking was made against: the light, its pages and their windows.
struct MarkTag {
    light: u64,
    space: PageSpace,
    windows: Vec<Window>,
}

/// The pipeline, its buffers and the reading in flight.
pub struct PageMarking {
    pass: DepthCompute,
    uniform: wgpu::Buffer,
    marks: wgpu::Buffer,
    read: AsyncRead<MarkTag>,
    /// Markings started so far: which paged light is next, and each reading's number.
    started: u64,
}

/// Bytes of marks: every level's words.
const MARK_BYTES: u64 = (MAX_PAGE_LEVELS as usize * MARK_WORDS * 4) as u64;

impl PageMarking {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device) -> Self {
        let buffer = |label, size, usage| {
            device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size, usage, mapped_at_creation: false })
        };
        use wgpu::BufferUsages as U;
        PageMarking {
            pass: DepthCompute::new(device, "page marking", &[PAGE_MARKS], "mark_pages"),
            uniform: buffer("marking", size_of::<Marking>() as u64, U::UNIFORM | U::COPY_DST),
            marks: buffer("page marks", MARK_BYTES, U::STORAGE | U::COPY_DST | U::COPY_SRC),
            read: AsyncRead::new(device, "page marks read", MARK_BYTES),
            started: 0,
        }
    }

    /// Marks the pages the pixels of `depth` (the camera's depth buffer of `data`'s frame, its
    /// depth aspect, with a number that changes whenever it is made anew, and its size) need of
    /// the next paged light, and copies the marks out to be read, unless a reading is still
    /// under way or no light is paged.
    pub fn encode(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        encoder: &mut wgpu::CommandEncoder,
        (depth, made, size): (&wgpu::TextureView, u64, (u32, u32)),
        data: &FrameData,
    ) {
        let paged: Vec<_> = data.lights.iter().filter(|l| l.layer_count > 0 && l.light.pages.is_some()).collect();
        if self.read.busy() || paged.is_empty() {
            return;
        }
        let light = paged[(self.started % paged.len() as u64) as usize];
        self.started += 1;
        let Some(view) = light.light.pages.as_ref() else { return };
        let mut origins = [[0i32; 4]; (MAX_PAGE_LEVELS / 2) as usize];
        for (l, w) in view.windows.iter().enumerate().take(MAX_PAGE_LEVELS as usize) {
            origins[l / 2][2 * (l % 2)..2 * (l % 2) + 2].copy_from_slice(&[w.origin.x, w.origin.y]);
        }
        let frame = &data.frame;
        let kind = &light.light.kind;
        let reach = match kind.reach() {
            Reach::Everywhere => [0.0, 0.0, 0.0, -1.0],
            Reach::Sphere { centre, radius } => centre.extend(radius).to_array(),
        };
        let marking = Marking {
            world_from_clip: data.clip_from_world.inverse(),
            page_from_world: view.space.face_matrices(),
            origins,
            light: kind.homogeneous().to_array(),
            reach,
            eye: frame.camera_position,
            shadow_distance: if view.space.fades() { frame.shadow_distance } else { f32::MAX },
            forward: frame.camera_forward,
            finest_log2: view.space.finest_log2(),
            size: [size.0, size.1],
            levels: view.space.levels(),
            pixel_angle: frame.pixel_angle,
            bias: view.bias,
            extent: view.space.extent().unwrap_or(0.0),
            faces: view.space.faces() as u32,
            face_side: view.space.face_side().unwrap_or(0.0),
        };
        queue.write_buffer(&self.uniform, 0, bytemuck::bytes_of(&marking));
        encoder.clear_buffer(&self.marks, 0, None);
        // Each invocation marks 4x4 pixels, a workgroup 8x8 invocations.
        let groups = (size.0.div_ceil(32), size.1.div_ceil(32));
        self.pass.dispatch(device, encoder, (&self.uniform, &self.marks), (depth, made), groups);
        let tag = MarkTag { light: light.light.entity.to_bits(), space: view.space, windows: view.windows.clone() };
        self.read.copy(encoder, &self.marks, tag);
    }

    /// What the last marking read back, once the GPU has it; never waits (with `wait`, waits for
    /// the one submitted last).
    pub fn poll(&mut self, device: &wgpu::Device, wait: bool) -> Option<PageMarks> {
        let (bits, tag) = self.read.poll(device, wait)?;
        let seq = self.started;
        Some(PageMarks { light: tag.light, seq, space: tag.space, windows: tag.windows, bits })
    }
}
