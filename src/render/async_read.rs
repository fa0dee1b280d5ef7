//! A buffer read back without waiting: words copied out at the end of a frame, mapped when the
//! next frame asks, and handed over once the GPU has them (a frame or two later), each with what
//! it was made of. One reading at a time: while one is under way, none is started.

use std::sync::mpsc::{Receiver, TryRecvError};

/// The reading buffer and the reading in flight, tagged with a `T` saying what it holds.
pub struct AsyncRead<T> {
    read: wgpu::Buffer,
    /// The tag of what was copied into `read` and not yet mapped.
    copied: Option<T>,
    /// The mapping under way, and the tag of what it maps.
    mapping: Option<(Receiver<Result<(), wgpu::BufferAsyncError>>, T)>,
}

impl<T> AsyncRead<T> {
    /// A reading buffer of `bytes`.
    pub fn new(device: &wgpu::Device, label: &str, bytes: u64) -> Self {
        let read = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        AsyncRead { read, copied: None, mapping: None }
    }

    /// True while a reading is under way (copied, or being mapped): no new one can start.
    pub fn busy(&self) -> bool {
        self.copied.is_some() || self.mapping.is_some()
    }

    /// Copies `source` (as many bytes as the reading buffer holds) out at the end of `encoder`'s
    /// work, tagged `tag`.
    pub fn copy(&mut self, encoder: &mut wgpu::CommandEncoder, source: &wgpu::Buffer, tag: T) {
        encoder.copy_buffer_to_buffer(source, 0, &self.read, 0, self.read.size());
        self.copied = Some(tag);
    }

    /// The words of the last reading and its tag, once the GPU has them; never waits (with
    /// `wait`, waits for the one submitted last). A failed mapping reads as nothing.
    pub fn poll(&mut self, device: &wgpu::Device, wait: bool) -> Option<(Vec<u32>, T)> {
        if self.mapping.is_none()
            && let Some(tag) = self.copied.take()
        {
            let (tx, rx) = std::sync::mpsc::channel();
            self.read.map_async(wgpu::MapMode::Read, .., move |r| {
                let _ = tx.send(r);
            });
            self.mapping = Some((rx, tag));
        }
        // A wait that fails leaves the mapping to a later poll.
        if wait {
            let _ = super::wait::wait_for(device);
        } else {
            let _ = device.poll(wgpu::PollType::Poll);
        }
        let (rx, _) = self.mapping.as_ref()?;
        match rx.try_recv() {
            Err(TryRecvError::Empty) => None,
            done => {
                let (_, tag) = self.mapping.take()?;
                done.ok()?.ok()?;
                let words: Vec<u32> = {
                    let mapped = self.read.get_mapped_range(..).ok()?;
                    bytemuck::cast_slice(&mapped[..]).to_vec()
                };
                self.read.unmap();
                Some((words, tag))
            }
        }
    }
}
