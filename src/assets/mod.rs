//! What the scene is built from: procedural meshes and spot-light cookies (glTF models later).

mod cookie;
mod mesh;

pub use cookie::{COOKIE_SIZE, WINDOW_BAR, cookie_image};
pub use mesh::{MeshData, MeshLibrary, Vertex, cube, plane};
