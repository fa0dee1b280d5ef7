//! The `umbra` command's scene options, shared by every command, and the checks on their values.

use anyhow::Result;
use clap::Args;
use clap::builder::TypedValueParser;
use std::path::PathBuf;
use umbra::components::ShadowMethod;
use umbra::reproduce::{
    LightSetting, parse_bias, parse_contact, parse_method, parse_size as parse_light_size, parse_texels,
};
use umbra::settings::{
    CascadeSettings, CasterCulling, LightMaps, MapSettings, MomentBits, MomentResolve, MomentSource, SceneSettings,
    ShadowDepth, ShadowFaces, ShadowSettings, SunMaps, TileSizes, ViewSettings,
};
use umbra::shadow::FitMode;
use umbra::{NamedChoice, Settings};

/// The parser of a setting chosen by name: it takes the names of the table the settings read,
/// and its help lists them all from there.
fn choice<T: NamedChoice + std::str::FromStr<Err = String>>() -> impl clap::builder::TypedValueParser<Value = T> {
    clap::builder::PossibleValuesParser::new(T::all().iter().map(|c| c.choice_name())).try_map(|name| name.parse::<T>())
}

/// Settings shared by every command.
#[derive(Args, Clone, Default)]
pub struct SceneArgs {
    /// Turn shadows off.
    #[arg(long)]
    pub no_shadows: bool,
    /// Shadow-map layer size in texels: a sun cascade's, and the largest any other light's.
    #[arg(long, value_name = "TEXELS")]
    pub shadow_map_size: Option<u32>,
    /// Shadow memory in MiB (16..16384): every light's shadow takes tiles of one atlas this big.
    #[arg(long, value_name = "MIB")]
    pub shadow_memory: Option<u32>,
    /// Texels of shadow tiles redrawn per frame at most, as a number or with K or M (x1024,
    /// x1024²): `4M` is four 1024² tiles. 0 (the default): no limit.
    #[arg(long, value_name = "TEXELS", value_parser = parse_texels)]
    pub shadow_updates: Option<u32>,
    /// Frames (1..1000) a shadow layer may wait under --shadow-updates before it goes ahead of
    /// every layer that shows more (default 8).
    #[arg(long, value_name = "FRAMES")]
    pub max_stale: Option<u32>,
    /// Octaves (0..2) what a light shows must move before its shadow tile changes size class
    /// (default 0.75; 0 lets tiles flip at a class's edge: the tile-resize case).
    #[arg(long, value_name = "OCTAVES")]
    pub tile_hysteresis: Option<f32>,
    /// Let filters read past their tile into a neighbour's texels (the atlas-seams case).
    #[arg(long)]
    pub no_atlas_guard: bool,
    /// Let a pixel whose virtual page is missing read as lit (the camera-cut case).
    #[arg(long)]
    pub no_page_fallback: bool,
    /// Let a moved caster leave the maps over where it was (the moving-caster case).
    #[arg(long)]
    pub no_old_bounds: bool,
    /// How dark shadows are, 0..1.
    #[arg(long, value_name = "0..1", allow_negative_numbers = true)]
    pub shadow_strength: Option<f32>,
    /// Constant depth bias in texels.
    #[arg(long, value_name = "TEXELS", allow_negative_numbers = true)]
    pub depth_bias: Option<f32>,
    /// Slope-scaled depth bias in texels.
    #[arg(long, value_name = "TEXELS", allow_negative_numbers = true)]
    pub slope_bias: Option<f32>,
    /// Normal-offset bias in texels.
    #[arg(long, value_name = "TEXELS", allow_negative_numbers = true)]
    pub normal_bias: Option<f32>,
    /// Multiplicative depth offset: the share of the distance to the light a receiver is pulled
    /// towards it before the test, 0..0.5 (the source article's `depth × 0.95` is 0.05).
    #[arg(long, value_name = "SHARE", allow_negative_numbers = true)]
    pub bias_scale: Option<f32>,
    /// Number of animated cubes.
    #[arg(long)]
    pub cubes: Option<u32>,
    /// Shadowed lanterns hung over the sample scene, point and spot mixed, some moving (0..4096).
    #[arg(long, value_name = "N")]
    pub lanterns: Option<u32>,
    /// Cascades of the sun's shadow, 1..4.
    #[arg(long, value_name = "N")]
    pub cascades: Option<u32>,
    /// Cascade split scheme: 0 uniform .. 1 logarithmic.
    #[arg(long, value_name = "0..1", allow_negative_numbers = true)]
    pub split_lambda: Option<f32>,
    /// Fraction of each cascade that blends into the next, 0..0.5.
    #[arg(long, value_name = "FRACTION", allow_negative_numbers = true)]
    pub cascade_blend: Option<f32>,
    /// How cascades are fitted: stable (no shimmer), unsnapped, tight (sharper, shimmers) or
    /// sdsm (to what the camera saw: splits and boxes from a reduction of its depth buffer).
    #[arg(long, value_name = "MODE", value_parser = choice::<FitMode>())]
    pub fit: Option<FitMode>,
    /// How the sun's shadow is laid out: cascades (the default), or virtual (a clipmap of
    /// 64² pages round the camera, each drawn once and kept, at the resolution the visible
    /// pixels need; depth methods only).
    #[arg(long, value_name = "KIND", value_parser = choice::<SunMaps>())]
    pub sun_maps: Option<SunMaps>,
    /// How spot and point lights' shadows are laid out: atlas (the default: tiles sized by what
    /// each light shows), or virtual (a spot's map or a point light's cube in 64² pages, every
    /// level over the whole map, each drawn once and kept, at the resolution the visible pixels
    /// need; depth methods only).
    #[arg(long, value_name = "KIND", value_parser = choice::<LightMaps>())]
    pub light_maps: Option<LightMaps>,
    /// Octaves (-4..4) coarser than each pixel's footprint its virtual page is chosen (negative:
    /// finer, more pages; default -1, two texels across a pixel).
    #[arg(long, value_name = "OCTAVES", allow_negative_numbers = true)]
    pub page_bias: Option<f32>,
    /// MiB of the shadow memory every paged light's pages take together, one pool they share
    /// (default 32; at most half of --shadow-memory): when the view needs more, the lights that
    /// show least choose their levels coarser first.
    #[arg(long, value_name = "MIB")]
    pub page_memory: Option<u32>,
    /// Tint each cascade in its own colour.
    #[arg(long)]
    pub cascade_debug: bool,
    /// How shadow maps are sampled, for every light without a method of its own (evsm2: EVSM's
    /// positive warp alone; msm-hausdorff: MSM's bound knowing depths lie in 0..1; r32f: depth in
    /// an R32F colour target; r16f-radial: distance from the light in R16F; planar: shadows
    /// projected onto the ground, no map).
    #[arg(long, alias = "filter", value_name = "METHOD", value_parser = choice::<ShadowMethod>())]
    pub method: Option<ShadowMethod>,
    /// Blur radius of moment maps (vsm, evsm, evsm2, msm) in texels, 0..16 (0: none).
    #[arg(long, value_name = "TEXELS")]
    pub moment_blur: Option<u32>,
    /// Light-bleeding reduction of moment maps, 0..0.9: the share of their bound cut away.
    #[arg(long, value_name = "0..0.9")]
    pub light_bleeding: Option<f32>,
    /// Float bits per moment: auto (each method's own choice), 16 or 32.
    #[arg(long, value_name = "BITS", value_parser = choice::<MomentBits>())]
    pub moment_bits: Option<MomentBits>,
    /// How moment maps are made: depth (resolved from the depth map), depth/2 or depth/4 (at
    /// half or a quarter of its side, each texel the mean of 2x2 or 4x4 depth texels), or
    /// colour (drawn as a colour target of their own).
    #[arg(long, value_name = "SOURCE", value_parser = choice::<MomentSource>())]
    pub moments_from: Option<MomentSource>,
    /// How moments resolved from depth are made: compute (one dispatch resolves and blurs in
    /// shared memory), passes (full-screen passes: resolve, rows, columns) or auto (compute on a
    /// GPU, passes on a software rasterizer).
    #[arg(long, value_name = "HOW", value_parser = choice::<MomentResolve>())]
    pub moment_resolve: Option<MomentResolve>,
    /// Samples per texel of moment maps resolved from depth: 1, or 2, 4 or 8 (the depth map
    /// drawn multisampled at the moment map's size, each texel the mean of its samples).
    #[arg(long, value_name = "N")]
    pub moment_samples: Option<u32>,
    /// Format of the depth maps: d32 (32-bit float) or d16 (16-bit fixed point, half the memory).
    #[arg(long, value_name = "FORMAT", value_parser = choice::<ShadowDepth>())]
    pub shadow_depth: Option<ShadowDepth>,
    /// Filters compare every tap with the lookup's centre, not with the receiver's plane (for
    /// every light without a bias of its own; key R in play).
    #[arg(long)]
    pub no_receiver_plane: bool,
    /// Every shadowed light also draws planar shadows onto the ground, which takes those in
    /// place of its maps (other surfaces keep the maps).
    #[arg(long)]
    pub planar_ground: bool,
    /// Toon shading with this many bands, 2..16 (key T in play).
    #[arg(long, value_name = "BANDS")]
    pub toon: Option<u32>,
    /// Which casters shadow maps take: light (all in the light's volume) or camera (only those
    /// the camera sees, a shortcut that loses off-screen casters).
    #[arg(long, value_name = "MODE", value_parser = choice::<CasterCulling>())]
    pub culling: Option<CasterCulling>,
    /// Which caster faces shadow maps take: both, or back (only those turned away from the light).
    #[arg(long, value_name = "FACES", value_parser = choice::<ShadowFaces>())]
    pub shadow_faces: Option<ShadowFaces>,
    /// How big lights' shadow tiles are: screen (by what each shows, the default), fixed (every
    /// layer at the map size) or bevy (spots at the map size, point lights' faces at half).
    #[arg(long, value_name = "POLICY", value_parser = choice::<TileSizes>())]
    pub tile_sizes: Option<TileSizes>,
    /// Draw every shadow map every frame instead of only those of dirty lights.
    #[arg(long)]
    pub redraw_shadows: bool,
    /// Draw every caster into shadow maps with a call of its own, not instanced by mesh.
    #[arg(long)]
    pub no_instancing: bool,
    /// Keep the casters at rest in static maps and draw a dirty shadow map over a copy of them,
    /// only those that moved drawn again (twice the shadow memory a texel).
    #[arg(long)]
    pub static_cache: bool,
    /// Leave the walking character out.
    #[arg(long)]
    pub no_character: bool,
    /// Place this glTF model (.gltf or .glb) in the middle of the scene, playing its first clip.
    #[arg(long, value_name = "PATH")]
    pub model: Option<PathBuf>,
    /// Play this glTF scene (.gltf or .glb) instead of the sample: its meshes, its lights
    /// (KHR_lights_punctual) with shadows, its first camera (or one that frames it); a sun is
    /// added when it has no light.
    #[arg(long, value_name = "PATH", conflicts_with = "model")]
    pub scene: Option<PathBuf>,
    /// What one lux (or one candela at 1 m) of a scene file's lights is worth on screen; files
    /// with physical values (a 100000 lux sun) want about 0.00001.
    #[arg(long, value_name = "FACTOR")]
    pub exposure: Option<f32>,
    /// Per-light shadow biases from a file written by `umbra tune` (and per-light methods, if it
    /// has `"methods": {"spot 1": "pcss"}`).
    #[arg(long, value_name = "FILE")]
    pub biases: Option<PathBuf>,
    /// One light's shadow method, by its name: `--light-method "spot 1=pcss"` (repeat for more
    /// lights; the others take --method).
    #[arg(long, value_name = "LIGHT=METHOD", value_parser = parse_method)]
    pub light_method: Vec<(String, LightSetting)>,
    /// One light's own bias: `--light-bias "spot 1=CONSTANT,SLOPE,NORMAL[,SCALE][,flat]"` (texels;
    /// the multiplicative offset; `flat` turns its receiver plane off).
    #[arg(long, value_name = "LIGHT=BIAS", value_parser = parse_bias)]
    pub light_bias: Vec<(String, LightSetting)>,
    /// One light's size, for PCSS and the soft truth: `--light-size "sun=0.5"` (a sun's disc
    /// radius in degrees; a spot's or point light's radius in metres).
    #[arg(long, value_name = "LIGHT=SIZE", value_parser = parse_light_size)]
    pub light_size: Vec<(String, LightSetting)>,
    /// This light casts no shadow (repeat for more lights).
    #[arg(long, value_name = "LIGHT")]
    pub no_light_shadow: Vec<String>,
    /// Every light's shadow test adds screen-space contact shadows: a short march towards the
    /// light through the camera's depth, which finds thin casters and the gap a bias opens at
    /// contact (key J in play).
    #[arg(long)]
    pub contact_shadows: bool,
    /// One light's contact shadows on or off: `--light-contact "spot 1=on"` (repeat for more
    /// lights; the others follow --contact-shadows).
    #[arg(long, value_name = "LIGHT=on|off", value_parser = parse_contact)]
    pub light_contact: Vec<(String, LightSetting)>,
    /// Steps of the contact-shadow march, 1..64 (default 16).
    #[arg(long, value_name = "N")]
    pub contact_steps: Option<u32>,
    /// How far the contact-shadow march goes towards the light, in metres (default 0.3).
    #[arg(long, value_name = "METRES")]
    pub contact_length: Option<f32>,
    /// How thick surfaces are taken to be by the contact-shadow march, in metres (default 0.1):
    /// a step farther behind what the camera sees passes.
    #[arg(long, value_name = "METRES")]
    pub contact_thickness: Option<f32>,
    /// A plain ground, without the faint checker that shows stair-steps and shimmer.
    #[arg(long)]
    pub no_ground_grid: bool,
    /// Show, in place of the shading, how many shadow-map texels of this light fall on each
    /// pixel: red a texel over several pixels, green one each, blue many a pixel.
    #[arg(long, value_name = "LIGHT")]
    pub texel_density: Option<String>,
    /// Draw each shadowed light's layers (cascade boxes, spot and cube-face frusta) as lines.
    #[arg(long)]
    pub light_volumes: bool,
    /// Beyond this view distance (metres) the sun casts no shadow.
    #[arg(long, value_name = "METRES")]
    pub shadow_distance: Option<f32>,
    /// Where the camera starts: X,Y,Z in metres (with --target).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_point, requires = "target", allow_hyphen_values = true)]
    pub eye: Option<glam::Vec3>,
    /// What the camera looks at: X,Y,Z in metres (with --eye).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_point, requires = "eye", allow_hyphen_values = true)]
    pub target: Option<glam::Vec3>,
}

