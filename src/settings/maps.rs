//! The maps' settings: the shadow memory and how it is spent, and how each map is drawn, kept
//! and made.

use super::{MomentBits, MomentResolve, MomentSource, SettingsError, SettingsGroup, bad};
use bevy_ecs::prelude::*;

/// How shadow maps are sized, drawn, kept and made.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct MapSettings {
    /// Width and height of a sun cascade's layer in texels, and the largest any other light's
    /// layers get (their tiles are sized by what they show; see [`crate::systems::size_shadow_maps`]).
    pub shadow_map_size: u32,
    /// Shadow memory in MiB: the atlas every light's layers take tiles of (depth, its static copy
    /// and any colour map together) holds no more.
    pub shadow_memory: u32,
    /// How big each light's shadow tiles are (umbra's by screen coverage, or fixed as in the
    /// bench's baselines).
    pub tile_sizes: TileSizes,
    /// Octaves what a light shows must move from its tile's size class before the class changes
    /// (the defence against tiles resized to and fro; see the tile-resize case).
    pub tile_hysteresis: f32,
    /// Lookups keep every filter's taps inside their own tile of the atlas, and virtual pages are
    /// drawn with a border as wide as a filter reaches (the guard against atlas and page seams);
    /// off only to show what reading a neighbour's texels does.
    pub atlas_guard: bool,
    /// Texels of shadow tiles redrawn per frame at most (0: no limit). Layers whose light or
    /// casters moved wait their turn by priority, sampled meanwhile as they were last drawn; a
    /// tile new to its layer holds nothing yet and is drawn whatever the budget (see
    /// [`crate::shadow::plan_updates`]).
    pub shadow_updates: u32,
    /// Frames an out-of-date layer may wait under the update budget before it goes ahead of
    /// every layer that shows more (the defence against a starved light; see the
    /// starved-budget case).
    pub max_stale: u32,
    /// Keep a light's shadow maps until it is dirty (true), or draw every map every frame.
    pub reuse_shadow_maps: bool,
    /// In a depth-only layer, the opaque rigid casters that share a mesh are drawn in one
    /// instanced call (false: one call per caster, as skinned and cut-out casters always are).
    pub instancing: bool,
    /// With the cache, a depth-only layer keeps the casters at rest in a static map of their
    /// own and, when only others moved, is drawn again from a copy of it (where the device can
    /// read depth textures: not on GL, which draws every caster). Off by default: in the atlas
    /// a copy is put back by a triangle over the tile that writes depth, which on a software
    /// rasterizer costs more than drawing the casters at rest again, and the static copies take
    /// half the shadow memory (see docs/book/5-performance.md).
    pub static_cache: bool,
    /// The depth maps' format.
    pub shadow_depth: ShadowDepth,
    /// Which casters are drawn into a shadow map and fitted into its depth range.
    pub caster_culling: CasterCulling,
    /// Which faces of the casters are drawn into shadow maps.
    pub shadow_faces: ShadowFaces,
    /// Widest spot cone (half angle, radians) one perspective map shadows; a wider spot is
    /// shadowed through a cube.
    pub spot_map_limit: f32,
    /// Handle the seams of shadow cubes: pick the face a lookup reads for the biased point, and
    /// let each face reach [`CUBE_MARGIN`] texels past its 90° edge for the filters (off shows
    /// the seams).
    pub cube_seams: bool,
    /// How moment maps are made: resolved from the depth map (at its size, or a half or a
    /// quarter of it), or drawn as colour targets of their own.
    pub moments_from: MomentSource,
    /// How moments resolved from depth are made: by one compute dispatch that resolves and
    /// blurs in shared memory, or by full-screen passes (auto: each where it is faster).
    pub moment_resolve: MomentResolve,
    /// Float bits per moment: each method's own choice (auto), 16 or 32.
    pub moment_bits: MomentBits,
    /// Radius in texels of the Gaussian blur a moment map gets after it is made (0: none).
    pub moment_blur: u32,
    /// Samples per texel of a moment map resolved from depth: 1, or 2, 4 or 8 for a depth map
    /// drawn multisampled at the moment map's size, each moment texel the mean of its samples'
    /// moments (an MSAA resolve; the device may allow fewer: 4 everywhere but GL, where none).
    pub moment_samples: u32,
    /// How the sun's shadow is laid out: cascades, or a virtual map in pages where the visible
    /// pixels need them (depth methods only; a moment or colour method stays on cascades).
    pub sun_maps: SunMaps,
    /// How spot and point lights' shadows are laid out: tiles of the atlas, or virtual maps in
    /// pages where the visible pixels need them (depth methods only).
    pub light_maps: LightMaps,
    /// Octaves coarser (negative: finer) than its footprint a pixel's virtual page is chosen.
    pub page_bias: f32,
    /// MiB of the shadow memory the pages of every paged light take together (the pool they share),
    /// at most half of it.
    pub page_memory: u32,
    /// A pixel whose virtual page is not resident reads a coarser level's, or the coarse map
    /// (the guard of the camera-cut and pool-too-small cases); off only to show what a missing
    /// page does (it reads as lit).
    pub page_fallback: bool,
    /// A caster that moved makes the maps over its box before it moved stale as well as those
    /// over its box after (the guard of the moving-caster case); off only to show an old shadow
    /// left behind in the pages it moved out of.
    pub old_bounds: bool,
}

