//! The shadow configurations `umbra bench` compares (each a set of shadow settings, with its
//! label and its memory) and which of them a sweep takes; its views and options are in
//! [`super::sweep_options`]. Timing ([`super::cost`]) and the sweep itself ([`super::sweep`])
//! both read these.

use crate::components::ShadowMethod;
use crate::settings::{
    LightMaps, MomentBits, MomentResolve, MomentSource, Settings, ShadowDepth, ShadowFaces, SunMaps,
};
use crate::shadow::FitMode;

/// One shadow configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Config {
    /// Texels per side of each map.
    pub map_size: u32,
    /// Sun cascades.
    pub cascades: u32,
    /// Cascade fitting.
    pub fit: FitMode,
    /// How every light's shadow map is sampled.
    pub method: ShadowMethod,
    /// Constant, slope and normal bias, all the same, in texels.
    pub bias: f32,
    /// Faces drawn into the maps.
    pub faces: ShadowFaces,
    /// Filters compare with the receiver's plane.
    pub receiver_plane: bool,
    /// Blur radius of moment maps, in texels.
    pub blur: u32,
    /// Bits per moment of moment maps.
    pub moment_bits: MomentBits,
    /// How moment maps are made.
    pub moments_from: MomentSource,
    /// How moments from depth are made.
    pub moment_resolve: MomentResolve,
    /// Samples per moment texel of moments from depth (MSAA).
    pub moment_samples: u32,
    /// Format of the depth maps.
    pub depth: ShadowDepth,
    /// Multiplicative depth offset (share of the distance to the light).
    pub bias_scale: f32,
    /// Every light adds contact shadows (at the settings' steps, length and thickness).
    pub contact: bool,
    /// How the sun's shadow is laid out: cascades (map size, cascades and fit above) or a
    /// virtual map (its coarse map at the map size up to 1024², its pages as the defaults have
    /// them).
    pub sun_maps: SunMaps,
    /// How spot and point lights' shadows are laid out: atlas tiles, or virtual maps (their
    /// pages as the defaults have them).
    pub light_maps: LightMaps,
    /// Instead of the above: the Bevy-like baseline ([`bevy_like`]).
    pub bevy_like: bool,
}

/// The family virtual shadow maps are charted as, whatever their method.
pub const VIRTUAL_FAMILY: &str = "virtual pages";

/// The family the Bevy-like baseline is charted as.
pub const BEVY_FAMILY: &str = "Bevy-like";

/// What a user would otherwise get from Bevy, as its documented defaults read: 4 cascades
/// split geometrically from 10 m to 150 m, each blending 20 % into the next; a depth bias of
/// 0.02 m along the light and a normal bias of 1.8 texels; its 9-tap Gaussian PCF (Castaño's,
/// `gauss5`); 2048² maps; no receiver plane. Umbra's stable fit stands in for Bevy's own.
#[must_use]
pub fn bevy_like(base: &Settings) -> Settings {
    base.clone().with(|s| {
        s.maps.shadow_map_size = 2048;
        s.cascade.cascades = 4;
        s.cascade.first_cascade_far = Some(10.0);
        s.cascade.shadow_distance = 150.0;
        s.cascade.cascade_blend = 0.2;
        s.cascade.fit_mode = FitMode::Stable;
        s.shadow.method = ShadowMethod::Gauss5;
        s.shadow.depth_bias = 0.0;
        s.shadow.slope_bias = 0.0;
        s.shadow.normal_bias = 1.8;
        s.shadow.depth_bias_metres = 0.02;
        s.shadow.receiver_plane = false;
        s.maps.shadow_faces = ShadowFaces::Both;
    })
}

impl Config {
    /// The default settings' configuration.
    pub fn default_settings() -> Config {
        let d = Settings::default();
        Config {
            map_size: d.maps.shadow_map_size,
            cascades: d.cascade.cascades,
            fit: d.cascade.fit_mode,
            method: d.shadow.method,
            bias: d.shadow.depth_bias,
            faces: d.maps.shadow_faces,
            receiver_plane: d.shadow.receiver_plane,
            blur: d.maps.moment_blur,
            moment_bits: d.maps.moment_bits,
            moments_from: d.maps.moments_from,
            moment_resolve: d.maps.moment_resolve,
            moment_samples: d.maps.moment_samples,
            depth: d.maps.shadow_depth,
            bias_scale: d.shadow.bias_scale,
            contact: d.shadow.contact_shadows,
            sun_maps: d.maps.sun_maps,
            light_maps: d.maps.light_maps,
            bevy_like: false,
        }
    }

