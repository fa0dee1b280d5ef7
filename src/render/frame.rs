//! The frame as the passes read it: what extraction ([`super::extract`]) makes of the world, one
//! struct per thing drawn (objects, shadow-map layers, lights, planar shadows), before any GPU
//! work. Every pass reads these; none of them reads the world.

use super::gpu_types::{Frame, GpuLayer, GpuLight, GpuPlanar, Object};
use crate::components::*;
use crate::light::clusters::LightGrid;
use crate::light::{Kind, Light, LightLabel};
use crate::shadow::Tile;
use bytemuck::Zeroable;
use glam::Mat4;

/// A layer's name across frames: its light's entity and its place among the light's layers.
pub type LayerKey = (u64, u32);

/// Most lights that draw planar shadows: the stencil that keeps each from darkening a pixel twice
/// counts them in 8 bits (0 is no light).
pub const MAX_PLANAR: usize = 255;

/// One mesh entity to draw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawItem {
    /// Which mesh of the library.
    pub mesh: Mesh,
    /// Its uniform data.
    pub object: Object,
    /// Drawn into shadow maps.
    pub caster: bool,
    /// Deformed by joint matrices from [`FrameData::joints`].
    pub skinned: bool,
    /// Its material's base-colour texture.
    pub texture: Option<Texture>,
    /// How its material uses alpha.
    pub alpha: AlphaMode,
    /// Drawn from both sides.
    pub double_sided: bool,
    /// A caster at rest ([`crate::systems::CastersAtRest`]): drawn into the static part of the
    /// maps it meets.
    pub at_rest: bool,
}

/// One shadow-map layer to keep or draw, with the casters inside its volume.
#[derive(Clone, Debug, PartialEq)]
pub struct LayerDraw {
    /// The light it belongs to.
    pub light: LightLabel,
    /// Its name across frames (its light's entity and its place among the light's layers).
    pub key: LayerKey,
    /// Its index in [`FrameData::layers`].
    pub slot: u32,
    /// Texels along its side.
    pub resolution: u32,
    /// Its tile of the atlas, once the renderer has placed it (none: it is not drawn).
    pub tile: Option<Tile>,
    /// Its tile is new to it this frame: what the tile holds is another layer's, or nothing.
    pub fresh: bool,
    /// How much its light shows on screen (see [`crate::components::ShadowMap::shows`]).
    pub shows: f32,
    /// World to the layer's clip space.
    pub clip_from_world: Mat4,
    /// Version of its contents (see [`ShadowLayer::version`]).
    pub version: u64,
    /// Version of what its casters at rest draw (see [`ShadowLayer::static_version`]).
    pub static_version: u64,
    /// How its light's shadow is sampled (a moment method needs a moment map too).
    pub method: ShadowMethod,
    /// Indices into [`FrameData::items`] of the casters whose bounds meet the layer's volume.
    pub casters: Vec<usize>,
    /// The page of a virtual map it is, if it is one.
    pub page: Option<crate::shadow::PageId>,
}

/// Everything one frame needs from the world.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameData {
    /// The main pass's frame uniform.
    pub frame: Frame,
    /// Every light, in [`crate::light::light_list`] order, with the slots its layers take.
    pub lights: Vec<FrameLight>,
    /// Every shadow-map layer, by slot.
    pub layers: Vec<GpuLayer>,
    /// Objects in draw order.
    pub items: Vec<DrawItem>,
    /// The layers with their casters, by slot.
    pub draws: Vec<LayerDraw>,
    /// World to the camera's clip space.
    pub clip_from_world: Mat4,
    /// The joint matrices of every skinned object, one after another.
    pub joints: Vec<Mat4>,
    /// The order the main pass draws [`FrameData::items`] in: opaque and masked objects front to
    /// back, then the blended ones from the farthest to the nearest.
    pub draw_order: Vec<usize>,
    /// The shadow methods the lights use, a bit (1 << method) each.
    pub methods: u32,
    /// The planar shadows to draw over the ground, one per light that has them.
    pub planar: Vec<PlanarDraw>,
    /// Each cluster of the camera's view and the lights it lists (empty for a frame of shadow
    /// maps alone).
    pub grid: LightGrid,
    /// The shadowed lights that are lit without their shadow this frame, each with why.
    pub shadowless: Vec<(LightLabel, Shadowless)>,
    /// The paged lights' page tables, one after another (written once the layers have tiles:
    /// [`super::page_table::write_page_tables`]).
    pub page_words: Vec<u32>,
}

