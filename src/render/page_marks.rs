//! The marking of virtual pages (see `shaders/page_marks.wgsl`): after the main pass, a compute
//! pass over the camera's depth buffer sets a bit for each page a visible pixel of a paged light
//! needs; the bits are read back without waiting and reach the app a frame or two later, which
//! gives the pages slots ([`crate::components::MarkedPages`]). A marking takes up to
//! [`MARK_BATCH`] paged lights, each in its own slice of the marks: with more, the batches take
//! turns, a batch a marking.

use super::async_read::AsyncRead;
use super::depth_compute::DepthCompute;
use super::frame::{FrameData, FrameLight};
use super::gpu_types::{MarkLight, MarkView};
use super::shaders::MARK_MODULE;
use crate::light::Kind;
use crate::light::clusters::Reach;
use crate::shadow::{MARK_WORDS, MAX_PAGE_LEVELS, PageMarks, PageSpace, Window};

/// Most paged lights one marking takes. The pass costs each pixel a box test for each light of
/// the batch, and the marks read back are 8 KiB a light.
pub const MARK_BATCH: usize = 64;

/// What a light's marking was made against: the light, its pages, their windows and the bias.
struct MarkTag {
    light: u64,
    space: PageSpace,
    windows: Vec<Window>,
    bias: f32,
}

/// The pipeline, its buffers and the reading in flight.
pub struct PageMarking {
    pass: DepthCompute,
    view: wgpu::Buffer,
    lights: wgpu::Buffer,
    marks: wgpu::Buffer,
    read: AsyncRead<Vec<MarkTag>>,
    /// Markings started so far: which batch of paged lights is next, and each reading's number.
    started: u64,
}

/// Words of marks a light: every level's.
const LIGHT_WORDS: usize = MAX_PAGE_LEVELS as usize * MARK_WORDS;

impl PageMarking {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device) -> Self {
        let buffer = |label, size, usage| {
            device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size, usage, mapped_at_creation: false })
        };
        use wgpu::BufferUsages as U;
        let mark_bytes = (MARK_BATCH * LIGHT_WORDS * 4) as u64;
        PageMarking {
            pass: DepthCompute::new(device, "page marking", MARK_MODULE, "mark_pages", 1),
            view: buffer("marking view", size_of::<MarkView>() as u64, U::UNIFORM | U::COPY_DST),
            lights: buffer("marking lights", (MARK_BATCH * size_of::<MarkLight>()) as u64, U::STORAGE | U::COPY_DST),
            marks: buffer("page marks", mark_bytes, U::STORAGE | U::COPY_DST | U::COPY_SRC),
            read: AsyncRead::new(device, "page marks read", mark_bytes),
            started: 0,
        }
    }

    /// Marks the pages the pixels of `depth` (the camera's depth buffer of `data`'s frame, its
    /// depth aspect, and its size) need of the next batch of paged lights, and copies the marks
    /// out to be read, unless a reading is still under way or no light is paged.
    pub fn encode(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        encoder: &mut wgpu::CommandEncoder,
        (depth, size): (&wgpu::TextureView, (u32, u32)),
        data: &FrameData,
    ) {
        let paged: Vec<_> = data.lights.iter().filter(|l| l.layer_count > 0 && l.light.pages.is_some()).collect();
        if self.read.busy() || paged.is_empty() {
            return;
        }
        let batches = paged.chunks(MARK_BATCH).count() as u64;
        let batch = paged.chunks(MARK_BATCH).nth((self.started % batches) as usize).unwrap_or_default();
        self.started += 1;
        let (lights, tags): (Vec<MarkLight>, Vec<MarkTag>) = batch.iter().filter_map(|l| mark_light(l, data)).unzip();
        let frame = &data.frame;
        let view = MarkView {
            world_from_clip: data.clip_from_world.inverse(),
            eye: frame.camera_position,
            count: lights.len() as u32,
            forward: frame.camera_forward,
            pixel_angle: frame.pixel_angle,
            size: [size.0, size.1],
            _pad0: 0,
            _pad1: 0,
        };
        queue.write_buffer(&self.view, 0, bytemuck::bytes_of(&view));
        queue.write_buffer(&self.lights, 0, bytemuck::cast_slice(&lights));
        encoder.clear_buffer(&self.marks, 0, Some((lights.len() * LIGHT_WORDS * 4) as u64));
        // Each invocation marks 4x4 pixels, a workgroup 8x8 invocations.
        let groups = (size.0.div_ceil(32), size.1.div_ceil(32));
        self.pass.dispatch(device, encoder, (&self.view, &self.marks, &[&self.lights]), depth, groups);
        self.read.copy(encoder, &self.marks, tags);
    }

    /// What the last marking read back for each light of its batch, once the GPU has it; never
    /// waits (with `wait`, waits for the one submitted last).
    pub fn poll(&mut self, device: &wgpu::Device, wait: bool) -> Vec<PageMarks> {
        let Some((bits, tags)) = self.read.poll(device, wait) else { return Vec::new() };
        let seq = self.started;
        let slices = bits.chunks(LIGHT_WORDS);
        let each = tags.into_iter().zip(slices);
        let marks = |(tag, bits): (MarkTag, &[u32])| PageMarks {
            light: tag.light,
            seq,
            space: tag.space,
            windows: tag.windows,
            bias: tag.bias,
            bits: bits.to_vec(),
        };
        each.map(marks).collect()
    }
}

/// What the marking reads of paged light `light` of frame `data`, and what its marks will be
/// taken against; none for a light that is not paged.
fn mark_light(light: &FrameLight, data: &FrameData) -> Option<(MarkLight, MarkTag)> {
    let pages = light.light.pages.as_ref()?;
    let mut origins = [[0i32; 4]; (MAX_PAGE_LEVELS / 2) as usize];
    for (l, w) in pages.windows.iter().enumerate().take(MAX_PAGE_LEVELS as usize) {
        origins[l / 2][2 * (l % 2)..2 * (l % 2) + 2].copy_from_slice(&[w.origin.x, w.origin.y]);
    }
    let kind = &light.light.kind;
    let reach = match kind.reach() {
        Reach::Everywhere => [0.0, 0.0, 0.0, -1.0],
        Reach::Sphere { centre, radius } => centre.extend(radius).to_array(),
    };
    let space = &pages.space;
    let marking = MarkLight {
        page_from_world: space.face_matrices(),
        origins,
        light: kind.homogeneous().to_array(),
        reach,
        shadow_distance: if space.fades() { data.frame.shadow_distance } else { f32::MAX },
        finest_log2: space.finest_log2(),
        levels: space.levels(),
        bias: pages.bias,
        extent: space.extent().unwrap_or(0.0),
        faces: space.faces() as u32,
        face_side: space.face_side().unwrap_or(0.0),
        coarser: light.light.reads_coarser_pages(data.frame.pcss_search == 1) as u32,
    };
    let tag = MarkTag {
        light: light.light.entity.to_bits(),
        space: *space,
        windows: pages.windows.clone(),
        bias: pages.bias,
    };
    Some((marking, tag))
}
