//! glTF 2.0 loading (.gltf with external or embedded buffers, and .glb) into a [`Model`].
//!
//! The gltf crate parses and validates the JSON; umbra reads the binary data itself so that every
//! offset, count and index is checked, and a broken file gives an error that names the file and
//! the problem instead of a panic.

mod accessor;
mod build;
mod container;

use super::model::Model;
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

/// Loads a .gltf or .glb file; buffers in other files are looked up next to it.
pub fn load_model(path: &Path) -> Result<Model, ModelError> {
    let fail = |problem: String| ModelError { path: path.display().to_string(), problem };
    let bytes = std::fs::read(path).map_err(|e| fail(format!("cannot read it: {e}")))?;
    parse_model(&bytes, path.parent(), &path.display().to_string())
}

/// Loads a model from the bytes of a .gltf or .glb file named `name`; external buffers are
/// looked up in `dir`.
pub fn parse_model(bytes: &[u8], dir: Option<&Path>, name: &str) -> Result<Model, ModelError> {
    let fail = |problem: String| ModelError { path: name.to_string(), problem };
    let source = container::open(bytes, dir).map_err(fail)?;
    let mut warnings = Vec::new();
    let mut model = build::build(&source, name, &mut warnings).map_err(fail)?;
    warnings.dedup();
    model.warnings = warnings.into_iter().map(|w| format!("{name}: {w}")).collect();
    Ok(model)
}
