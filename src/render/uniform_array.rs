//! An array of equal-sized uniform blocks in one buffer, bound one at a time by dynamic offset.

/// Uniform blocks of one type at a device-aligned stride, with the bind group that reads them.
pub struct UniformArray {
    label: &'static str,
    /// Layout of the bind group: binding 0, a dynamic-offset uniform.
    pub layout: wgpu::BindGroupLayout,
    buffer: wgpu::Buffer,
    /// The bind group over the buffer.
    pub bind_group: wgpu::BindGroup,
    item_size: u64,
    stride: u64,
    capacity: usize,
}

impl UniformArray {
    /// An array of blocks of `item_size` bytes visible to `stages`.
    pub fn new(device: &wgpu::Device, label: &'static str, item_size: u64, stages: wgpu::ShaderStages) -> Self {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: stages,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: true,
                    min_binding_size: wgpu::BufferSize::new(item_size),
                },
                count: None,
            }],
        });
        let align = device.limits().min_uniform_buffer_offset_alignment as u64;
        let stride = item_size.div_ceil(align) * align;
        let (buffer, bind_group) = Self::allocate(device, label, &layout, item_size, stride, 16);
        UniformArray { label, layout, buffer, bind_group, item_size, stride, capacity: 16 }
    }

    fn allocate(
        device: &wgpu::Device,
        label: &str,
        layout: &wgpu::BindGroupLayout,
        item_size: u64,
        stride: u64,
        capacity: usize,
    ) -> (wgpu::Buffer, wgpu::BindGroup) {
        // wgpu clears a new buffer itself: no zeroed copy of it on the CPU to upload (at 100,000
        // objects that copy and its staging took 67 MB of the peak).
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: stride * capacity as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &buffer,
                    offset: 0,
                    size: wgpu::BufferSize::new(item_size),
                }),
            }],
        });
        (buffer, bind_group)
    }

    /// Uploads `items` (each `item_size` bytes), growing the buffer when they do not fit.
    pub fn write<T: bytemuck::Pod>(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, items: &[T]) {
        debug_assert_eq!(std::mem::size_of::<T>() as u64, self.item_size);
        if items.len() > self.capacity {
            let capacity = items.len().next_power_of_two();
            (self.buffer, self.bind_group) =
                Self::allocate(device, self.label, &self.layout, self.item_size, self.stride, capacity);
            self.capacity = capacity;
        }
        let Some(size) = wgpu::BufferSize::new(self.stride * items.len() as u64) else { return };
        // Straight into the staging memory (the padding between blocks is never read): at 20,000
        // objects a 5 MB buffer zeroed and copied once more each frame was most of the upload.
        let Some(mut view) = queue.write_buffer_with(&self.buffer, 0, size) else { return };
        for (i, item) in items.iter().enumerate() {
            let at = i * self.stride as usize;
            view.slice(at..at + self.item_size as usize).copy_from_slice(bytemuck::bytes_of(item));
        }
    }

    /// Dynamic offset of block `i`.
    pub fn offset(&self, i: usize) -> u32 {
        (i as u64 * self.stride) as u32
    }
}
