//! Settings, by concern: the scene's (used once, when the app is made), the shadows' (how maps
//! are tested and filtered), the maps' (memory, sizes, drawing and keeping), the cascades' and
//! the view's. Each group checks its own values where it is defined; [`Settings`] holds one of
//! each, as the command line and the bench build them, and the app keeps each per-frame group as
//! a resource of its own, so a system reads only the groups it needs.

use crate::components::ShadowMethod;
use bevy_ecs::prelude::*;

mod cascade;
mod lights;
mod maps;
mod moments;
mod scene;
mod shadow;
mod view;
pub use cascade::{CascadeSettings, DEFAULT_SPLIT_LAMBDA};
pub use lights::{LightBiases, LightSetting};
pub use maps::*;
pub use moments::{MomentBits, MomentResolve, MomentSource};
pub use scene::{MAX_CUBES, SceneSettings};
pub use shadow::*;
pub use view::{DEFAULT_TOON_BANDS, MAX_TOON_BANDS, ViewSettings};

/// Every setting, one group per concern; [`Settings::validate`] rejects nonsense before it
/// reaches the GPU.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Settings {
    /// What the scene holds and where it starts: used when the app is made, then never again.
    pub scene: SceneSettings,
    /// Whether and how shadows are tested and filtered.
    pub shadow: ShadowSettings,
    /// The shadow memory, and how maps are sized, drawn, kept and made.
    pub maps: MapSettings,
    /// How the sun's cascades cover the view.
    pub cascade: CascadeSettings,
    /// How the picture is shaded and what it shows to explain itself.
    pub view: ViewSettings,
}

/// The groups a frame is drawn with, borrowed from the world that holds them (what the renderer
/// reads, without copying them).
#[derive(Clone, Copy, Debug)]
pub struct FrameSettings<'w> {
    /// Whether and how shadows are tested and filtered.
    pub shadow: &'w ShadowSettings,
    /// The shadow memory, and how maps are sized, drawn, kept and made.
    pub maps: &'w MapSettings,
    /// How the sun's cascades cover the view.
    pub cascade: &'w CascadeSettings,
    /// How the picture is shaded and what it shows to explain itself.
    pub view: &'w ViewSettings,
}

impl<'w> FrameSettings<'w> {
    /// The groups `world` holds; `None` if it lacks one (a world not made by [`crate::App`]).
    #[must_use]
    pub fn of(world: &'w World) -> Option<FrameSettings<'w>> {
        Some(FrameSettings {
            shadow: world.get_resource()?,
            maps: world.get_resource()?,
            cascade: world.get_resource()?,
            view: world.get_resource()?,
        })
    }
}

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

/// One group of settings: a resource of its own that checks its own values.
pub trait SettingsGroup: Resource + Clone + PartialEq {
    /// Checks every setting of the group; the first bad one is named in the error.
    fn validate(&self) -> Result<(), SettingsError>;

    /// Puts the group in force in `world` if it is valid (refused, with nothing changed, if not).
    /// A group equal to the one the world holds is left alone, so systems that watch it for
    /// changes do not see one.
    fn put(&self, world: &mut World) -> Result<(), SettingsError> {
        self.validate()?;
        if world.get_resource::<Self>() != Some(self) {
            world.insert_resource(self.clone());
        }
        Ok(())
    }
}

/// The error for setting `name`, whose `value` is not what it must be (`why`).
fn bad(name: &'static str, value: impl ToString, why: &'static str) -> Result<(), SettingsError> {
    Err(SettingsError { name, value: value.to_string(), why })
}

impl Settings {
    /// These settings with `change` made to them: `Settings::default().with(|s| s.maps.shadow_map_size = 512)`.
    #[must_use]
    pub fn with(mut self, change: impl FnOnce(&mut Settings)) -> Settings {
        change(&mut self);
        self
    }

    /// Checks every group; the first bad setting is named in the error.
    pub fn validate(&self) -> Result<(), SettingsError> {
        self.shadow.validate()?;
        self.maps.validate()?;
        self.cascade.validate()?;
        self.view.validate()?;
        self.scene.validate()
    }

    /// Why the lights' maps cannot be what the settings ask for: virtual maps are pages of
    /// depth, which a method reading a colour map (moments, depth in colour) or planar shadows
    /// cannot use (such a light keeps its cascades or its tile). None when they can.
    #[must_use]
    pub fn pages_refused(&self) -> Option<String> {
        (self.maps.paged() && !self.shadow.method.pages()).then(|| {
            format!(
                "virtual shadow maps are pages of depth, and {} reads {}: moment maps, depth in colour and \
                 planar shadows stay on the atlas's tiles. Choose a depth method (nearest, bilinear, pcf3, pcf5, \
                 gauss5, poisson16, poisson32, pcss), or --sun-maps cascades and --light-maps atlas",
                self.shadow.method.name(),
                if self.shadow.method == ShadowMethod::Planar { "no map" } else { "a colour map" }
            )
        })
    }

    /// Puts each group in force in `world` as a resource of its own ([`SettingsGroup::put`]),
    /// or refuses them all, with nothing changed, if one is out of range.
    pub fn put(&self, world: &mut World) -> Result<(), SettingsError> {
        self.validate()?;
        self.scene.put(world)?;
        self.shadow.put(world)?;
        self.maps.put(world)?;
        self.cascade.put(world)?;
        self.view.put(world)
    }

