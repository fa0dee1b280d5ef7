//! The light volumes drawn as lines over the picture: every shadow layer's clip volume (a sun's
//! cascade boxes, a spot's frustum, a cube's six face frusta), in its light's colour.

use super::frame::FrameData;
use super::shaders::{Composed, LINES};
use crate::light::Kind;
use crate::shadow::frustum_corners;
use glam::Mat4;

/// One end of a line: where it is in the world and its colour.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LineVertex {
    /// World position.
    pub position: [f32; 3],
    /// Linear RGBA.
    pub color: [f32; 4],
}

/// The twelve edges of the clip volume of `clip_from_world` as line ends, in `color`.
#[must_use]
pub fn volume_edges(clip_from_world: &Mat4, color: [f32; 4]) -> Vec<LineVertex> {
    let corners = frustum_corners(clip_from_world);
    if !corners.iter().all(|c| c.is_finite()) {
        return Vec::new();
    }
    // Corner i has x, y and depth in its bits 0, 1, 2: an edge joins corners one bit apart.
    (0..8usize)
        .flat_map(|a| [1, 2, 4].into_iter().filter(move |bit| a & bit == 0).map(move |bit| (a, a | bit)))
        .flat_map(|(a, b)| [a, b])
        .map(|i| LineVertex { position: corners[i].to_array(), color })
        .collect()
}

/// The line ends of every layer of the frame's lights, each in the colour its light's kind gives
/// it.
#[must_use]
pub fn volume_lines(data: &FrameData) -> Vec<LineVertex> {
    data.lights
        .iter()
        .flat_map(|l| {
            // The draws are in slot order, one per layer.
            let first = l.first_layer as usize;
            let layers = data.draws.get(first..first + l.layer_count as usize).unwrap_or(&[]);
            layers.iter().enumerate().flat_map(|(k, d)| volume_edges(&d.clip_from_world, l.light.kind.volume_colour(k)))
        })
        .collect()
}

/// The pipeline that draws lines, and its buffers.
pub struct LinePass {
    pipeline: wgpu::RenderPipeline,
    camera: wgpu::Buffer,
    bind: wgpu::BindGroup,
    vertices: Option<wgpu::Buffer>,
}

impl LinePass {
    /// Lines drawn into targets of `format`.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> LinePass {
        let module = Composed::new(&[LINES]).module(device);
        let camera = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("line camera"),
            size: 64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("line camera"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("line camera"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: camera.as_entire_binding() }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("lines"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x4];
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("lines"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_line"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<LineVertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &attributes,
                })],
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_line"),
                compilation_options: Default::default(),
                targets: &[Some(format.into())],
            }),
            primitive: wgpu::PrimitiveState { topology: wgpu::PrimitiveTopology::LineList, ..Default::default() },
            depth_stencil: None,
            multisample: Default::default(),
            multiview_mask: None,
            cache: None,
        });
        LinePass { pipeline, camera, bind, vertices: None }
    }

    /// Draws `lines` over `target`, seen through `clip_from_world`.
    pub fn encode(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
        clip_from_world: &Mat4,
        lines: &[LineVertex],
    ) {
        if lines.is_empty() {
            return;
        }
        let bytes: &[u8] = bytemuck::cast_slice(lines);
        if self.vertices.as_ref().is_none_or(|b| b.size() < bytes.len() as u64) {
            self.vertices = Some(device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("lines"),
                size: bytes.len().next_power_of_two() as u64,
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }));
        }
        let Some(vertices) = &self.vertices else { return };
        queue.write_buffer(vertices, 0, bytes);
        queue.write_buffer(&self.camera, 0, bytemuck::bytes_of(&clip_from_world.to_cols_array()));
        let mut pass = super::colour_pass(encoder, "light volumes", target, None);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind, &[]);
        pass.set_vertex_buffer(0, vertices.slice(..bytes.len() as u64));
        pass.draw(0..lines.len() as u32, 0..1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn a_volume_has_twelve_edges_along_its_box() {
        let ortho = glam::camera::rh::proj::directx::orthographic(-1.0, 1.0, -2.0, 2.0, 0.5, 3.0);
        let edges = volume_edges(&ortho, [1.0; 4]);
        assert_eq!(edges.len(), 24);
        for pair in edges.chunks_exact(2) {
            let (a, b) = (Vec3::from(pair[0].position), Vec3::from(pair[1].position));
            let along = (b - a).abs();
            // Each edge runs along one axis: two of its coordinates agree.
            assert_eq!(along.cmpgt(Vec3::splat(1e-5)).bitmask().count_ones(), 1, "{a} to {b}");
        }
        assert!(volume_edges(&Mat4::ZERO, [1.0; 4]).is_empty(), "a singular matrix draws nothing");
    }
}
