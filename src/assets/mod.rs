//! Meshes the scene is built from: procedural shapes now, glTF models later.

mod mesh;

pub use mesh::{MeshData, MeshLibrary, Vertex, cube, plane};