impl Default for MapSettings {
    fn default() -> Self {
        MapSettings {
            shadow_map_size: 2048,
            // Holds the sample scene's four 2048² cascades, its two spots at 2048² and its
            // lantern's cube at 1024² a face, twice over (with static copies, or a colour map); and
            // 64 shadowed lamps beside them.
            shadow_memory: 256,
            tile_sizes: TileSizes::Screen,
            tile_hysteresis: crate::shadow::HYSTERESIS,
            atlas_guard: true,
            shadow_updates: 0,
            max_stale: crate::shadow::MAX_STALE,
            reuse_shadow_maps: true,
            instancing: true,
            static_cache: false,
            shadow_depth: ShadowDepth::Float32,
            caster_culling: CasterCulling::LightVolume,
            shadow_faces: ShadowFaces::Both,
            spot_map_limit: crate::shadow::MAX_MAP_HALF_ANGLE,
            cube_seams: true,
            moments_from: MomentSource::Depth,
            moment_resolve: MomentResolve::Auto,
            moment_bits: MomentBits::Auto,
            moment_blur: DEFAULT_MOMENT_BLUR,
            moment_samples: 1,
            sun_maps: SunMaps::Cascades,
            light_maps: LightMaps::Atlas,
            // Two texels across each pixel's footprint: at one, a bilinear lookup puts an edge up
            // to half a pixel off and the texel-sized bias moves it as far again (on the sample
            // view at 1280x720: 0.083 % of the sun's pixels wrong at 0, 0.040 % at -1 in 27 MiB of
            // pages, 0.022 % at -2 in 57 MiB; four 2048² cascades 0.072 % in 64 MiB).
            page_bias: -1.0,
            // A 1280x720 view's pages, with room for the pages about it as the camera turns.
            page_memory: 32,
            page_fallback: true,
            old_bounds: true,
        }
    }
}

/// Largest shadow-map layer accepted (the device may allow less; the renderer checks again).
pub const MAX_SHADOW_MAP_SIZE: u32 = 8192;
/// Least shadow memory, in MiB: an atlas of 16 MiB still holds hundreds of small tiles.
pub const MIN_SHADOW_MEMORY: u32 = 16;
/// Most shadow memory, in MiB.
pub const MAX_SHADOW_MEMORY: u32 = 16384;
/// The smallest update budget: the smallest tile ([`crate::shadow::MIN_TILE`]²).
pub const MIN_SHADOW_UPDATES: u32 = crate::shadow::MIN_TILE * crate::shadow::MIN_TILE;
/// The longest wait `max_stale` may promise, in frames.
pub const MAX_STALE_FRAMES: u32 = 1000;
/// The widest `tile_hysteresis`, in octaves.
pub const MAX_HYSTERESIS: f32 = 2.0;
/// Texels a cube face reaches past its edge when seams are handled: as far as the widest method
/// samples.
pub const CUBE_MARGIN: u32 = 4;
/// Default blur radius of moment maps, in texels.
pub const DEFAULT_MOMENT_BLUR: u32 = 2;
/// Largest blur radius of moment maps, in texels.
pub const MAX_MOMENT_BLUR: u32 = 16;
/// The samples per texel a moment map may be resolved from.
pub const MOMENT_SAMPLES: [u32; 4] = [1, 2, 4, 8];
/// The widest `page_bias`, in octaves either way.
pub const MAX_PAGE_BIAS: f32 = 4.0;

