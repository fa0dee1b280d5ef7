//! glTF 2.0 loading (.gltf with external or embedded buffers, and .glb) into a [`Model`].
//!
//! The gltf crate parses and validates the JSON; umbra reads the binary data itself so that every
//! offset, count and index is checked, and a broken file gives an error that names the file and
//! the problem instead of a panic.

mod accessor;
mod budget;
mod build;
mod census;
mod container;
mod keys;
mod material;
mod primitive;
mod punctual;

use super::model::Model;
use budget::Budget;
pub use budget::{MAX_DECODED_BYTES, MAX_INPUT_BYTES, MAX_OBJECTS, MAX_PARTS};
use std::path::Path;

/// A model file that could not be loaded, and why.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {problem}")]
pub struct ModelError {
    /// The file.
    pub path: String,
    /// What is wrong with it.
    pub problem: String,
}

/// Loads a .gltf or .glb file; buffers and images in other files are looked up next to it.
/// Only regular files are read, within [`MAX_INPUT_BYTES`] for the model and all it names.
pub fn load_model(path: &Path) -> Result<Model, ModelError> {
    let name = path.display().to_string();
    let input = Budget::input();
    let bytes = budget::read_file(path, "it", &input).map_err(|problem| ModelError { path: name.clone(), problem })?;
    parse_with(&bytes, path.parent(), &name, &input)
}

/// Loads a model from the bytes of a .gltf or .glb file named `name`; external buffers are
/// looked up in `dir`.
pub fn parse_model(bytes: &[u8], dir: Option<&Path>, name: &str) -> Result<Model, ModelError> {
    let input = Budget::input();
    input.spend(bytes.len() as u64).map_err(|problem| ModelError { path: name.to_string(), problem })?;
    parse_with(bytes, dir, name, &input)
}

fn parse_with(bytes: &[u8], dir: Option<&Path>, name: &str, input: &Budget) -> Result<Model, ModelError> {
    let fail = |problem: String| ModelError { path: name.to_string(), problem };
    let source = container::open(bytes, dir, input).map_err(fail)?;
    let mut warnings = Vec::new();
    let mut model = build::build(&source, name, input, &mut warnings).map_err(fail)?;
    warnings.dedup();
    model.warnings = warnings.into_iter().map(|w| format!("{name}: {w}")).collect();
    Ok(model)
}