pub fn parse_size(s: &str) -> Result<u32, String> {
    match s.parse::<i64>() {
        Ok(v) if (1..=16384).contains(&v) => Ok(v as u32),
        _ => Err(format!("`{s}` is not a size: give a whole number of pixels from 1 to 16384")),
    }
}

pub fn parse_angle(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(a) if (0.0..=10.0).contains(&a) => Ok(a),
        _ => Err(format!("`{s}` is not an angle: give degrees from 0 to 10")),
    }
}

pub fn parse_radius(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(r) if (0.0..=10.0).contains(&r) => Ok(r),
        _ => Err(format!("`{s}` is not a radius: give metres from 0 to 10")),
    }
}

pub fn parse_time(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(t) if t.is_finite() && t >= 0.0 => Ok(t),
        _ => Err(format!("`{s}` is not a time: give seconds, 0 or more")),
    }
}

/// Reads `X,Y,Z`.
pub fn parse_point(s: &str) -> Result<glam::Vec3, String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|p| p.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("`{s}` is not a point: give X,Y,Z in metres"))?;
    match v[..] {
        [x, y, z] if v.iter().all(|c| c.is_finite() && c.abs() <= 1e6) => Ok(glam::Vec3::new(x, y, z)),
        _ => Err(format!("`{s}` is not a point: give X,Y,Z in metres, each finite")),
    }
}

