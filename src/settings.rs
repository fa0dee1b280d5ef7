//! Settings: every knob of the scene and the shadows, checked before use.

use crate::components::ShadowMethod;
use crate::shadow::{FitMode, MAX_CASCADES};
use bevy_ecs::prelude::*;

mod lights;
mod moments;
pub use lights::{LightBiases, LightSetting};
pub use moments::{MomentBits, MomentSource};

/// Everything a user can tune; [`Settings::validate`] rejects nonsense before it reaches the GPU.
#[derive(Resource, Clone, Debug, PartialEq)]
pub struct Settings {
    /// Draw shadows at all.
    pub shadows: bool,
    /// How dark a full shadow is: 0 = no darkening, 1 = only ambient light remains.
    pub shadow_strength: f32,
    /// Width and height of a sun cascade's layer in texels, and the largest any other light's
    /// layers get (their tiles are sized by what they show; see [`crate::systems::size_shadow_maps`]).
    pub shadow_map_size: u32,
    /// Shadow memory in MiB: the atlas every light's layers take tiles of (depth, its static copy
    /// and any colour map together) holds no more.
    pub shadow_memory: u32,
    /// Lookups keep every filter's taps inside their own tile of the atlas (the guard against
    /// atlas seams); off only to show what reading a neighbour's texels does.
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
    /// Octaves what a light shows must move from its tile's size class before the class changes
    /// (the defence against tiles resized to and fro; see the tile-resize case).
    pub tile_hysteresis: f32,
    /// Constant depth bias, in shadow-map texels, for every light without a bias of its own.
    pub depth_bias: f32,
    /// Depth bias per unit of surface slope (tan of the light angle), in texels.
    pub slope_bias: f32,
    /// Offset along the surface normal, in texels.
    pub normal_bias: f32,
    /// Multiplicative depth offset: the share of the receiver's distance from the light it is
    /// pulled towards it (see [`crate::components::ShadowBias::scale`]).
    pub bias_scale: f32,
    /// A constant depth bias in metres along the light, on top of every light's bias (the way
    /// engines such as Bevy give it; 0 in umbra, whose biases are all in texels).
    pub depth_bias_metres: f32,
    /// Beyond this view distance (metres) the sun casts no shadow.
    pub shadow_distance: f32,
    /// Cascades of the sun's shadow, 1 to 4.
    pub cascades: u32,
    /// Split scheme: 0 = uniform splits, 1 = logarithmic; in between blends the two.
    pub split_lambda: f32,
    /// Split geometrically instead, from a first cascade that ends this far (metres) out.
    pub first_cascade_far: Option<f32>,
    /// Fraction (0..0.5) at the end of each cascade over which it blends into the next.
    pub cascade_blend: f32,
    /// How each cascade's box is fitted to its slice of the view.
    pub fit_mode: FitMode,
    /// Tint each cascade in its own colour to show where it is used.
    pub cascade_debug: bool,
    /// How shadow maps are sampled, for every light without a method of its own.
    pub method: ShadowMethod,
    /// Settings of their own for the lights so named ("sun", "spot 1", "point 1"): a method, a
    /// bias, a size, no shadow; applied in order when the scene is made, and a name no light has
    /// is an error then.
    pub light_settings: Vec<(String, LightSetting)>,
    /// Where the camera starts (eye, target), instead of the scene's own camera.
    pub camera: Option<(glam::Vec3, glam::Vec3)>,
    /// Which casters are drawn into a shadow map and fitted into its depth range.
    pub caster_culling: CasterCulling,
    /// Which faces of the casters are drawn into shadow maps.
    pub shadow_faces: ShadowFaces,
    /// How big each light's shadow tiles are (umbra's by screen coverage, or fixed as in the
    /// bench's baselines).
    pub tile_sizes: TileSizes,
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
    /// Widest spot cone (half angle, radians) one perspective map shadows; a wider spot is
    /// shadowed through a cube.
    pub spot_map_limit: f32,
    /// Handle the seams of shadow cubes: pick the face a lookup reads for the biased point, and
    /// let each face reach [`CUBE_MARGIN`] texels past its 90° edge for the filters (off shows
    /// the seams).
    pub cube_seams: bool,
    /// Filters compare each of their taps with the depth the receiver's plane has there
    /// (receiver-plane depth bias), not with the depth at the lookup's centre (off shows the
    /// "soft acne" of wide kernels on lit slopes).
    pub receiver_plane: bool,
    /// PCSS searches for blockers and sizes its filter by their distance (off: a fixed kernel,
    /// the Poisson 32 one, which loses contact hardening).
    pub pcss_blocker_search: bool,
    /// Radius in texels of the Gaussian blur a moment map gets after it is drawn (0: none).
    pub moment_blur: u32,
    /// How much of the bound a variance or moment map gives is cut away as light bleeding (0:
    /// none; the rest is stretched over 0..1).
    pub light_bleeding: f32,
    /// Float bits per moment: each method's own choice (auto), 16 or 32.
    pub moment_bits: MomentBits,
    /// Every light's shadow test adds screen-space contact shadows (a light's own
    /// [`crate::components::ContactShadows`] overrides it).
    pub contact_shadows: bool,
    /// Steps of the contact-shadow march.
    pub contact_steps: u32,
    /// How far the contact-shadow march goes towards the light, in metres.
    pub contact_length: f32,
    /// How thick a surface the camera sees is taken to be by the march, in metres: a step
    /// farther behind it than this passes (behind a thin pole, the far wall stays lit).
    pub contact_thickness: f32,
    /// How moment maps are made: resolved from the depth map (at its size, or a half or a
    /// quarter of it), or drawn as colour targets of their own.
    pub moments_from: MomentSource,
    /// The depth maps' format.
    pub shadow_depth: ShadowDepth,
    /// Lights that keep their shadow maps also draw planar shadows onto the ground, which then
    /// takes those instead of the maps (lights whose method is planar always do).
    pub planar_ground: bool,
    /// The ground shows a faint 1 m checker, so stair-steps, acne and shimmer are easy to see
    /// (the picture only: the measuring view and the truth never see it).
    pub ground_grid: bool,
    /// Shows, in place of the shading, how many shadow-map texels of the light so named fall
    /// on each screen pixel (Lloyd et al.'s aliasing measure).
    pub texel_density: Option<String>,
    /// Draws each shadowed light's layers (cascade boxes, spot and cube-face frusta) as lines.
    pub light_volumes: bool,
    /// Toon shading: each light's diffuse strength falls into this many bands, and a shadow
    /// takes a surface one band down (0: Phong shading).
    pub toon_bands: u32,
    /// Ambient light level (0..1) that reaches every surface.
    pub ambient: f32,
    /// Number of animated cubes in the sample scene.
    pub cubes: u32,
    /// Shadowed lanterns hung over the sample scene (see [`crate::lanterns`]).
    pub lanterns: u32,
    /// The walking character is in the sample scene.
    pub character: bool,
    /// A glTF model of the user's to place in the middle of the sample scene.
    pub model: Option<std::path::PathBuf>,
    /// A glTF scene of the user's to play instead of the sample scene, with its lights and camera.
    pub scene: Option<std::path::PathBuf>,
    /// What a file's lights give in umbra's units per lux (directional) or per candela at 1 m
    /// (point, spot): see [`crate::scene_file`].
    pub exposure: f32,
    /// Per-light biases (as `umbra tune` finds them) that replace the three above, light by light.
    pub biases: Option<LightBiases>,
    /// Fixed simulation step in seconds.
    pub dt: f32,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            shadows: true,
            shadow_strength: 1.0,
            shadow_map_size: 2048,
            // Holds the sample scene's four 2048² cascades, its two spots at 2048² and its
            // lantern's cube at 1024² a face, twice over (with static copies, or a colour map); and
            // 64 shadowed lamps beside them.
            shadow_memory: 256,
            atlas_guard: true,
            shadow_updates: 0,
            max_stale: crate::shadow::MAX_STALE,
            tile_hysteresis: crate::shadow::HYSTERESIS,
            // The same as a light's default bias (see `ShadowBias::default`).
            depth_bias: 0.5,
            slope_bias: 0.5,
            normal_bias: 0.5,
            bias_scale: 0.0,
            depth_bias_metres: 0.0,
            shadow_distance: 60.0,
            cascades: 4,
            split_lambda: DEFAULT_SPLIT_LAMBDA,
            first_cascade_far: None,
            cascade_blend: 0.1,
            fit_mode: FitMode::Stable,
            cascade_debug: false,
            method: ShadowMethod::Bilinear,
            light_settings: Vec::new(),
            camera: None,
            caster_culling: CasterCulling::LightVolume,
            shadow_faces: ShadowFaces::Both,
            tile_sizes: TileSizes::Screen,
            reuse_shadow_maps: true,
            instancing: true,
            static_cache: false,
            cube_seams: true,
            receiver_plane: true,
            pcss_blocker_search: true,
            moment_blur: DEFAULT_MOMENT_BLUR,
            light_bleeding: DEFAULT_LIGHT_BLEEDING,
            moment_bits: MomentBits::Auto,
            moments_from: MomentSource::Colour,
            contact_shadows: false,
            contact_steps: DEFAULT_CONTACT_STEPS,
            contact_length: DEFAULT_CONTACT_LENGTH,
            contact_thickness: DEFAULT_CONTACT_THICKNESS,
            shadow_depth: ShadowDepth::Float32,
            toon_bands: 0,
            ground_grid: true,
            texel_density: None,
            light_volumes: false,
            planar_ground: false,
            spot_map_limit: crate::shadow::MAX_MAP_HALF_ANGLE,
            ambient: 0.12,
            cubes: 10,
            lanterns: 0,
            character: true,
            model: None,
            scene: None,
            exposure: 1.0,
            biases: None,
            dt: 1.0 / 60.0,
        }
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

