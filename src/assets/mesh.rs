//! Triangle meshes in CPU memory and the library that owns them.

use crate::shadow::Aabb;
use bevy_ecs::prelude::*;
use glam::Vec3;
use std::sync::Arc;

/// One vertex as the GPU reads it.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    /// Object-space position.
    pub position: [f32; 3],
    /// Object-space unit normal.
    pub normal: [f32; 3],
    /// Texture coordinates of the material's base-colour texture.
    pub uv: [f32; 2],
    /// Linear RGBA vertex colour (white where the mesh has none).
    pub color: [f32; 4],
}

impl Vertex {
    /// A white vertex at `position` with `normal` and no texture coordinates.
    #[must_use]
    pub fn new(position: [f32; 3], normal: [f32; 3]) -> Vertex {
        Vertex { position, normal, uv: [0.0; 2], color: [1.0; 4] }
    }
}

/// Which joints move a vertex of a skinned mesh, and how much (a second vertex stream).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SkinVertex {
    /// Up to four joints, as indices into the skin's joint list.
    pub joints: [u16; 4],
    /// Their weights: non-negative, summing to 1.
    pub weights: [f32; 4],
}

/// An indexed triangle list with its object-space bounds.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshData {
    /// Vertices (for a skinned mesh, in the bind pose).
    pub vertices: Vec<Vertex>,
    /// Three indices per triangle.
    pub indices: Vec<u32>,
    /// Object-space bounds of the vertices.
    pub bounds: Aabb,
    /// Joint influences, one per vertex, for a skinned mesh.
    pub skin: Option<Vec<SkinVertex>>,
}

impl MeshData {
    /// A rigid mesh from vertices and indices, computing its bounds.
    pub fn new(vertices: Vec<Vertex>, indices: Vec<u32>) -> Self {
        let bounds = Aabb::from_points(vertices.iter().map(|v| Vec3::from(v.position)));
        MeshData { vertices, indices, bounds, skin: None }
    }

    /// A skinned mesh: `skin` holds one entry per vertex.
    pub fn skinned(vertices: Vec<Vertex>, indices: Vec<u32>, skin: Vec<SkinVertex>) -> Self {
        debug_assert_eq!(vertices.len(), skin.len());
        MeshData { skin: Some(skin), ..MeshData::new(vertices, indices) }
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }
}

/// All meshes of the scene; a [`crate::components::Mesh`] is an index into it.
#[derive(Resource, Default, Debug)]
pub struct MeshLibrary {
    meshes: Vec<Arc<MeshData>>,
}

impl MeshLibrary {
    /// Adds a mesh and returns the component that refers to it.
    pub fn add(&mut self, mesh: MeshData) -> crate::components::Mesh {
        self.add_shared(Arc::new(mesh))
    }

    /// Adds a mesh that may be shared with others (a model's instanced parts).
    pub fn add_shared(&mut self, mesh: Arc<MeshData>) -> crate::components::Mesh {
        self.meshes.push(mesh);
        crate::components::Mesh(self.meshes.len() - 1)
    }

    /// The mesh a component refers to, if it exists.
    pub fn get(&self, mesh: crate::components::Mesh) -> Option<&Arc<MeshData>> {
        self.meshes.get(mesh.0)
    }

    /// All meshes in index order.
    pub fn all(&self) -> &[Arc<MeshData>] {
        &self.meshes
    }
}

/// A box centred on the origin with the given half extents and flat face normals.
pub fn cube(half: Vec3) -> MeshData {
    let mut vertices = Vec::with_capacity(24);
    let mut indices = Vec::with_capacity(36);
    for axis in 0..3 {
        for sign in [1.0f32, -1.0] {
            let n = Vec3::from_array(std::array::from_fn(|i| if i == axis { sign } else { 0.0 }));
            // Two tangents chosen so (u, v, n) is right-handed: triangles wind counter-clockwise.
            let u = Vec3::from_array(std::array::from_fn(|i| if i == (axis + 1) % 3 { 1.0 } else { 0.0 }));
            let v = n.cross(u);
            let base = vertices.len() as u32;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let p = (n + u * a + v * b) * half;
                vertices.push(Vertex::new(p.to_array(), n.to_array()));
            }
            indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        }
    }
    MeshData::new(vertices, indices)
}

/// A square in the XZ plane, `size` metres on a side, facing +Y.
pub fn plane(size: f32) -> MeshData {
    let h = size * 0.5;
    let n = [0.0, 1.0, 0.0];
    let vertices = [(-h, h), (h, h), (h, -h), (-h, -h)].map(|(x, z)| Vertex::new([x, 0.0, z], n)).to_vec();
    MeshData::new(vertices, vec![0, 1, 2, 0, 2, 3])
}

/// A sphere of `radius` around the origin, smooth-shaded: `rings` bands from pole to pole and
/// twice as many segments around.
pub fn sphere(radius: f32, rings: u32) -> MeshData {
    let rings = rings.max(2);
    let segments = rings * 2;
    let mut vertices = Vec::with_capacity(((rings + 1) * (segments + 1)) as usize);
    for r in 0..=rings {
        let phi = r as f32 / rings as f32 * std::f32::consts::PI;
        for k in 0..=segments {
            let theta = k as f32 / segments as f32 * std::f32::consts::TAU;
            let n = Vec3::new(phi.sin() * theta.cos(), phi.cos(), phi.sin() * theta.sin());
            let mut v = Vertex::new((n * radius).to_array(), n.to_array());
            v.uv = [k as f32 / segments as f32, r as f32 / rings as f32];
            vertices.push(v);
        }
    }
    let row = segments + 1;
    let mut indices = Vec::with_capacity((rings * segments * 6) as usize);
    for r in 0..rings {
        for k in 0..segments {
            let (a, b) = (r * row + k, (r + 1) * row + k);
            // Counter-clockwise seen from outside; the poles' degenerate triangles are left out.
            if r > 0 {
                indices.extend([a, a + 1, b]);
            }
            if r + 1 < rings {
                indices.extend([a + 1, b + 1, b]);
            }
        }
    }
    MeshData::new(vertices, indices)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every triangle must wind counter-clockwise seen from outside (its normal's side).
    fn assert_outward(mesh: &MeshData) {
        for t in mesh.indices.chunks(3) {
            let [a, b, c] = [0, 1, 2].map(|i| mesh.vertices[t[i] as usize]);
            let (pa, pb, pc) = (Vec3::from(a.position), Vec3::from(b.position), Vec3::from(c.position));
            let face = (pb - pa).cross(pc - pa);
            assert!(face.dot(Vec3::from(a.normal)) > 0.0, "triangle {t:?} winds inwards");
        }
    }

    #[test]
    fn cube_is_closed_outward_and_bounded() {
        let c = cube(Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(c.triangle_count(), 12);
        assert_outward(&c);
        assert_eq!(c.bounds, Aabb::new(Vec3::new(-1.0, -2.0, -3.0), Vec3::new(1.0, 2.0, 3.0)));
    }

    #[test]
    fn sphere_is_round_and_faces_out() {
        let s = sphere(0.8, 12);
        assert_outward(&s);
        for v in &s.vertices {
            assert!((Vec3::from(v.position).length() - 0.8).abs() < 1e-5);
        }
        assert!((s.bounds.max - Vec3::splat(0.8)).abs().max_element() < 1e-5);
        assert_eq!(s.triangle_count(), 12 * 24 * 2 - 2 * 24, "no triangles of zero area at the poles");
    }

    #[test]
    fn plane_faces_up() {
        let p = plane(4.0);
        assert_outward(&p);
        assert_eq!(p.bounds.max.x, 2.0);
    }
}