    /// `base` with this configuration's shadow settings.
    pub fn settings(&self, base: &Settings) -> Settings {
        if self.bevy_like {
            return bevy_like(base).with(|s| s.shadow.contact_shadows = self.contact);
        }
        base.clone().with(|s| {
            s.maps.shadow_map_size = self.map_size;
            s.cascade.cascades = self.cascades;
            s.cascade.fit_mode = self.fit;
            s.shadow.method = self.method;
            s.shadow.depth_bias = self.bias;
            s.shadow.slope_bias = self.bias;
            s.shadow.normal_bias = self.bias;
            s.maps.shadow_faces = self.faces;
            s.shadow.receiver_plane = self.receiver_plane;
            s.maps.moment_blur = self.blur;
            s.maps.moment_bits = self.moment_bits;
            s.maps.moments_from = self.moments_from;
            s.maps.moment_resolve = self.moment_resolve;
            s.maps.moment_samples = self.moment_samples;
            s.maps.shadow_depth = self.depth;
            s.shadow.bias_scale = self.bias_scale;
            s.maps.shadow_memory = self.memory_mib();
            s.shadow.contact_shadows = self.contact;
            s.maps.sun_maps = self.sun_maps;
            s.maps.light_maps = self.light_maps;
        })
    }

    /// Shadow memory in MiB that holds sixteen layers at this configuration's map size with
    /// their static copies (at least the default): a sweep's map size is then what the sun's
    /// cascades get, and no light's tile is halved for want of room.
    pub fn memory_mib(&self) -> u32 {
        let size = u64::from(self.map_size);
        let bytes = 16 * size * size * u64::from(self.texel_bytes() + 4);
        (bytes.div_ceil(1 << 20) as u32)
            .clamp(Settings::default().maps.shadow_memory, crate::settings::MAX_SHADOW_MEMORY)
    }

    /// Bytes a texel of one layer takes: the depth map's, and the colour map's where its method
    /// reads one (moments at the bits they get where full floats exist, shared among the depth
    /// texels a moment texel covers, at least a byte).
    pub fn texel_bytes(&self) -> u32 {
        let depth = match self.depth {
            ShadowDepth::Float32 => 4,
            ShadowDepth::Unorm16 => 2,
        };
        let channels = self.method.moment_count();
        let colour_bits = match (self.method.moments(), self.moment_bits) {
            (false, _) => self.method.colour_depth_bits(),
            (true, MomentBits::Auto) => channels * self.method.moment_bits(),
            (true, MomentBits::Half) => channels * 16,
            (true, MomentBits::Full) => channels * 32,
        };
        let scale = self.moments_from.colour_scale(self.method.colour_depth_bits() > 0);
        depth + (colour_bits / 8).div_ceil(scale * scale)
    }

    /// What it changes of the depth comparison: the depth format, the multiplicative offset.
    fn depth_label(&self) -> String {
        let d = Config::default_settings();
        let mut out = String::new();
        if self.depth != d.depth {
            out += &format!(" {}", self.depth.name());
        }
        if self.bias_scale != d.bias_scale {
            out += &format!(" s{}", self.bias_scale);
        }
        out
    }

    /// The device can draw it: R32F and explicit 32-bit moments need full floats, moments
    /// from multisampled depth a sample count among `sample_counts`
    /// ([`crate::render::sample_counts`]).
    pub fn supported(&self, full_floats: bool, sample_counts: u32) -> bool {
        let floats = full_floats
            || !(self.method.colour_depth_bits() > 16 || self.method.moments() && self.moment_bits == MomentBits::Full);
        floats && (self.moment_samples == 1 || sample_counts & self.moment_samples != 0)
    }

