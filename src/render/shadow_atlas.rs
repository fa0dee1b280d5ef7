//! The shadow atlas on the GPU: pages of one depth texture array (and of a colour array, tile for
//! tile, where a light's method reads a colour map), and the placing of each frame's layers in
//! tiles of them ([`crate::shadow::Atlas`]), kept from frame to frame while a layer keeps its
//! size. A layer the atlas cannot hold leaves its light lit without a shadow, and said so.

use super::frame::{FrameData, LayerKey, Shadowless};
use super::moments::{ColourLayout, ColourMaps};
use super::texture::LayeredTarget;
use crate::settings::ShadowDepth;
use crate::shadow::{Atlas, AtlasShape, Tile};

/// The texture format of depth maps of `depth`.
pub(super) fn depth_texture(depth: ShadowDepth) -> wgpu::TextureFormat {
    match depth {
        ShadowDepth::Float32 => wgpu::TextureFormat::Depth32Float,
        ShadowDepth::Unorm16 => wgpu::TextureFormat::Depth16Unorm,
    }
}

/// Layers of a texture array holding `pages` pages: at least 2 (GL cannot view a single-layer
/// texture as an array) and never a multiple of 6, which the GL backend takes for a cube map or
/// cube array.
pub(super) fn array_layers(pages: u32) -> u32 {
    let layers = pages.max(2);
    if layers.is_multiple_of(6) { layers + 1 } else { layers }
}

/// The atlas's pages and the views the passes use.
pub struct ShadowMaps {
    /// Its pages' size and number.
    pub shape: AtlasShape,
    /// Their depth format.
    pub depth: ShadowDepth,
    /// The depth pages: one render view each, and the whole array for sampling.
    pub pages: LayeredTarget,
    /// The colour pages, tile for tile (a stand-in when no light uses one).
    pub moments: ColourMaps,
}

impl ShadowMaps {
    /// Pages of `shape` in `depth`, with colour pages of `colour`.
    pub fn new(device: &wgpu::Device, shape: AtlasShape, colour: ColourLayout, depth: ShadowDepth) -> Self {
        let layers = array_layers(shape.pages);
        let pages = LayeredTarget::new(device, "shadow atlas", depth_texture(depth), shape.page, layers);
        let moments = ColourMaps::new(device, colour, shape.page, layers);
        ShadowMaps { shape, depth, pages, moments }
    }
}

/// Where each layer's tile is, kept across frames.
pub struct Placement {
    atlas: Atlas<LayerKey>,
}

impl Placement {
    /// No layer placed yet, in an atlas of `shape`.
    pub fn new(shape: AtlasShape) -> Self {
        Placement { atlas: Atlas::new(shape) }
    }

    /// The shape it places in.
    pub fn shape(&self) -> AtlasShape {
        self.atlas.shape()
    }

    /// Gives every layer of `data` its tile (a layer keeps last frame's while it keeps its size)
    /// and writes where it is into the layer the shaders read. A light any of whose layers find
    /// no room is lit without its shadow: none of its layers keeps a tile (so none is drawn) and
    /// it is named in [`FrameData::shadowless`]; a paged light only when its coarse map finds
    /// none (a page without one is left out of the page table).
    pub fn place(&mut self, data: &mut FrameData) {
        let wanted: Vec<(LayerKey, u32)> = data.draws.iter().map(|d| (d.key, d.resolution)).collect();
        let placed = self.atlas.place(&wanted);
        let page = self.shape().page as f32;
        for ((draw, layer), p) in data.draws.iter_mut().zip(data.layers.iter_mut()).zip(&placed) {
            (draw.tile, draw.fresh) = (p.tile, p.moved);
            if let Some(Tile { page: on, x, y, .. }) = p.tile {
                layer.page = on;
                let side = draw.resolution as f32;
                layer.tile = [x as f32 / page, y as f32 / page, side / page, side];
            }
        }
        for light in data.lights.iter_mut().filter(|l| l.layer_count > 0) {
            // The draws are in slot order, one per layer. A page that found no room is left out of
            // its light's page table (it reads a coarser page); only its coarse map must have one.
            let coarse = light.light.pages.as_ref().map(|p| p.space.faces() as u32);
            let needed = coarse.unwrap_or(light.layer_count);
            let slots = light.first_layer as usize..(light.first_layer + light.layer_count) as usize;
            if data.draws[slots.clone()].iter().take(needed as usize).any(|d| d.tile.is_none()) {
                light.layer_count = 0;
                data.shadowless.push((light.light.label, Shadowless::AtlasFull));
                data.draws[slots].iter_mut().for_each(|d| d.tile = None);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::array_layers;

    #[test]
    fn layer_counts_avoid_what_gl_takes_for_cube_maps() {
        assert_eq!(array_layers(0), 2);
        assert_eq!(array_layers(1), 2);
        assert_eq!(array_layers(5), 5);
        assert_eq!(array_layers(6), 7);
        assert_eq!(array_layers(12), 13);
    }
}
