//! What the scene is built from: procedural meshes, spot-light cookies, and glTF models with
//! their skins and animation clips.

pub mod character;
pub mod clip;
mod cookie;
mod gltf;
mod mesh;
pub mod model;
pub mod skin;

pub use cookie::{COOKIE_SIZE, WINDOW_BAR, cookie_image};
pub use gltf::{ModelError, load_model, parse_model};
pub use mesh::{MeshData, MeshLibrary, SkinVertex, Vertex, cube, plane};
pub use model::Model;