    /// This configuration as an adapter that is a software rasterizer (`software`) or not runs
    /// it: an `auto` moment resolve replaced by the way auto picks there.
    #[must_use]
    pub fn as_run(&self, software: bool) -> Config {
        let compute = self.moment_resolve.compute(software);
        Config { moment_resolve: if compute { MomentResolve::Compute } else { MomentResolve::Passes }, ..*self }
    }

    /// How its moment maps are made (blur radius, bits, source when not the default), for
    /// moment methods only.
    fn moment_label(&self) -> String {
        if !self.method.moments() {
            return String::new();
        }
        let bits = if self.moment_bits == MomentBits::Auto {
            String::new()
        } else {
            format!(" {}-bit", self.moment_bits.name())
        };
        let d = Config::default_settings();
        let from =
            if self.moments_from == d.moments_from { String::new() } else { format!(" {}", self.moments_from.name()) };
        let resolve = if self.moments_from.from_depth() && self.moment_resolve != d.moment_resolve {
            format!(" {}", self.moment_resolve.name())
        } else {
            String::new()
        };
        let samples = if self.moments_from.from_depth() && self.moment_samples != d.moment_samples {
            format!(" msaa{}", self.moment_samples)
        } else {
            String::new()
        };
        format!(" blur{}{bits}{from}{samples}{resolve}", self.blur)
    }

    /// Its family for the charts and the summary: the method's, or the baseline's own.
    pub fn family(&self) -> &'static str {
        match (self.bevy_like, self.sun_maps, self.light_maps) {
            (true, _, _) => BEVY_FAMILY,
            (false, SunMaps::Virtual, _) | (false, _, LightMaps::Virtual) => VIRTUAL_FAMILY,
            (false, SunMaps::Cascades, LightMaps::Atlas) => self.method.family(),
        }
    }

    /// How the sun's maps are laid out, as labels start: `2048 x4` for cascades (with the fit
    /// when it is not the default's), `virtual` for pages; `+ virtual lights` follows where spot
    /// and point lights are paged.
    fn sun_label(&self, full: bool) -> String {
        let spots = if self.light_maps == LightMaps::Virtual { " + virtual lights" } else { "" };
        self.sun_maps_label(full) + spots
    }

    /// The sun's part of [`Config::sun_label`].
    fn sun_maps_label(&self, full: bool) -> String {
        let d = Config::default_settings();
        match self.sun_maps {
            SunMaps::Virtual => "virtual".into(),
            SunMaps::Cascades if full => format!("{} x{} {}", self.map_size, self.cascades, self.fit.name()),
            SunMaps::Cascades if self.fit != d.fit => {
                format!("{} x{} {}", self.map_size, self.cascades, self.fit.name())
            }
            SunMaps::Cascades => format!("{} x{}", self.map_size, self.cascades),
        }
    }

    /// Its name for charts: map size and cascades, then only what differs from the defaults.
    pub fn short_label(&self) -> String {
        let contact = if self.contact { " contact" } else { "" };
        if self.bevy_like {
            return format!("bevy-like{contact}");
        }
        let d = Config::default_settings();
        let mut out = self.sun_label(false);
        if self.method != d.method {
            out += &format!(" {}", self.method.name());
        }
        if self.bias != d.bias {
            out += &format!(" b{}", self.bias);
        }
        if self.faces != d.faces {
            out += &format!(" {}", self.faces.name());
        }
        if !self.receiver_plane {
            out += " flat";
        }
        out + &self.depth_label() + &self.moment_label() + contact
    }

    /// A short name: `2048 x4 stable bilinear b1`, with `back` when only back faces are drawn and
    /// `flat` when filters compare with the centre's depth, not the receiver's plane.
    pub fn label(&self) -> String {
        let contact = if self.contact { " contact" } else { "" };
        if self.bevy_like {
            return format!("bevy-like (2048 x4 gauss5, 0.02 m + 1.8 texels normal){contact}");
        }
        let faces = if self.faces == ShadowFaces::Back { " back" } else { "" };
        let flat = if self.receiver_plane { "" } else { " flat" };
        format!(
            "{} {} b{}{faces}{flat}{}{}{contact}",
            self.sun_label(true),
            self.method.name(),
            self.bias,
            self.depth_label(),
            self.moment_label()
        )
    }
}

