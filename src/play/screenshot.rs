//! The screenshot key: the window's frame, panel and overlay included, saved as a PNG.

use crate::render::{Gpu, read_picture};
use std::path::{Path, PathBuf};

/// The first `umbra-screenshot-N.png` in `dir` that does not exist yet, so nothing is overwritten.
pub fn free_name(dir: &Path) -> PathBuf {
    (1..)
        .map(|n| dir.join(format!("umbra-screenshot-{n}.png")))
        .find(|p| !p.exists())
        .unwrap_or_else(|| dir.join("umbra-screenshot.png"))
}

/// Where the frame goes when a screenshot is asked for: the window's own frame if it can be
/// copied from (`None`), or else a texture like it (drawn as well, then read back).
pub(super) fn copy_target(gpu: &Gpu, frame: &wgpu::Texture) -> Option<wgpu::Texture> {
    if frame.usage().contains(wgpu::TextureUsages::COPY_SRC) {
        return None;
    }
    gpu.target("screenshot", (frame.width(), frame.height()), frame.format()).ok()
}

/// Saves the picture in `texture` (drawn, not yet presented) into the working directory and says
/// where; a failure is said, not fatal.
pub(super) fn save(gpu: &Gpu, texture: &wgpu::Texture) {
    let path = free_name(Path::new("."));
    match read_picture(gpu, texture).and_then(|image| image.save_png(&path).map(|_| image)) {
        Ok(image) => println!("wrote {} ({}x{})", path.display(), image.width, image.height),
        Err(e) => eprintln!("screenshot failed: {e}"),
    }
}
