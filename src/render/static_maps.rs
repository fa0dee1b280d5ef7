//! The static part of the shadow maps, after Unity HDRP's mixed cached shadow maps: for each
//! depth-only layer, a depth map of its casters at rest alone ([`crate::systems::CastersAtRest`]),
//! drawn again only when its static version changes. A dirty layer is then made by copying that
//! map and drawing only the moving casters over it.
//!
//! The depth test keeps the nearest fragment whatever the order, so the nearest of the static
//! map and of the moving casters is exactly what drawing them all together gives: the maps are
//! bit-identical to redrawing everything (tested over 300 random frames). Colour-map layers
//! (moments, depth in colour) keep the last of equally near fragments and are blurred after, so
//! they are drawn whole. GL cannot copy depth textures (no `DEPTH_TEXTURE_AND_BUFFER_COPIES`):
//! there every dirty layer draws all of its casters, as without this cache.

use super::texture::LayeredTarget;

/// Static depth maps, slot for slot beside the shadow maps.
pub struct StaticMaps {
    target: LayeredTarget,
    /// Size, layers and format, to tell when the shadow maps changed under them.
    shape: (u32, u32, wgpu::TextureFormat),
    /// The static version each slot's map holds.
    drawn: Vec<Option<u64>>,
}

impl StaticMaps {
    /// Maps of `size`² texels, `layers` layers, `format` depth, holding nothing yet.
    pub fn new(device: &wgpu::Device, size: u32, layers: u32, format: wgpu::TextureFormat) -> Self {
        let target = LayeredTarget::copyable(
            device,
            "static shadow maps",
            format,
            (size, layers),
            wgpu::TextureUsages::COPY_SRC,
        );
        StaticMaps { target, shape: (size, layers, format), drawn: vec![None; layers as usize] }
    }

    /// True when these maps have the shape `(size, layers, format)`.
    pub fn fits(&self, shape: (u32, u32, wgpu::TextureFormat)) -> bool {
        self.shape == shape
    }

    /// True when slot `slot` holds what static version `version` draws.
    pub fn holds(&self, slot: u32, version: u64) -> bool {
        self.drawn.get(slot as usize).copied().flatten() == Some(version)
    }

    /// Records that slot `slot` is being drawn with static version `version`.
    pub fn mark_drawn(&mut self, slot: u32, version: u64) {
        if let Some(d) = self.drawn.get_mut(slot as usize) {
            *d = Some(version);
        }
    }

    /// The render view of slot `slot`.
    pub fn view(&self, slot: u32) -> &wgpu::TextureView {
        &self.target.layer_views[slot as usize]
    }

    /// Copies slot `slot` into the same layer of `maps` (a texture of the same shape).
    pub fn copy_into(&self, encoder: &mut wgpu::CommandEncoder, slot: u32, maps: &wgpu::Texture) {
        let layer = |texture| wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d { x: 0, y: 0, z: slot },
            aspect: wgpu::TextureAspect::All,
        };
        let size = self.shape.0;
        let extent = wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 1 };
        encoder.copy_texture_to_texture(layer(&self.target.texture), layer(maps), extent);
    }
}

/// True when `adapter` can copy depth textures, which the static maps need.
pub fn copies_depth(adapter: &wgpu::Adapter) -> bool {
    adapter.get_downlevel_capabilities().flags.contains(wgpu::DownlevelFlags::DEPTH_TEXTURE_AND_BUFFER_COPIES)
}