/// The configurations swept: map size against cascades at the defaults, then each other
/// choice varied on its own around the defaults. `quick` takes a few of them.
pub fn configs(quick: bool) -> Vec<Config> {
    let d = Config::default_settings();
    let mut out = Vec::new();
    let mut push = |c: Config| {
        if !out.contains(&c) {
            out.push(c);
        }
    };
    let (sizes, cascades): (&[u32], &[u32]) =
        if quick { (&[1024, 2048], &[1, 4]) } else { (&[512, 1024, 2048, 4096], &[1, 2, 3, 4]) };
    for &map_size in sizes {
        for &c in cascades {
            push(Config { map_size, cascades: c, ..d });
        }
    }
    let around: &[u32] = if quick { &[2048] } else { &[1024, 2048, 4096] };
    for &map_size in around {
        for fit in [FitMode::Unsnapped, FitMode::Tight, FitMode::Sdsm] {
            push(Config { map_size, fit, ..d });
        }
        // Moment maps (on the software rasterizer one frame takes seconds) and planar shadows
        // (no map: one row) only at the default size: every method once there, which the
        // gallery's captions read.
        let here = |m: &ShadowMethod| map_size == d.map_size || !(m.moments() || *m == ShadowMethod::Planar);
        for &method in ShadowMethod::ALL.iter().filter(|m| here(m)) {
            push(Config { map_size, method, ..d });
        }
    }
    // VSM drawn as a colour target, and a moment map at half the depth map's side resolved both
    // ways: what the quick sweep takes of the ways to make them.
    push(Config { method: ShadowMethod::Vsm, moments_from: MomentSource::Colour, ..d });
    for moment_resolve in [MomentResolve::Compute, MomentResolve::Passes] {
        push(Config { method: ShadowMethod::Vsm, moments_from: MomentSource::Half, moment_resolve, ..d });
    }
    // And at half its side from depth drawn there with 4x MSAA (the four samples every device
    // allows): a moment texel of four samples, as depth/2's, from a quarter of the raster. VSM,
    // and EVSM with both warps and with the positive one alone, which the bleeding cases tell
    // apart (the cheapest moment maps on a software rasterizer).
    for method in [ShadowMethod::Vsm, ShadowMethod::Evsm, ShadowMethod::Evsm2] {
        push(Config { method, moments_from: MomentSource::Half, moment_samples: 4, ..d });
    }
    // Moment maps drawn as colour targets, and resolved from the depth map at a half and a
    // quarter of its side (the full sweep only).
    if !quick {
        for &method in ShadowMethod::ALL.iter().filter(|m| m.moments()) {
            for moments_from in [MomentSource::Colour, MomentSource::Half, MomentSource::Quarter] {
                push(Config { method, moments_from, ..d });
            }
        }
        // 4x MSAA at full size and at a quarter of the side for VSM, at half the side for MSM.
        for moments_from in [MomentSource::Depth, MomentSource::Quarter] {
            push(Config { method: ShadowMethod::Vsm, moments_from, moment_samples: 4, ..d });
        }
        push(Config { method: ShadowMethod::Msm, moments_from: MomentSource::Half, moment_samples: 4, ..d });
        // Both ways of resolving at full size, whichever auto picks here.
        for moment_resolve in [MomentResolve::Compute, MomentResolve::Passes] {
            push(Config { method: ShadowMethod::Vsm, moments_from: MomentSource::Depth, moment_resolve, ..d });
        }
    }
    // Moment maps: half floats against full, and a narrower and a wider blur.
    if !quick {
        for &method in ShadowMethod::ALL.iter().filter(|m| m.moments()) {
            push(Config { method, moment_bits: MomentBits::Half, ..d });
        }
        for blur in [1, 4] {
            push(Config { method: ShadowMethod::Msm, blur, ..d });
        }
    }
    // Depth formats: 16-bit fixed point, and the source articles' multiplicative offset on its
    // own (seed 001's `depth × 0.95`, with R32F as it kept depth, and with the depth map).
    push(Config { depth: ShadowDepth::Unorm16, ..d });
    if !quick {
        push(Config { method: ShadowMethod::DepthR32f, bias: 0.0, bias_scale: 0.05, ..d });
        for bias_scale in [0.01, 0.05] {
            push(Config { bias: 0.0, bias_scale, ..d });
        }
    }
    // What the receiver plane does for the grid filters: the same without it.
    for method in [ShadowMethod::Pcf3, ShadowMethod::Pcf5] {
        push(Config { method, receiver_plane: false, ..d });
    }
    let biases: &[f32] = if quick { &[0.0] } else { &[0.0, 0.25, 1.0, 2.0, 4.0] };
    for &bias in biases {
        push(Config { bias, ..d });
    }
    push(Config { faces: ShadowFaces::Back, bias: 0.0, ..d });
    push(Config { bevy_like: true, ..d });
    // Virtual maps for the sun: the default method, and in the full sweep every depth method;
    // and every light's maps virtual, at the default method.
    use ShadowMethod::*;
    let paged: &[ShadowMethod] =
        if quick { &[Bilinear] } else { &[Nearest, Bilinear, Pcf3, Pcf5, Gauss5, Poisson32, Pcss] };
    for &method in paged {
        push(Config { method, sun_maps: SunMaps::Virtual, ..d });
    }
    push(Config { sun_maps: SunMaps::Virtual, light_maps: LightMaps::Virtual, ..d });
    // Contact shadows over the default, a member of every family with a map (two moment maps)
    // and Bevy-like (full sweep only).
    if !quick {
        push(Config { contact: true, ..d });
        let members = [
            ShadowMethod::Pcf5,
            ShadowMethod::Gauss5,
            ShadowMethod::Poisson32,
            ShadowMethod::Pcss,
            ShadowMethod::RadialR16f,
            ShadowMethod::Evsm,
            ShadowMethod::Msm,
        ];
        for method in members {
            push(Config { method, contact: true, ..d });
        }
        push(Config { bevy_like: true, contact: true, ..d });
    }
    if !quick {
        push(Config { faces: ShadowFaces::Back, ..d });
    }
    out
}