    /// The groups `world` holds (each group's defaults where it holds none): a copy, to read or
    /// to change and put back, not a thing for every frame.
    #[must_use]
    pub fn from_world(world: &World) -> Settings {
        fn get<R: Resource + Clone + Default>(world: &World) -> R {
            world.get_resource::<R>().cloned().unwrap_or_default()
        }
        Settings { scene: get(world), shadow: get(world), maps: get(world), cascade: get(world), view: get(world) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shadow::FitMode;

    #[test]
    fn cube_faces_reach_as_far_as_every_method_samples() {
        for m in ShadowMethod::ALL {
            assert!(m.reach() <= CUBE_MARGIN, "{m:?} reaches {} texels", m.reach());
        }
    }

    #[test]
    fn virtual_sun_maps_refuse_a_method_without_depth_maps_by_name() {
        let virtual_with =
            |method| Settings::default().with(|s| (s.maps.sun_maps, s.shadow.method) = (SunMaps::Virtual, method));
        let why = virtual_with(ShadowMethod::Vsm).pages_refused().unwrap();
        assert!(why.contains("vsm reads a colour map") && why.contains("--sun-maps cascades"), "{why}");
        assert!(virtual_with(ShadowMethod::Planar).pages_refused().unwrap().contains("planar reads no map"));
        assert_eq!(virtual_with(ShadowMethod::Pcss).pages_refused(), None);
        assert_eq!(Settings::default().with(|s| s.shadow.method = ShadowMethod::Vsm).pages_refused(), None);
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
        let cases: [Case; 35] = [
            (|s| s.maps.spot_map_limit = 0.0, "spot_map_limit"),
            (|s| s.shadow.depth_bias_metres = -1.0, "depth_bias_metres"),
            (|s| s.cascade.first_cascade_far = Some(1000.0), "first_cascade_far"),
            (|s| s.shadow.contact_steps = 0, "contact_steps"),
            (|s| s.shadow.contact_length = f32::INFINITY, "contact_length"),
            (|s| s.shadow.contact_thickness = 0.0, "contact_thickness"),
            (|s| s.scene.cubes = MAX_CUBES + 1, "cubes"),
            (|s| s.scene.lanterns = 5000, "lanterns"),
            (|s| s.scene.camera = Some((glam::Vec3::ONE, glam::Vec3::ONE)), "camera"),
            (|s| s.shadow.bias_scale = 0.9, "bias_scale"),
            (|s| s.view.toon_bands = 1, "toon_bands"),
            (|s| s.maps.moment_blur = 99, "moment_blur"),
            (|s| s.maps.moment_samples = 3, "moment_samples"),
            (|s| s.maps.moment_samples = 0, "moment_samples"),
            (|s| s.maps.page_bias = f32::NAN, "page_bias"),
            (|s| s.maps.page_bias = 5.0, "page_bias"),
            (|s| s.maps.page_memory = 0, "page_memory"),
            (|s| s.maps.page_memory = 200, "page_memory"),
            (|s| s.shadow.light_bleeding = f32::NAN, "light_bleeding"),
            (|s| s.cascade.cascades = 5, "cascades"),
            (|s| s.cascade.split_lambda = -0.1, "split_lambda"),
            (|s| s.cascade.cascade_blend = 0.9, "cascade_blend"),
            (|s| s.shadow.shadow_strength = 2.0, "shadow_strength"),
            (|s| s.maps.shadow_map_size = 0, "shadow_map_size"),
            (|s| s.maps.shadow_memory = 8, "shadow_memory"),
            (|s| s.maps.shadow_memory = u32::MAX, "shadow_memory"),
            (|s| s.maps.shadow_updates = 5, "shadow_updates"),
            (|s| s.maps.max_stale = 0, "max_stale"),
            (|s| s.maps.tile_hysteresis = f32::NAN, "tile_hysteresis"),
            (|s| s.shadow.slope_bias = f32::NAN, "slope_bias"),
            (|s| s.cascade.shadow_distance = -1.0, "shadow_distance"),
            (|s| s.view.ambient = f32::INFINITY, "ambient"),
            (|s| s.scene.dt = 0.0, "dt"),
            (|s| s.scene.exposure = 0.0, "exposure"),
            (|s| (s.scene.model, s.scene.file) = (Some("a.glb".into()), Some("b.gltf".into())), "model"),
        ];
        for (break_it, name) in cases {
            let mut s = Settings::default();
            break_it(&mut s);
            let err = s.validate().unwrap_err();
            assert_eq!(err.name, name);
            assert!(err.to_string().contains(name));
        }
        let mut s = Settings::default().with(|s| s.scene.cubes = MAX_CUBES + 1);
        assert!(s.validate().unwrap_err().to_string().contains(&MAX_CUBES.to_string()), "the limit is named");
        s.scene.cubes = MAX_CUBES;
        assert_eq!(s.validate(), Ok(()));
    }

    #[test]
    fn a_group_is_put_in_force_only_when_valid_and_changed() {
        let mut world = World::new();
        Settings::default().put(&mut world).unwrap();
        let bad = MapSettings { shadow_map_size: 0, ..MapSettings::default() };
        assert_eq!(bad.put(&mut world).unwrap_err().name, "shadow_map_size");
        assert_eq!(*world.resource::<MapSettings>(), MapSettings::default(), "nothing changed");
        let all_bad = Settings::default().with(|s| (s.shadow.method, s.view.ambient) = (ShadowMethod::Pcf5, -1.0));
        assert_eq!(all_bad.put(&mut world).unwrap_err().name, "ambient");
        assert_eq!(Settings::from_world(&world), Settings::default(), "no group of a refused set changed");
        // A group put again unchanged is not seen as changed by the systems that watch it.
        let watch = world.register_system(|m: Res<MapSettings>| m.is_changed());
        let changed = |world: &mut World| world.run_system(watch).unwrap();
        assert!(changed(&mut world), "new to the world");
        MapSettings::default().put(&mut world).unwrap();
        assert!(!changed(&mut world));
        MapSettings { shadow_map_size: 512, ..MapSettings::default() }.put(&mut world).unwrap();
        assert!(changed(&mut world));
    }
}
