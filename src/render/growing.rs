//! A GPU buffer that grows when what is written into it does not fit: the lights, their layers,
//! their clustered lists and their planar shadows, however many a scene has.

/// A buffer of some usage that is made anew, twice as large or more, when it must hold more.
pub struct GrowingBuffer {
    label: &'static str,
    usage: wgpu::BufferUsages,
    /// The buffer as it is now (rebind it after a write that made it anew).
    pub buffer: wgpu::Buffer,
}

/// The smallest a buffer is made: a binding must hold something.
const SMALLEST: u64 = 256;

impl GrowingBuffer {
    /// An empty buffer for `usage` (copies into it are added).
    pub fn new(device: &wgpu::Device, label: &'static str, usage: wgpu::BufferUsages) -> Self {
        let usage = usage | wgpu::BufferUsages::COPY_DST;
        GrowingBuffer { label, usage, buffer: Self::make(device, label, usage, SMALLEST) }
    }

    fn make(device: &wgpu::Device, label: &str, usage: wgpu::BufferUsages, size: u64) -> wgpu::Buffer {
        device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size, usage, mapped_at_creation: false })
    }

    /// Makes room for `bytes`; true when the buffer was made anew, so whatever binds it must
    /// bind it again (its old contents are gone).
    pub fn reserve(&mut self, device: &wgpu::Device, bytes: u64) -> bool {
        if bytes <= self.buffer.size() {
            return false;
        }
        let size = bytes.next_power_of_two().max(SMALLEST);
        self.buffer = Self::make(device, self.label, self.usage, size);
        true
    }

    /// Writes `data` from the start, growing first when it does not fit; true when the buffer
    /// was made anew.
    pub fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, data: &[u8]) -> bool {
        let grew = self.reserve(device, data.len() as u64);
        if !data.is_empty() {
            queue.write_buffer(&self.buffer, 0, data);
        }
        grew
    }
}

/// Words kept in an integer texture `width` words wide whose rows grow as the words do: the
/// clustered light lists, the page tables. (A texture, not a storage buffer: on lavapipe a third storage buffer
/// read by the main pass's fragments made every draw allocate about 2.5 MB, so 700 cubes took
/// 2.4 GB and 11 s against 0.6 GB and 3 s.)
pub struct GrowingRows {
    label: &'static str,
    width: u32,
    texture: wgpu::Texture,
    /// A view of the whole texture.
    pub view: wgpu::TextureView,
}

impl GrowingRows {
    /// One row of `width` words.
    pub fn new(device: &wgpu::Device, label: &'static str, width: u32) -> Self {
        let (texture, view) = Self::make(device, label, width, 1);
        GrowingRows { label, width, texture, view }
    }

    fn make(device: &wgpu::Device, label: &str, width: u32, rows: u32) -> (wgpu::Texture, wgpu::TextureView) {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d { width, height: rows, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Uint,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        (texture, view)
    }

    /// Rows `words` need.
    #[must_use]
    pub fn rows_for(&self, words: usize) -> u32 {
        (words as u32).div_ceil(self.width).max(1)
    }

    /// Writes `words` from the first row on, growing the texture (to twice the rows it needs)
    /// when they do not fit; true when it was made anew (then rebind its view).
    pub fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, words: &[u32]) -> bool {
        let rows = self.rows_for(words.len());
        let grew = rows > self.texture.height();
        if grew {
            (self.texture, self.view) = Self::make(device, self.label, self.width, rows.next_power_of_two());
        }
        let mut padded = words.to_vec();
        padded.resize((rows * self.width) as usize, 0);
        queue.write_texture(
            self.texture.as_image_copy(),
            bytemuck::cast_slice(&padded),
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(4 * self.width), rows_per_image: Some(rows) },
            wgpu::Extent3d { width: self.width, height: rows, depth_or_array_layers: 1 },
        );
        grew
    }
}
