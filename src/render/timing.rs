//! GPU time of the shadow pass and the main pass, from timestamp queries written at the start
//! and end of each: read at once by the measuring tools, or a frame or two later without waiting
//! by the window's live graph.

use super::{Gpu, RenderError};

/// Query indices: shadow pass start and end, main pass start and end.
const SHADOW_START: u32 = 0;
const SHADOW_END: u32 = 1;
const MAIN_START: u32 = 2;
const MAIN_END: u32 = 3;

/// Timestamp queries around the passes of one frame.
pub struct PassTimer {
    queries: wgpu::QuerySet,
    resolved: wgpu::Buffer,
    read: wgpu::Buffer,
    /// Nanoseconds per timestamp tick.
    period: f64,
    /// Whether the frame being encoded draws any shadow layer (otherwise its shadow time is zero).
    shadow_written: bool,
    /// Whether the frame being encoded drew the camera's depth before the main pass (which then
    /// starts the main pass's time).
    main_started: bool,
    /// Whether the frame whose stamps `read` holds drew any shadow layer.
    copied_shadow: bool,
    /// `read` holds the stamps of a submitted frame that nobody has asked for yet.
    copied: bool,
    /// `read` is being mapped for [`PassTimer::poll`]; frames go unstamped into it meanwhile.
    mapping: Option<std::sync::mpsc::Receiver<Result<(), wgpu::BufferAsyncError>>>,
}

/// What the passes of the last frame cost on the GPU.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PassTimes {
    /// Every shadow layer drawn, first pass start to last pass end, in milliseconds.
    pub shadow_ms: f64,
    /// The main pass (with the camera's depth drawn before it, for contact shadows), in
    /// milliseconds.
    pub main_ms: f64,
}

