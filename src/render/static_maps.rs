//! The static part of the shadow maps, after Unity HDRP's mixed cached shadow maps: for each
//! depth-only layer, a depth map of its casters at rest alone ([`crate::systems::CastersAtRest`])
//! in the same tile of a static atlas, drawn again only when its static version changes (or its
//! tile moves). A dirty layer is then made by putting that depth back into its tile (a fill:
//! WebGPU copies depth only in whole textures) and drawing only the moving casters over it.
//!
//! The depth test keeps the nearest fragment whatever the order, so the nearest of the static
//! map and of the moving casters is exactly what drawing them all together gives: the maps are
//! bit-identical to redrawing everything (tested over 300 random frames). Colour-map layers
//! (moments, depth in colour) keep the last of equally near fragments and are blurred after, so
//! they are drawn whole. GL cannot read a depth texture's values (naga writes no `textureLoad`
//! of depth for it, and it has no `DEPTH_TEXTURE_AND_BUFFER_COPIES`): there every dirty layer
//! draws all of its casters, as without this cache.

use super::frame::LayerKey;
use super::texture::LayeredTarget;
use crate::shadow::Tile;
use std::collections::HashMap;

/// The static atlas, page for page beside the shadow atlas.
pub struct StaticMaps {
    /// Its pages.
    pub pages: LayeredTarget,
    /// Page side, pages and format, to tell when the shadow atlas changed under it.
    shape: (u32, u32, wgpu::TextureFormat),
    /// The static version each layer's tile holds, and where that tile is.
    drawn: HashMap<LayerKey, (u64, Tile)>,
}

impl StaticMaps {
    /// `pages` pages of `side`² texels of `format` depth, holding nothing yet.
    pub fn new(device: &wgpu::Device, side: u32, pages: u32, format: wgpu::TextureFormat) -> Self {
        let pages_target = LayeredTarget::new(device, "static shadow atlas", format, side, pages);
        StaticMaps { pages: pages_target, shape: (side, pages, format), drawn: HashMap::new() }
    }

    /// True when these pages have the shape `(side, pages, format)`.
    pub fn fits(&self, shape: (u32, u32, wgpu::TextureFormat)) -> bool {
        self.shape == shape
    }

    /// True when layer `key`'s tile `tile` holds what static version `version` draws.
    pub fn holds(&self, key: LayerKey, tile: Tile, version: u64) -> bool {
        self.drawn.get(&key) == Some(&(version, tile))
    }

    /// Records that layer `key`'s tile `tile` is being drawn with static version `version`.
    pub fn mark_drawn(&mut self, key: LayerKey, tile: Tile, version: u64) {
        self.drawn.insert(key, (version, tile));
    }

    /// Forgets the layers not in `keep` (their tiles may be another's now).
    pub fn forget_others(&mut self, keep: &std::collections::HashSet<LayerKey>) {
        self.drawn.retain(|k, _| keep.contains(k));
    }
}

/// True when `adapter` can read a depth texture's values back, which putting a static map back
/// needs: the backends with depth copies (`DEPTH_TEXTURE_AND_BUFFER_COPIES`), which GL lacks.
pub fn reads_depth(adapter: &wgpu::Adapter) -> bool {
    adapter.get_downlevel_capabilities().flags.contains(wgpu::DownlevelFlags::DEPTH_TEXTURE_AND_BUFFER_COPIES)
}