impl SceneArgs {
    pub fn settings(&self) -> Result<Settings> {
        let d = Settings::default();
        let (biases, file_methods) = match self.biases.as_deref() {
            Some(path) => {
                let (biases, methods) = umbra::biases::LightBiases::load_with_methods(path)?;
                (Some(biases), methods)
            }
            None => (None, Vec::new()),
        };
        let scene = SceneSettings {
            cubes: self.cubes.unwrap_or(d.scene.cubes),
            lanterns: self.lanterns.unwrap_or(d.scene.lanterns),
            character: !self.no_character,
            model: self.model.clone(),
            file: self.scene.clone(),
            exposure: self.exposure.unwrap_or(d.scene.exposure),
            camera: self.eye.zip(self.target),
            // The file's first, so the command line's win.
            light_settings: file_methods
                .into_iter()
                .map(|(light, m)| (light, LightSetting::Method(m)))
                .chain(self.light_method.iter().cloned())
                .chain(self.light_bias.iter().cloned())
                .chain(self.light_size.iter().cloned())
                .chain(self.light_contact.iter().cloned())
                .chain(self.no_light_shadow.iter().map(|l| (l.clone(), LightSetting::NoShadow)))
                .collect(),
            biases,
            ..d.scene
        };
        let shadow = ShadowSettings {
            enabled: !self.no_shadows,
            shadow_strength: self.shadow_strength.unwrap_or(d.shadow.shadow_strength),
            method: self.method.unwrap_or(d.shadow.method),
            depth_bias: self.depth_bias.unwrap_or(d.shadow.depth_bias),
            slope_bias: self.slope_bias.unwrap_or(d.shadow.slope_bias),
            normal_bias: self.normal_bias.unwrap_or(d.shadow.normal_bias),
            bias_scale: self.bias_scale.unwrap_or(d.shadow.bias_scale),
            receiver_plane: !self.no_receiver_plane,
            light_bleeding: self.light_bleeding.unwrap_or(d.shadow.light_bleeding),
            contact_shadows: self.contact_shadows,
            contact_steps: self.contact_steps.unwrap_or(d.shadow.contact_steps),
            contact_length: self.contact_length.unwrap_or(d.shadow.contact_length),
            contact_thickness: self.contact_thickness.unwrap_or(d.shadow.contact_thickness),
            planar_ground: self.planar_ground,
            ..d.shadow
        };
        let maps = MapSettings {
            shadow_map_size: self.shadow_map_size.unwrap_or(d.maps.shadow_map_size),
            shadow_memory: self.shadow_memory.unwrap_or(d.maps.shadow_memory),
            tile_sizes: self.tile_sizes.unwrap_or(d.maps.tile_sizes),
            tile_hysteresis: self.tile_hysteresis.unwrap_or(d.maps.tile_hysteresis),
            atlas_guard: !self.no_atlas_guard,
            shadow_updates: self.shadow_updates.unwrap_or(d.maps.shadow_updates),
            max_stale: self.max_stale.unwrap_or(d.maps.max_stale),
            reuse_shadow_maps: !self.redraw_shadows,
            instancing: !self.no_instancing,
            static_cache: self.static_cache,
            shadow_depth: self.shadow_depth.unwrap_or(d.maps.shadow_depth),
            caster_culling: self.culling.unwrap_or(d.maps.caster_culling),
            shadow_faces: self.shadow_faces.unwrap_or(d.maps.shadow_faces),
            moments_from: self.moments_from.unwrap_or(d.maps.moments_from),
            moment_resolve: self.moment_resolve.unwrap_or(d.maps.moment_resolve),
            moment_bits: self.moment_bits.unwrap_or(d.maps.moment_bits),
            moment_blur: self.moment_blur.unwrap_or(d.maps.moment_blur),
            moment_samples: self.moment_samples.unwrap_or(d.maps.moment_samples),
            sun_maps: self.sun_maps.unwrap_or(d.maps.sun_maps),
            light_maps: self.light_maps.unwrap_or(d.maps.light_maps),
            page_bias: self.page_bias.unwrap_or(d.maps.page_bias),
            page_memory: self.page_memory.unwrap_or(d.maps.page_memory),
            page_fallback: !self.no_page_fallback,
            old_bounds: !self.no_old_bounds,
            ..d.maps
        };
        let cascade = CascadeSettings {
            shadow_distance: self.shadow_distance.unwrap_or(d.cascade.shadow_distance),
            cascades: self.cascades.unwrap_or(d.cascade.cascades),
            split_lambda: self.split_lambda.unwrap_or(d.cascade.split_lambda),
            cascade_blend: self.cascade_blend.unwrap_or(d.cascade.cascade_blend),
            fit_mode: self.fit.unwrap_or(d.cascade.fit_mode),
            ..d.cascade
        };
        let view = ViewSettings {
            toon_bands: self.toon.unwrap_or(d.view.toon_bands),
            ground_grid: !self.no_ground_grid,
            cascade_debug: self.cascade_debug,
            texel_density: self.texel_density.clone(),
            light_volumes: self.light_volumes,
            ..d.view
        };
        let settings = Settings { scene, shadow, maps, cascade, view };
        if let Some(why) = settings.pages_refused() {
            anyhow::bail!("virtual maps with --method {}: {why}", settings.shadow.method.name());
        }
        Ok(settings)
    }
}
