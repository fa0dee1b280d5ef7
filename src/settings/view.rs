//! The view's settings: what the picture shows besides the shadows themselves, the lab's aids
//! among them.

use super::{SettingsError, SettingsGroup, bad};
use bevy_ecs::prelude::*;

/// How the picture is shaded and what it shows to explain itself.
#[derive(Resource, Clone, Debug, PartialEq)]
pub struct ViewSettings {
    /// Ambient light level (0..1) that reaches every surface.
    pub ambient: f32,
    /// Toon shading: each light's diffuse strength falls into this many bands, and a shadow
    /// takes a surface one band down (0: Phong shading).
    pub toon_bands: u32,
    /// The ground shows a faint 1 m checker, so stair-steps, acne and shimmer are easy to see
    /// (the picture only: the measuring view and the truth never see it).
    pub ground_grid: bool,
    /// Tint each cascade in its own colour to show where it is used.
    pub cascade_debug: bool,
    /// Shows, in place of the shading, how many shadow-map texels of the light so named fall
    /// on each screen pixel (Lloyd et al.'s aliasing measure).
    pub texel_density: Option<String>,
    /// Draws each shadowed light's layers (cascade boxes, spot and cube-face frusta) as lines.
    pub light_volumes: bool,
}

/// Bands of toon shading when it is turned on without a number (key T).
pub const DEFAULT_TOON_BANDS: u32 = 4;
/// Most bands of toon shading.
pub const MAX_TOON_BANDS: u32 = 16;

impl Default for ViewSettings {
    fn default() -> Self {
        ViewSettings {
            ambient: 0.12,
            toon_bands: 0,
            ground_grid: true,
            cascade_debug: false,
            texel_density: None,
            light_volumes: false,
        }
    }
}

impl SettingsGroup for ViewSettings {
    /// Checks every setting of the view; the first bad one is named in the error.
    fn validate(&self) -> Result<(), SettingsError> {
        if self.toon_bands == 1 || self.toon_bands > MAX_TOON_BANDS {
            return bad("toon_bands", self.toon_bands, "must be 0 (Phong) or between 2 and 16 bands");
        }
        if !(self.ambient.is_finite() && (0.0..=1.0).contains(&self.ambient)) {
            return bad("ambient", self.ambient, "must be between 0 and 1");
        }
        Ok(())
    }
}