/// Steps of the contact-shadow march by default (Bevy's; Filament takes 8).
pub const DEFAULT_CONTACT_STEPS: u32 = 16;
/// Most steps of the contact-shadow march.
pub const MAX_CONTACT_STEPS: u32 = 64;
/// Length of the contact-shadow march by default, in metres (Bevy's and Filament's).
pub const DEFAULT_CONTACT_LENGTH: f32 = 0.3;
/// Thickness the contact-shadow march takes surfaces to have by default, in metres.
pub const DEFAULT_CONTACT_THICKNESS: f32 = 0.1;
/// Default blur radius of moment maps, in texels.
pub const DEFAULT_MOMENT_BLUR: u32 = 2;
/// Largest blur radius of moment maps, in texels.
pub const MAX_MOMENT_BLUR: u32 = 16;
/// Bands of toon shading when it is turned on without a number (key T).
pub const DEFAULT_TOON_BANDS: u32 = 4;
/// Most bands of toon shading.
pub const MAX_TOON_BANDS: u32 = 16;
/// Largest multiplicative depth offset (half the distance to the light).
pub const MAX_BIAS_SCALE: f32 = 0.5;

/// Why a bias term in texels was refused ([`crate::components::ShadowBias::MAX_TEXELS`]).
const BIAS_TEXELS_WHY: &str = "must be between 0 and 100 texels";
/// Default light-bleeding reduction.
pub const DEFAULT_LIGHT_BLEEDING: f32 = 0.2;

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

