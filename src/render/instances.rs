//! Instanced drawing in the shadow pass: a depth-only layer's opaque rigid casters that share a
//! mesh (and pipeline) are drawn in one call, each instance's placement read from a buffer of
//! matrices, so ten thousand cubes in a cascade are one draw, not ten thousand.
//!
//! Only depth-only layers are batched: there the depth test keeps the nearest fragment whatever
//! the order, so the map is the same bit for bit. A layer with a colour map keeps the last of
//! equally near fragments, and keeps its casters' order by drawing them one by one. Skinned and
//! cut-out casters read their own joints, texture and cutoff, and are drawn one by one too.

use super::frame::DrawItem;
use super::mesh::{AlphaClass, Batch, Variant};
use glam::Mat4;

/// A layer's casters: those drawn one by one (in the order given) and the batches.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LayerCalls {
    /// Casters drawn one call each, with their variant.
    pub singles: Vec<(usize, Variant)>,
    /// Casters drawn as instances.
    pub batches: Vec<Batch>,
}

impl LayerCalls {
    /// Draw calls this layer takes.
    #[must_use]
    pub fn calls(&self) -> usize {
        self.singles.len() + self.batches.len()
    }
}

/// Sorts `casters` of `items` into calls. With `instancing`, rigid opaque ones are grouped by
/// mesh and variant (in the order each group first appears), their placements appended to
/// `placements`; the rest, or all of them without `instancing`, are drawn one by one.
#[must_use]
pub fn layer_calls(
    items: &[DrawItem],
    casters: &[usize],
    variant: impl Fn(&DrawItem) -> Variant,
    instancing: bool,
    placements: &mut Vec<Mat4>,
) -> LayerCalls {
    let mut calls = LayerCalls::default();
    let mut groups: Vec<((usize, Variant), Vec<Mat4>)> = Vec::new();
    for &i in casters {
        let Some(item) = items.get(i) else { continue };
        let v = variant(item);
        if !(instancing && !v.skinned && v.alpha == AlphaClass::Opaque) {
            calls.singles.push((i, v));
            continue;
        }
        let key = (item.mesh.0, Variant { instanced: true, ..v });
        match groups.iter_mut().find(|(k, _)| *k == key) {
            Some((_, group)) => group.push(item.object.world_from_local),
            None => groups.push((key, vec![item.object.world_from_local])),
        }
    }
    for ((mesh, variant), group) in groups {
        let first = placements.len() as u32;
        placements.extend(group);
        calls.batches.push(Batch { variant, mesh, instances: first..placements.len() as u32 });
    }
    calls
}

/// The placements of every batch of a frame, in one vertex buffer (step mode instance).
pub struct InstanceBuffer {
    buffer: wgpu::Buffer,
    capacity: usize,
}

impl InstanceBuffer {
    /// An empty buffer with room for a few placements.
    pub fn new(device: &wgpu::Device) -> Self {
        InstanceBuffer { buffer: Self::allocate(device, 64), capacity: 64 }
    }

    fn allocate(device: &wgpu::Device, capacity: usize) -> wgpu::Buffer {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("instances"),
            size: (capacity * size_of::<Mat4>()) as u64,
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    /// Uploads `placements`, growing the buffer when they do not fit.
    pub fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, placements: &[Mat4]) {
        if placements.len() > self.capacity {
            self.capacity = placements.len().next_power_of_two();
            self.buffer = Self::allocate(device, self.capacity);
        }
        if !placements.is_empty() {
            queue.write_buffer(&self.buffer, 0, bytemuck::cast_slice(placements));
        }
    }

    /// The buffer the batches read.
    pub fn buffer(&self) -> &wgpu::Buffer {
        &self.buffer
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::{AlphaMode, Mesh};
    use crate::render::gpu_types::Object;
    use bytemuck::Zeroable;

    fn item(mesh: usize, x: f32, skinned: bool, alpha: AlphaMode) -> DrawItem {
        let object = Object { world_from_local: Mat4::from_translation(glam::Vec3::X * x), ..Object::zeroed() };
        DrawItem {
            mesh: Mesh(mesh),
            object,
            caster: true,
            skinned,
            texture: None,
            alpha,
            double_sided: false,
            at_rest: false,
        }
    }

    fn variant(item: &DrawItem) -> Variant {
        let alpha = if item.alpha == AlphaMode::Opaque { AlphaClass::Opaque } else { AlphaClass::Mask };
        Variant { skinned: item.skinned, cull: None, alpha, textured: false, methods: 0, instanced: false }
    }

    #[test]
    fn rigid_opaque_casters_sharing_a_mesh_become_one_call_and_the_rest_keep_their_order() {
        let mask = AlphaMode::Mask { cutoff: 0.5 };
        let items = [
            item(0, 0.0, false, AlphaMode::Opaque),
            item(1, 1.0, true, AlphaMode::Opaque),
            item(0, 2.0, false, AlphaMode::Opaque),
            item(2, 3.0, false, mask),
            item(3, 4.0, false, AlphaMode::Opaque),
            item(0, 5.0, false, AlphaMode::Opaque),
        ];
        let mut placements = vec![Mat4::IDENTITY];
        let calls = layer_calls(&items, &[0, 1, 2, 3, 4, 5, 99], variant, true, &mut placements);
        assert_eq!(calls.singles.iter().map(|s| s.0).collect::<Vec<_>>(), vec![1, 3], "skinned and cut-out");
        assert_eq!(calls.batches.len(), 2);
        assert_eq!((calls.batches[0].mesh, calls.batches[0].instances.clone()), (0, 1..4));
        assert_eq!((calls.batches[1].mesh, calls.batches[1].instances.clone()), (3, 4..5));
        assert!(calls.batches.iter().all(|b| b.variant.instanced && !b.variant.skinned));
        let xs: Vec<f32> = placements[1..].iter().map(|m| m.w_axis.x).collect();
        assert_eq!(xs, vec![0.0, 2.0, 5.0, 4.0], "each batch's placements in caster order");
        assert_eq!(calls.calls(), 4);

        let mut none = Vec::new();
        let one_by_one = layer_calls(&items, &[0, 1, 2, 3, 4, 5], variant, false, &mut none);
        assert_eq!(one_by_one.singles.iter().map(|s| s.0).collect::<Vec<_>>(), vec![0, 1, 2, 3, 4, 5]);
        assert!(one_by_one.batches.is_empty() && none.is_empty());
    }

    #[test]
    fn casters_of_one_mesh_with_different_pipelines_are_batched_apart() {
        let items = [item(0, 0.0, false, AlphaMode::Opaque), item(0, 1.0, false, AlphaMode::Opaque)];
        let culled = |i: &DrawItem| Variant {
            cull: (i.object.world_from_local.w_axis.x > 0.5).then_some(wgpu::Face::Front),
            ..variant(i)
        };
        let calls = layer_calls(&items, &[0, 1], culled, true, &mut Vec::new());
        assert_eq!(calls.batches.len(), 2);
        assert!(layer_calls(&items, &[], variant, true, &mut Vec::new()).calls() == 0);
    }
}