/// `configs` less each that runs as an earlier one does on an adapter that is a software
/// rasterizer (`software`) or not: an explicit moment resolve naming what auto picks there
/// measures its auto twin again.
#[must_use]
pub fn distinct_as_run(configs: Vec<Config>, software: bool) -> Vec<Config> {
    let mut seen = Vec::new();
    configs
        .into_iter()
        .filter(|c| {
            let run = c.as_run(software);
            let new = !seen.contains(&run);
            seen.push(run);
            new
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn configurations_are_distinct_and_include_the_defaults() {
        for quick in [true, false] {
            let c = configs(quick);
            assert!(c.contains(&Config::default_settings()));
            for (i, a) in c.iter().enumerate() {
                assert!(c[i + 1..].iter().all(|b| b != a), "{} twice", a.label());
                a.settings(&Settings::default()).validate().unwrap();
            }
        }
        assert!(configs(true).len() < configs(false).len());
        assert_eq!(Config::default_settings().label(), "2048 x4 stable bilinear b0.5");
        let c = Config { method: ShadowMethod::Pcf3, bias: 2.0, ..Config::default_settings() };
        assert_eq!(c.short_label(), "2048 x4 pcf3 b2");
        let c = Config { depth: ShadowDepth::Unorm16, bias_scale: 0.05, ..Config::default_settings() };
        assert_eq!(c.label(), "2048 x4 stable bilinear b0.5 d16 s0.05");
        let paged = Config { sun_maps: SunMaps::Virtual, method: ShadowMethod::Pcf5, ..Config::default_settings() };
        assert_eq!((paged.label(), paged.short_label()), ("virtual pcf5 b0.5".into(), "virtual pcf5".into()));
        assert_eq!(paged.family(), VIRTUAL_FAMILY);
        assert_eq!(paged.settings(&Settings::default()).maps.sun_maps, SunMaps::Virtual);
        assert!(configs(true).iter().any(|c| c.sun_maps == SunMaps::Virtual), "the quick sweep has virtual maps");
    }

    #[test]
    fn both_sweeps_take_every_method_at_the_default_settings() {
        // The gallery captions each picture from a run: each method at the default settings.
        for quick in [true, false] {
            let c = configs(quick);
            for &method in ShadowMethod::ALL {
                let at_default = Config { method, ..Config::default_settings() };
                assert!(c.contains(&at_default), "{} (quick: {quick})", at_default.label());
            }
        }
    }

    #[test]
    fn contact_shadows_are_swept_with_every_family_that_has_a_map() {
        let all = configs(false);
        for method in ShadowMethod::ALL.iter().filter(|m| **m != ShadowMethod::Planar) {
            let family = method.family();
            assert!(all.iter().any(|c| c.contact && !c.bevy_like && c.method.family() == family), "{family}");
        }
        assert!(all.iter().any(|c| c.contact && c.bevy_like));
        assert!(configs(true).iter().all(|c| !c.contact), "the quick sweep leaves them out");
    }

    #[test]
    fn a_resolve_named_as_auto_picks_it_is_measured_once() {
        let all = configs(false);
        let d = Config::default_settings();
        let vsm = |moment_resolve| Config {
            method: ShadowMethod::Vsm,
            moments_from: MomentSource::Half,
            moment_resolve,
            ..d
        };
        assert!(
            [MomentResolve::Auto, MomentResolve::Compute, MomentResolve::Passes].iter().all(|&r| all.contains(&vsm(r)))
        );
        for (software, twin, other) in [
            (false, MomentResolve::Compute, MomentResolve::Passes),
            (true, MomentResolve::Passes, MomentResolve::Compute),
        ] {
            let kept = distinct_as_run(all.clone(), software);
            // Auto and the resolve it picks here: the first of the two kept, the other way too.
            let twins = [vsm(MomentResolve::Auto), vsm(twin)].iter().filter(|c| kept.contains(c)).count();
            assert_eq!(twins, 1, "software {software}: auto and its explicit twin both measured");
            assert!(kept.contains(&vsm(other)));
            // Only twins go: every configuration that runs differently stays, in order.
            let runs: Vec<Config> = all.iter().map(|c| c.as_run(software)).collect();
            let distinct = runs.iter().enumerate().filter(|(i, r)| !runs[..*i].contains(r)).count();
            assert_eq!(kept.len(), distinct);
            assert_eq!(kept[0], all[0]);
        }
    }

    #[test]
    fn a_texel_costs_its_depth_and_its_colour_map() {
        let d = Config::default_settings();
        assert_eq!(d.texel_bytes(), 4);
        assert_eq!(Config { depth: ShadowDepth::Unorm16, ..d }.texel_bytes(), 2);
        assert_eq!(Config { method: ShadowMethod::RadialR16f, ..d }.texel_bytes(), 6);
        assert_eq!(Config { method: ShadowMethod::DepthR32f, ..d }.texel_bytes(), 8);
        assert_eq!(Config { method: ShadowMethod::Vsm, ..d }.texel_bytes(), 12);
        assert_eq!(Config { method: ShadowMethod::Evsm, ..d }.texel_bytes(), 12);
        assert_eq!(Config { method: ShadowMethod::Evsm2, ..d }.texel_bytes(), 8);
        assert_eq!(Config { method: ShadowMethod::Msm, ..d }.texel_bytes(), 20);
        // Resolved at half the side, four depth texels share a moment texel.
        let half = Config { method: ShadowMethod::Msm, moments_from: MomentSource::Half, ..d };
        assert_eq!(half.texel_bytes(), 4 + 4);
        assert!(!Config { method: ShadowMethod::DepthR32f, ..d }.supported(false, 4));
        assert!(Config { method: ShadowMethod::Vsm, ..d }.supported(false, 4));
        let msaa = Config { method: ShadowMethod::Vsm, moment_samples: 4, ..d };
        assert!(msaa.supported(true, 4) && !msaa.supported(true, 0) && !msaa.supported(true, 2 | 8));
    }
}
