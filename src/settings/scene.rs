//! The scene's settings: what the app is made with, applied once when it starts.

use super::{LightBiases, LightSetting, SettingsError, SettingsGroup, bad};
use bevy_ecs::prelude::*;

/// What the scene holds and where it starts. These are used when the app is made
/// ([`crate::App::new`]) and never read again; changing them later changes nothing.
#[derive(Resource, Clone, Debug, PartialEq)]
pub struct SceneSettings {
    /// Number of animated cubes in the sample scene.
    pub cubes: u32,
    /// Shadowed lanterns hung over the sample scene (see [`crate::lanterns`]).
    pub lanterns: u32,
    /// The walking character is in the sample scene.
    pub character: bool,
    /// A glTF model of the user's to place in the middle of the sample scene.
    pub model: Option<std::path::PathBuf>,
    /// A glTF scene of the user's to play instead of the sample scene, with its lights and camera.
    pub file: Option<std::path::PathBuf>,
    /// What a file's lights give in umbra's units per lux (directional) or per candela at 1 m
    /// (point, spot): see [`crate::scene_file`].
    pub exposure: f32,
    /// Where the camera starts (eye, target), instead of the scene's own camera.
    pub camera: Option<(glam::Vec3, glam::Vec3)>,
    /// Settings of their own for the lights so named ("sun", "spot 1", "point 1"): a method, a
    /// bias, a size, no shadow; applied in order when the scene is made, and a name no light has
    /// is an error then.
    pub light_settings: Vec<(String, LightSetting)>,
    /// Per-light biases (as `umbra tune` finds them) that replace the shadow settings' biases,
    /// light by light.
    pub biases: Option<LightBiases>,
    /// Fixed simulation step in seconds.
    pub dt: f32,
}

/// Most animated cubes a scene may hold (the stress scene's ten thousand, with room to spare).
pub const MAX_CUBES: u32 = 100_000;

impl Default for SceneSettings {
    fn default() -> Self {
        SceneSettings {
            cubes: 10,
            lanterns: 0,
            character: true,
            model: None,
            file: None,
            exposure: 1.0,
            camera: None,
            light_settings: Vec::new(),
            biases: None,
            dt: 1.0 / 60.0,
        }
    }
}

impl SettingsGroup for SceneSettings {
    /// Checks every setting of the scene; the first bad one is named in the error.
    fn validate(&self) -> Result<(), SettingsError> {
        if !(self.exposure.is_finite() && (1e-6..=1e6).contains(&self.exposure)) {
            return bad("exposure", self.exposure, "must be a factor between 0.000001 and 1000000");
        }
        if let (Some(model), Some(_)) = (&self.model, &self.file) {
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
