//! What the scene is built from: procedural meshes, spot-light cookies, and glTF models with
//! their skins and animation clips.

pub mod character;
pub mod clip;
mod cookie;
mod decode;
mod gltf;
mod mesh;
pub mod model;
pub mod skin;
mod texture;

pub use cookie::{COOKIE_SIZE, WINDOW_BAR, cookie_image};
pub use gltf::{MAX_DECODED_BYTES, MAX_INPUT_BYTES, MAX_OBJECTS, MAX_PARTS, ModelError, load_model, parse_model};
pub use mesh::{MeshData, MeshLibrary, SkinVertex, Vertex, cube, plane, sphere};
pub use model::{Model, ModelInstance};
pub use texture::{
    DecodeError, Filter, ImageData, MAX_KEPT_SIZE, MAX_TEXTURE_SIZE, Sampling, TextureData, TextureLibrary,
    UvTransform, Wrap, decode_image, mipmapped_bytes,
};
