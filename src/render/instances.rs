//! Instanced drawing in the shadow pass: a depth-only layer's opaque rigid casters that share a
//! mesh (and pipeline) are drawn in one call, so ten thousand cubes in a cascade are one draw, not
//! ten thousand. Each instance is the number of its object, whose placement the shader reads from
//! a storage buffer holding every object's once: an object in twelve layers costs 64 bytes and
//! twelve numbers, not twelve matrices (100,000 objects in twelve layers: buffers of 17 MB, not 134).
//!
//! Only depth-only layers are batched: there the depth test keeps the nearest fragment whatever
//! the order, so the map is the same bit for bit. A layer with a colour map keeps the last of
//! equally near fragments, and keeps its casters' order by drawing them one by one. Skinned and
//! cut-out casters read their own joints, texture and cutoff, and are drawn one by one too.

use super::frame::DrawItem;
use super::mesh::{AlphaClass, Batch, JointPalette, Variant};
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
/// mesh and variant (in the order each group first appears), their object numbers appended to
/// `instances`; the rest, or all of them without `instancing`, are drawn one by one.
#[must_use]
pub fn layer_calls(
    items: &[DrawItem],
    casters: &[usize],
    variant: impl Fn(&DrawItem) -> Variant,
    instancing: bool,
    instances: &mut Vec<u32>,
) -> LayerCalls {
    let mut calls = LayerCalls::default();
    let mut groups: Vec<((usize, Variant), Vec<u32>)> = Vec::new();
    for &i in casters {
        let Some(item) = items.get(i) else { continue };
        let v = variant(item);
        if !(instancing && !v.skinned && v.alpha == AlphaClass::Opaque) {
            calls.singles.push((i, v));
            continue;
        }
        let key = (item.mesh.0, Variant { instanced: true, ..v });
        match groups.iter_mut().find(|(k, _)| *k == key) {
            Some((_, group)) => group.push(i as u32),
            None => groups.push((key, vec![i as u32])),
        }
    }
    for ((mesh, variant), group) in groups {
        let first = instances.len() as u32;
        instances.extend(group);
        calls.batches.push(Batch { variant, mesh, instances: first..instances.len() as u32 });
    }
    calls
}

/// The instances of every batch of a frame: their object numbers in one vertex buffer (step mode
/// instance), and every object's placement in a storage buffer laid out as the joint palette is
/// (an instanced draw is rigid, so the group that holds a skinned draw's joints holds them).
pub struct InstanceBuffer {
    buffer: wgpu::Buffer,
    capacity: usize,
    placements: JointPalette,
}

impl InstanceBuffer {
    /// An empty buffer with room for a few instances, its placements bound with `layout` (the
    /// joint palette's).
    pub fn new(device: &wgpu::Device, layout: &wgpu::BindGroupLayout) -> Self {
        let placements = JointPalette::with_layout(device, layout.clone());
        InstanceBuffer { buffer: Self::allocate(device, 64), capacity: 64, placements }
    }

    fn allocate(device: &wgpu::Device, capacity: usize) -> wgpu::Buffer {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("instances"),
            size: (capacity * size_of::<u32>()) as u64,
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    /// Uploads the instances' object numbers and, when there are any, every object's placement
    /// (`items`, by object number), growing the buffers when they do not fit.
    pub fn write(&mut self, (device, queue): (&wgpu::Device, &wgpu::Queue), instances: &[u32], items: &[DrawItem]) {
        if instances.is_empty() {
            return;
        }
        if instances.len() > self.capacity {
            self.capacity = instances.len().next_power_of_two();
            self.buffer = Self::allocate(device, self.capacity);
        }
        queue.write_buffer(&self.buffer, 0, bytemuck::cast_slice(instances));
        let placements: Vec<Mat4> = items.iter().map(|i| i.object.world_from_local).collect();
        self.placements.write(device, queue, &placements);
    }

    /// The object numbers the batches read, and the bind group of every object's placement.
    pub fn bindings(&self) -> (&wgpu::Buffer, &wgpu::BindGroup) {
        (&self.buffer, self.placements.bind_group())
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
        let mut instances = vec![7];
        let calls = layer_calls(&items, &[0, 1, 2, 3, 4, 5, 99], variant, true, &mut instances);
        assert_eq!(calls.singles.iter().map(|s| s.0).collect::<Vec<_>>(), vec![1, 3], "skinned and cut-out");
        assert_eq!(calls.batches.len(), 2);
        assert_eq!((calls.batches[0].mesh, calls.batches[0].instances.clone()), (0, 1..4));
        assert_eq!((calls.batches[1].mesh, calls.batches[1].instances.clone()), (3, 4..5));
        assert!(calls.batches.iter().all(|b| b.variant.instanced && !b.variant.skinned));
        assert_eq!(instances[1..], [0, 2, 5, 4], "each batch's objects in caster order");
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