named_choices!(TileSizes, "a tile-size policy", Screen = "screen", Fixed = "fixed", Bevy = "bevy");
named_choices!(FitMode, "a fit mode", Stable = "stable", Unsnapped = "unsnapped", Tight = "tight", Sdsm = "sdsm");
named_choices!(ShadowFaces, "a face choice", Both = "both", Back = "back");
named_choices!(
    ShadowMethod,
    "a shadow method",
    Nearest = "nearest",
    Bilinear = "bilinear",
    Pcf3 = "pcf3",
    Pcf5 = "pcf5",
    Gauss5 = "gauss5",
    Poisson16 = "poisson16",
    Poisson32 = "poisson32",
    Pcss = "pcss",
    Vsm = "vsm",
    Evsm = "evsm",
    Evsm2 = "evsm2",
    Msm = "msm",
    MsmHausdorff = "msm-hausdorff",
    DepthR32f = "r32f",
    RadialR16f = "r16f-radial",
    Planar = "planar"
);
named_choices!(ShadowDepth, "a depth-map format", Float32 = "d32", Unorm16 = "d16");
named_choices!(CasterCulling, "a culling mode", LightVolume = "light", CameraView = "camera");

/// A setting outside what makes sense, with the reason.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("setting `{name}` = {value} is invalid: {why}")]
pub struct SettingsError {
    /// Which setting.
    pub name: &'static str,
    /// Its value as text.
    pub value: String,
    /// What it must be instead.
    pub why: &'static str,
}