impl SettingsGroup for MapSettings {
    /// Checks every setting of the maps; the first bad one is named in the error.
    fn validate(&self) -> Result<(), SettingsError> {
        if !(16..=MAX_SHADOW_MAP_SIZE).contains(&self.shadow_map_size) {
            return bad("shadow_map_size", self.shadow_map_size, "must be between 16 and 8192 texels");
        }
        if !(MIN_SHADOW_MEMORY..=MAX_SHADOW_MEMORY).contains(&self.shadow_memory) {
            return bad("shadow_memory", self.shadow_memory, "must be between 16 and 16384 MiB");
        }
        if self.shadow_updates != 0 && self.shadow_updates < MIN_SHADOW_UPDATES {
            return bad(
                "shadow_updates",
                self.shadow_updates,
                "must be 0 (no limit) or at least 1024 texels (a 32² tile)",
            );
        }
        if !(1..=MAX_STALE_FRAMES).contains(&self.max_stale) {
            return bad("max_stale", self.max_stale, "must be between 1 and 1000 frames");
        }
        if !(self.tile_hysteresis.is_finite() && (0.0..=MAX_HYSTERESIS).contains(&self.tile_hysteresis)) {
            return bad("tile_hysteresis", self.tile_hysteresis, "must be between 0 and 2 octaves");
        }
        if !(self.spot_map_limit.is_finite() && (1f32.to_radians()..=89f32.to_radians()).contains(&self.spot_map_limit))
        {
            return bad("spot_map_limit", self.spot_map_limit, "must be an angle between 1° and 89° (in radians)");
        }
        if self.moment_blur > MAX_MOMENT_BLUR {
            return bad("moment_blur", self.moment_blur, "must be between 0 and 16 texels");
        }
        if !MOMENT_SAMPLES.contains(&self.moment_samples) {
            return bad("moment_samples", self.moment_samples, "must be 1, 2, 4 or 8 samples");
        }
        if !(self.page_bias.is_finite() && self.page_bias.abs() <= MAX_PAGE_BIAS) {
            return bad("page_bias", self.page_bias, "must be between -4 and 4 octaves");
        }
        if !(1..=self.shadow_memory / 2).contains(&self.page_memory) {
            return bad("page_memory", self.page_memory, "must be between 1 MiB and half the shadow memory");
        }
        Ok(())
    }
}

/// The format of the depth maps the shadow pass draws.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ShadowDepth {
    /// `Depth32Float`: 24 significant bits wherever the depth lies.
    #[default]
    Float32,
    /// `Depth16Unorm`: 65536 even steps of perspective depth, which crowds them next to the
    /// light; half the memory.
    Unorm16,
}

/// Which casters a shadow map takes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum CasterCulling {
    /// Every caster whose bounds meet the light's (cascade's) volume, the near plane pulled back
    /// to hold them: casters the camera cannot see still shadow what it can.
    #[default]
    LightVolume,
    /// Only casters inside the camera's view, with no pull-back: the common shortcut, here to
    /// show its failure (a tall pillar behind the camera casts no shadow into view).
    CameraView,
}

/// Which faces of the casters the shadow pass draws.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ShadowFaces {
    /// Every face: the map holds the surfaces nearest the light, one-sided surfaces block light
    /// from both sides (as in the truth), and a thick caster's shadow starts right at its foot.
    #[default]
    Both,
    /// Only faces turned away from the light (front faces culled), the classic cure for acne on
    /// lit surfaces: they are not in the map at all. But the map then holds the far side of each
    /// caster, so shadows come loose where a caster meets the ground (peter-panning) and open
    /// surfaces cast nothing.
    Back,
}

/// How big each shadowed light's tiles are (see [`crate::systems::size_shadow_maps`]); the sun's
/// cascades take the map size in every one.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TileSizes {
    /// In proportion to the share of the screen the light's reach covers, with hysteresis.
    #[default]
    Screen,
    /// Every layer at the map size, cube faces too: umbra before its atlas.
    Fixed,
    /// A spot's map at the map size, a point light's cube faces at half of it (Bevy's defaults
    /// at 2048: spots 2048², point lights 1024² a face).
    Bevy,
}

/// How the sun's shadow is laid out.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SunMaps {
    /// Cascades fitted to slices of the view: texels spent by distance from the camera.
    #[default]
    Cascades,
    /// A virtual map: a clipmap of pages round the camera, each drawn once and kept, at the
    /// resolution the visible pixels need (see [`crate::shadow::Clipmap`]).
    Virtual,
}

named_choices!(SunMaps, "a kind of sun maps", Cascades = "cascades", Virtual = "virtual");

/// How spot and point lights' shadows are laid out.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum LightMaps {
    /// A tile of the shadow atlas, sized by what the light shows.
    #[default]
    Atlas,
    /// Virtual maps: a spot's perspective map or a point light's cube in pages, every level over
    /// the whole map, each page drawn once and kept, at the resolution the visible pixels need
    /// (see [`crate::shadow::FrustumPages`] and [`crate::shadow::CubePages`]).
    Virtual,
}

named_choices!(LightMaps, "a kind of light maps", Atlas = "atlas", Virtual = "virtual");

impl MapSettings {
    /// True when some light's shadow may be paged.
    #[must_use]
    pub fn paged(&self) -> bool {
        self.sun_maps == SunMaps::Virtual || self.light_maps == LightMaps::Virtual
    }

    /// The same settings with no light paged: how each light lays out its shadow before its
    /// first virtual map is fitted.
    #[must_use]
    pub fn unpaged(self) -> MapSettings {
        MapSettings { sun_maps: SunMaps::Cascades, light_maps: LightMaps::Atlas, ..self }
    }
}
named_choices!(TileSizes, "a tile-size policy", Screen = "screen", Fixed = "fixed", Bevy = "bevy");
named_choices!(ShadowFaces, "a face choice", Both = "both", Back = "back");
named_choices!(ShadowDepth, "a depth-map format", Float32 = "d32", Unorm16 = "d16");
named_choices!(CasterCulling, "a culling mode", LightVolume = "light", CameraView = "camera");