impl PassTimer {
    /// Timestamp queries on `gpu`, or `None` when its device cannot write them.
    pub fn new(gpu: &Gpu) -> Option<PassTimer> {
        if !gpu.device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
            return None;
        }
        let queries = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("pass times"),
            ty: wgpu::QueryType::Timestamp,
            count: 4,
        });
        let buffer = |label, size, usage| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        // Each pass's pair is resolved on its own, at a resolve-aligned offset.
        let usage = wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC;
        let resolved = buffer("pass times", 2 * wgpu::QUERY_RESOLVE_BUFFER_ALIGNMENT, usage);
        let read = buffer("pass times read", 32, wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ);
        let period = gpu.queue.get_timestamp_period() as f64;
        Some(PassTimer {
            queries,
            resolved,
            read,
            period,
            shadow_written: false,
            main_started: false,
            copied_shadow: false,
            copied: false,
            mapping: None,
        })
    }

    /// Writes for shadow-layer pass `i` of `n`: the first marks the start, the last the end.
    pub fn shadow_writes(&mut self, i: usize, n: usize) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        self.shadow_written = n > 0;
        let (first, last) = (i == 0, i + 1 == n);
        (first || last).then_some(wgpu::RenderPassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: first.then_some(SHADOW_START),
            end_of_pass_write_index: last.then_some(SHADOW_END),
        })
    }

    /// Writes for the camera's depth drawn before the main pass (for contact shadows): the main
    /// pass's time starts with it.
    pub fn camera_writes(&mut self) -> wgpu::RenderPassTimestampWrites<'_> {
        self.main_started = true;
        wgpu::RenderPassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(MAIN_START),
            end_of_pass_write_index: None,
        }
    }

    /// Writes for a part of the main pass (see [`super::parts`]): the first its start, unless
    /// the camera's depth started it, the last its end; none for a part between.
    pub fn main_writes(&self, first: bool, last: bool) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let start = (first && !self.main_started).then_some(MAIN_START);
        let end = last.then_some(MAIN_END);
        (start.is_some() || end.is_some()).then_some(wgpu::RenderPassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: start,
            end_of_pass_write_index: end,
        })
    }

    /// Starts a frame: no shadow layer written yet, no camera depth drawn.
    pub fn begin(&mut self) {
        self.shadow_written = false;
        self.main_started = false;
    }

    /// Copies the frame's timestamps out; call after both passes are encoded. While an earlier
    /// frame's stamps are still being mapped, this frame's are not kept.
    pub fn resolve(&mut self, encoder: &mut wgpu::CommandEncoder) {
        if self.mapping.is_some() {
            return;
        }
        let second = wgpu::QUERY_RESOLVE_BUFFER_ALIGNMENT;
        if self.shadow_written {
            encoder.resolve_query_set(&self.queries, SHADOW_START..SHADOW_END + 1, &self.resolved, 0);
            encoder.copy_buffer_to_buffer(&self.resolved, 0, &self.read, 0, 16);
        }
        encoder.resolve_query_set(&self.queries, MAIN_START..MAIN_END + 1, &self.resolved, second);
        encoder.copy_buffer_to_buffer(&self.resolved, second, &self.read, 16, 16);
        (self.copied, self.copied_shadow) = (true, self.shadow_written);
    }

    /// The pass times of the frame last submitted (waits for the GPU).
    pub fn read(&mut self, gpu: &Gpu) -> Result<PassTimes, RenderError> {
        let rx = match self.mapping.take() {
            Some(rx) => rx,
            None => self.start_mapping(),
        };
        gpu.wait()?;
        rx.recv()
            .map_err(|e| RenderError::Wgpu(format!("timestamps never arrived: {e}")))?
            .map_err(|e| RenderError::Wgpu(format!("timestamps could not be read: {e}")))?;
        self.take_mapped()
    }

    /// The pass times of a frame submitted a little earlier, once the GPU has them; never waits.
    /// Call once a frame after submitting it: each call starts reading the newest stamps when
    /// none are on their way.
    pub fn poll(&mut self, gpu: &Gpu) -> Option<PassTimes> {
        if self.mapping.is_none() && self.copied {
            self.mapping = Some(self.start_mapping());
        }
        let _ = gpu.device.poll(wgpu::PollType::Poll);
        match self.mapping.as_ref()?.try_recv() {
            Err(std::sync::mpsc::TryRecvError::Empty) => None,
            done => {
                self.mapping = None;
                done.ok()?.ok()?;
                self.take_mapped().ok()
            }
        }
    }

    fn start_mapping(&mut self) -> std::sync::mpsc::Receiver<Result<(), wgpu::BufferAsyncError>> {
        let (tx, rx) = std::sync::mpsc::channel();
        self.read.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        self.copied = false;
        rx
    }

    /// The times in the mapped `read` buffer, which it unmaps.
    fn take_mapped(&self) -> Result<PassTimes, RenderError> {
        let ticks: [u64; 4] = {
            let mapped = self.read.get_mapped_range(..).map_err(|e| RenderError::Wgpu(e.to_string()))?;
            bytemuck::pod_read_unaligned(&mapped[..32])
        };
        self.read.unmap();
        let ms = |a: u64, b: u64| b.saturating_sub(a) as f64 * self.period / 1e6;
        let shadow_ms = if self.copied_shadow { ms(ticks[0], ticks[1]) } else { 0.0 };
        Ok(PassTimes { shadow_ms, main_ms: ms(ticks[2], ticks[3]) })
    }
}
/// Hands out the frame's shadow passes' timestamps: the first pass's start, the last's end.
pub(super) struct Stamps<'t> {
    pub(super) timer: Option<&'t mut PassTimer>,
    pub(super) next: usize,
    pub(super) total: usize,
}

impl Stamps<'_> {
    pub(super) fn next(&mut self) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let i = self.next;
        self.next += 1;
        self.timer.as_deref_mut()?.shadow_writes(i, self.total)
    }

    /// The same for a compute pass.
    pub(super) fn next_compute(&mut self) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.next().map(|w| wgpu::ComputePassTimestampWrites {
            query_set: w.query_set,
            beginning_of_pass_write_index: w.beginning_of_pass_write_index,
            end_of_pass_write_index: w.end_of_pass_write_index,
        })
    }
}