/// The default split scheme, mostly logarithmic.
///
/// Logarithmic splits match the way a perspective view spends its pixels (each cascade covers the
/// same ratio of depths), but with the camera's 0.1 m near plane they waste the first cascade on
/// the half metre in front of the lens: 4 cascades to 60 m split at 0.5, 2.4 and 12 m. A quarter of
/// uniform splitting moves those to 4.1, 9.3 and 20 m, where the sample's ground and cubes are
/// seen, while still giving near cascades far more texels per metre than far ones (uniform alone
/// would split at 15, 30 and 45 m and blur everything close to the camera).
pub const DEFAULT_SPLIT_LAMBDA: f32 = 0.75;

/// Texels a cube face reaches past its edge when seams are handled: as far as the widest method
/// samples.
pub const CUBE_MARGIN: u32 = 4;

/// Least shadow memory, in MiB: an atlas of 16 MiB still holds hundreds of small tiles.
pub const MIN_SHADOW_MEMORY: u32 = 16;
/// The smallest update budget: the smallest tile ([`crate::shadow::MIN_TILE`]²).
pub const MIN_SHADOW_UPDATES: u32 = crate::shadow::MIN_TILE * crate::shadow::MIN_TILE;
/// Most shadow memory, in MiB.
pub const MAX_SHADOW_MEMORY: u32 = 16384;
/// The longest wait `max_stale` may promise, in frames.
pub const MAX_STALE_FRAMES: u32 = 1000;
/// The widest `tile_hysteresis`, in octaves.
pub const MAX_HYSTERESIS: f32 = 2.0;

/// Largest shadow-map layer accepted (the device may allow less; the renderer checks again).
pub const MAX_SHADOW_MAP_SIZE: u32 = 8192;

/// Most animated cubes a scene may hold (the stress scene's ten thousand, with room to spare).
pub const MAX_CUBES: u32 = 100_000;

impl Settings {
    /// The bias every light gets from these settings.
    pub fn shadow_bias(&self) -> crate::components::ShadowBias {
        crate::components::ShadowBias {
            constant: self.depth_bias,
            slope: self.slope_bias,
            normal: self.normal_bias,
            scale: self.bias_scale,
            receiver_plane: self.receiver_plane,
        }
    }