/// One light of a frame: the light, and where its layers are in the shadow-map array.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameLight {
    /// The light.
    pub light: Light,
    /// Its first layer's slot.
    pub first_layer: u32,
    /// Its layers in the array (0: it is lit without a shadow).
    pub layer_count: u32,
    /// It draws planar shadows onto the ground in place of its maps there.
    pub planar_ground: bool,
    /// Where its page table starts in [`FrameData::page_words`] (a paged light's; see
    /// [`super::page_table`]).
    pub page_word: u32,
    /// How near to it its coarse map's casters come, along its axis (see
    /// [`GpuLight::nearest_caster`]); 0 where it is not measured.
    pub nearest_caster: f32,
}

impl FrameLight {
    /// The light as the shaders read it: what every kind has, then what its kind packs.
    #[must_use]
    pub fn gpu(&self) -> GpuLight {
        let light = &self.light;
        let mut g = GpuLight {
            color: light.color.to_array(),
            first_layer: self.first_layer,
            layer_count: self.layer_count,
            cookie: light.cookie.map_or(-1, |c| c.layer() as i32),
            bias_constant: light.bias.constant,
            bias_slope: light.bias.slope,
            bias_normal: light.bias.normal,
            bias_scale: light.bias.scale,
            receiver_plane: light.bias.receiver_plane as u32,
            method: light.method as u32,
            shape: light.shape.gpu_id(),
            size: light.size(),
            planar_ground: self.planar_ground as u32,
            contact: (light.shadowed && light.contact) as u32,
            ..GpuLight::zeroed()
        };
        let kind = light.kind.gpu();
        (g.kind, g.position, g.range) = (kind.code, kind.position.to_array(), kind.range);
        (g.direction, g.cos_outer, g.cos_inner) = (kind.direction.to_array(), kind.cos_outer, kind.cos_inner);
        g.cookie_from_world = kind.cookie_from_world.unwrap_or(Mat4::ZERO);
        if let Some(pages) = &light.pages {
            g.page_from_world = pages.space.page_from_world();
            (g.page_levels, g.page_word) = (pages.space.levels(), self.page_word);
            (g.page_finest_log2, g.page_bias) = (pages.space.finest_log2(), pages.bias);
            g.page_fades = pages.space.fades() as u32;
            g.page_faces = pages.space.faces() as u32;
            g.nearest_caster = self.nearest_caster;
        }
        g
    }
}

/// One light's planar shadow: its uniform and the casters flattened onto the ground.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanarDraw {
    /// What the shaders read.
    pub uniform: GpuPlanar,
    /// Indices into [`FrameData::items`] of the casters above the ground.
    pub casters: Vec<usize>,
}

/// Why a shadowed light is lit without its shadow in a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Shadowless {
    /// The shadow atlas had no room left for its layers.
    AtlasFull,
    /// The stencil that planar shadows count their lights in has no number left for it.
    StencilFull,
}

impl std::fmt::Display for Shadowless {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Shadowless::AtlasFull => write!(f, "the shadow atlas has no room left for them (see --shadow-memory)"),
            Shadowless::StencilFull => write!(f, "planar shadows count their lights in 8 bits, {MAX_PLANAR} at most"),
        }
    }
}

/// Shortest distance over which the sun's shadow fades to nothing at the shadow distance, as a
/// fraction of that distance.
pub const SHADOW_FADE: f32 = 0.1;

impl FrameData {
    /// The lights as the shaders read them.
    #[must_use]
    pub fn gpu_lights(&self) -> Vec<GpuLight> {
        self.lights.iter().map(FrameLight::gpu).collect()
    }

    /// The lights' names, in light order.
    #[must_use]
    pub fn labels(&self) -> Vec<LightLabel> {
        self.lights.iter().map(|l| l.light.label).collect()
    }

    /// Tells the probe shader the size of the grid of pixels its probes are drawn into.
    pub fn set_probe_grid(&mut self, width: u32, height: u32) {
        (self.frame.probe_width, self.frame.probe_height) = (width, height);
        // A probe is a point, not a pixel of the camera's picture: no march.
        self.frame.contact_steps = 0;
    }

    /// Makes the measuring view report lights `first` to `first + MEASURED_PER_PASS - 1`.
    pub fn measure_from(&mut self, first: usize) {
        self.frame.first_measured = first as u32;
    }
}