    /// Checks every setting; the first bad one is named in the error.
    pub fn validate(&self) -> Result<(), SettingsError> {
        fn bad(name: &'static str, value: impl ToString, why: &'static str) -> Result<(), SettingsError> {
            Err(SettingsError { name, value: value.to_string(), why })
        }
        let unit = |x: f32| x.is_finite() && (0.0..=1.0).contains(&x);
        let non_negative = |x: f32| x.is_finite() && x >= 0.0;
        if !unit(self.shadow_strength) {
            return bad("shadow_strength", self.shadow_strength, "must be between 0 and 1");
        }
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
        for (name, v) in
            [("depth_bias", self.depth_bias), ("slope_bias", self.slope_bias), ("normal_bias", self.normal_bias)]
        {
            if !crate::components::ShadowBias::texels_ok(v) {
                return bad(name, v, BIAS_TEXELS_WHY);
            }
        }
        if !(non_negative(self.bias_scale) && self.bias_scale <= MAX_BIAS_SCALE) {
            return bad(
                "bias_scale",
                self.bias_scale,
                "must be a share between 0 and 0.5 of the distance to the light",
            );
        }
        if !(non_negative(self.depth_bias_metres) && self.depth_bias_metres <= 10.0) {
            return bad("depth_bias_metres", self.depth_bias_metres, "must be between 0 and 10 m");
        }
        if let Some(first) = self.first_cascade_far
            && !(first.is_finite() && first > 0.1 && first <= self.shadow_distance)
        {
            return bad("first_cascade_far", first, "must be a distance above 0.1 m and within the shadow distance");
        }
        if !(self.shadow_distance.is_finite() && self.shadow_distance > 0.1) {
            return bad("shadow_distance", self.shadow_distance, "must be a finite distance above 0.1 m");
        }
        if !(1..=MAX_CASCADES as u32).contains(&self.cascades) {
            return bad("cascades", self.cascades, "must be between 1 and 4");
        }
        if !unit(self.split_lambda) {
            return bad("split_lambda", self.split_lambda, "must be between 0 (uniform) and 1 (logarithmic)");
        }
        if !(self.cascade_blend.is_finite() && (0.0..=0.5).contains(&self.cascade_blend)) {
            return bad("cascade_blend", self.cascade_blend, "must be a fraction between 0 and 0.5");
        }
        if !(1..=MAX_CONTACT_STEPS).contains(&self.contact_steps) {
            return bad("contact_steps", self.contact_steps, "must be between 1 and 64");
        }
        if !(self.contact_length.is_finite() && (0.0..=10.0).contains(&self.contact_length)) {
            return bad("contact_length", self.contact_length, "must be between 0 and 10 metres");
        }
        if !(self.contact_thickness.is_finite() && self.contact_thickness > 0.0 && self.contact_thickness <= 10.0) {
            return bad("contact_thickness", self.contact_thickness, "must be more than 0 and at most 10 metres");
        }
        if self.moment_blur > MAX_MOMENT_BLUR {
            return bad("moment_blur", self.moment_blur, "must be between 0 and 16 texels");
        }
        if !(self.light_bleeding.is_finite() && (0.0..=0.9).contains(&self.light_bleeding)) {
            return bad("light_bleeding", self.light_bleeding, "must be a fraction between 0 and 0.9");
        }
        if self.toon_bands == 1 || self.toon_bands > MAX_TOON_BANDS {
            return bad("toon_bands", self.toon_bands, "must be 0 (Phong) or between 2 and 16 bands");
        }
        if !unit(self.ambient) {
            return bad("ambient", self.ambient, "must be between 0 and 1");
        }
        if !(self.spot_map_limit.is_finite() && (1f32.to_radians()..=89f32.to_radians()).contains(&self.spot_map_limit))
        {
            return bad("spot_map_limit", self.spot_map_limit, "must be an angle between 1° and 89° (in radians)");
        }
        if !(self.exposure.is_finite() && (1e-6..=1e6).contains(&self.exposure)) {
            return bad("exposure", self.exposure, "must be a factor between 0.000001 and 1000000");
        }
        if let (Some(model), Some(_)) = (&self.model, &self.scene) {
            let why = "a model goes into the sample scene and a scene file replaces it: give one or the other";
            return bad("model", model.display(), why);
        }
        if let Some((eye, target)) = self.camera
            && !(eye.is_finite() && target.is_finite() && eye.distance(target) > 1e-3)
        {
            return bad("camera", format!("{eye} looking at {target}"), "must be two finite points apart");
        }
        if self.cubes > MAX_CUBES {
            return bad("cubes", self.cubes, "must be at most 100000");
        }
        if self.lanterns > crate::lanterns::MAX_LANTERNS {
            return bad("lanterns", self.lanterns, "must be at most 4096");
        }
        if !(self.dt.is_finite() && self.dt > 0.0 && self.dt <= 1.0) {
            return bad("dt", self.dt, "must be a step above 0 and at most 1 second");
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cube_faces_reach_as_far_as_every_method_samples() {
        for m in ShadowMethod::ALL {
            assert!(m.reach() <= CUBE_MARGIN, "{m:?} reaches {} texels", m.reach());
        }
    }

    #[test]
    fn defaults_are_valid() {
        assert_eq!(Settings::default().validate(), Ok(()));
    }

    #[test]
    fn choices_parse_by_name_and_cycle() {
        assert_eq!("tight".parse::<FitMode>(), Ok(FitMode::Tight));
        assert_eq!("unsnapped".parse::<FitMode>(), Ok(FitMode::Unsnapped));
        assert!("loose".parse::<FitMode>().unwrap_err().contains("loose"));
        assert_eq!(FitMode::Stable.next(), FitMode::Unsnapped);
        assert_eq!(FitMode::Tight.next(), FitMode::Sdsm);
        assert_eq!(FitMode::Sdsm.next(), FitMode::Stable);
        assert_eq!("sdsm".parse::<FitMode>(), Ok(FitMode::Sdsm));
        assert_eq!("pcf5".parse::<ShadowMethod>(), Ok(ShadowMethod::Pcf5));
        assert!("blur".parse::<ShadowMethod>().unwrap_err().contains("not a shadow method"));
    }

    #[test]
    fn nonsense_is_named() {
        type Case = (fn(&mut Settings), &'static str);
        let cases: [Case; 26] = [
            (|s| s.contact_steps = 0, "contact_steps"),
            (|s| s.contact_length = f32::INFINITY, "contact_length"),
            (|s| s.contact_thickness = 0.0, "contact_thickness"),
            (|s| s.cubes = MAX_CUBES + 1, "cubes"),
            (|s| s.lanterns = 5000, "lanterns"),
            (|s| s.camera = Some((glam::Vec3::ONE, glam::Vec3::ONE)), "camera"),
            (|s| s.bias_scale = 0.9, "bias_scale"),
            (|s| s.toon_bands = 1, "toon_bands"),
            (|s| s.moment_blur = 99, "moment_blur"),
            (|s| s.light_bleeding = f32::NAN, "light_bleeding"),
            (|s| s.cascades = 5, "cascades"),
            (|s| s.split_lambda = -0.1, "split_lambda"),
            (|s| s.cascade_blend = 0.9, "cascade_blend"),
            (|s| s.shadow_strength = 2.0, "shadow_strength"),
            (|s| s.shadow_map_size = 0, "shadow_map_size"),
            (|s| s.shadow_memory = 8, "shadow_memory"),
            (|s| s.shadow_memory = u32::MAX, "shadow_memory"),
            (|s| s.shadow_updates = 5, "shadow_updates"),
            (|s| s.max_stale = 0, "max_stale"),
            (|s| s.tile_hysteresis = f32::NAN, "tile_hysteresis"),
            (|s| s.slope_bias = f32::NAN, "slope_bias"),
            (|s| s.shadow_distance = -1.0, "shadow_distance"),
            (|s| s.ambient = f32::INFINITY, "ambient"),
            (|s| s.dt = 0.0, "dt"),
            (|s| s.exposure = 0.0, "exposure"),
            (|s| (s.model, s.scene) = (Some("a.glb".into()), Some("b.gltf".into())), "model"),
        ];
        for (break_it, name) in cases {
            let mut s = Settings::default();
            break_it(&mut s);
            let err = s.validate().unwrap_err();
            assert_eq!(err.name, name);
            assert!(err.to_string().contains(name));
        }
        let mut s = Settings { cubes: MAX_CUBES + 1, ..Settings::default() };
        assert!(s.validate().unwrap_err().to_string().contains(&MAX_CUBES.to_string()), "the limit is named");
        s.cubes = MAX_CUBES;
        assert_eq!(s.validate(), Ok(()));
    }
}
