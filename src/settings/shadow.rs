//! The shadows' settings: whether lights cast shadows, how dark, and how every light without
//! settings of its own tests and filters its maps.

use super::{SettingsError, SettingsGroup, bad};
use crate::components::{ShadowBias, ShadowMethod};
use bevy_ecs::prelude::*;

/// How a shadow is tested where the maps are read, for every light without its own.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct ShadowSettings {
    /// Draw shadows at all.
    pub enabled: bool,
    /// How dark a full shadow is: 0 = no darkening, 1 = only ambient light remains.
    pub shadow_strength: f32,
    /// How shadow maps are sampled, for every light without a method of its own.
    pub method: ShadowMethod,
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
    /// Filters compare each of their taps with the depth the receiver's plane has there
    /// (receiver-plane depth bias), not with the depth at the lookup's centre (off shows the
    /// "soft acne" of wide kernels on lit slopes).
    pub receiver_plane: bool,
    /// PCSS searches for blockers and sizes its filter by their distance (off: a fixed kernel,
    /// the Poisson 32 one, which loses contact hardening).
    pub pcss_blocker_search: bool,
    /// How much of the bound a variance or moment map gives is cut away as light bleeding (0:
    /// none; the rest is stretched over 0..1).
    pub light_bleeding: f32,
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
    /// Lights that keep their shadow maps also draw planar shadows onto the ground, which then
    /// takes those instead of the maps (lights whose method is planar always do).
    pub planar_ground: bool,
}

/// Steps of the contact-shadow march by default (Bevy's; Filament takes 8).
pub const DEFAULT_CONTACT_STEPS: u32 = 16;
/// Most steps of the contact-shadow march.
pub const MAX_CONTACT_STEPS: u32 = 64;
/// Length of the contact-shadow march by default, in metres (Bevy's and Filament's).
pub const DEFAULT_CONTACT_LENGTH: f32 = 0.3;
/// Thickness the contact-shadow march takes surfaces to have by default, in metres.
pub const DEFAULT_CONTACT_THICKNESS: f32 = 0.1;
/// Default light-bleeding reduction.
pub const DEFAULT_LIGHT_BLEEDING: f32 = 0.2;
/// Largest multiplicative depth offset (half the distance to the light).
pub const MAX_BIAS_SCALE: f32 = 0.5;
/// Why a bias term in texels was refused ([`crate::components::ShadowBias::MAX_TEXELS`]).
const BIAS_TEXELS_WHY: &str = "must be between 0 and 100 texels";

impl Default for ShadowSettings {
    fn default() -> Self {
        ShadowSettings {
            enabled: true,
            shadow_strength: 1.0,
            method: ShadowMethod::Bilinear,
            // The same as a light's default bias (see `ShadowBias::default`).
            depth_bias: 0.5,
            slope_bias: 0.5,
            normal_bias: 0.5,
            bias_scale: 0.0,
            depth_bias_metres: 0.0,
            receiver_plane: true,
            pcss_blocker_search: true,
            light_bleeding: DEFAULT_LIGHT_BLEEDING,
            contact_shadows: false,
            contact_steps: DEFAULT_CONTACT_STEPS,
            contact_length: DEFAULT_CONTACT_LENGTH,
            contact_thickness: DEFAULT_CONTACT_THICKNESS,
            planar_ground: false,
        }
    }
}

impl ShadowSettings {
    /// The bias every light without its own gets from these settings.
    #[must_use]
    pub fn shadow_bias(&self) -> ShadowBias {
        ShadowBias {
            constant: self.depth_bias,
            slope: self.slope_bias,
            normal: self.normal_bias,
            scale: self.bias_scale,
            receiver_plane: self.receiver_plane,
        }
    }
}

impl SettingsGroup for ShadowSettings {
    /// Checks every setting of the shadows; the first bad one is named in the error.
    fn validate(&self) -> Result<(), SettingsError> {
        let non_negative = |x: f32| x.is_finite() && x >= 0.0;
        if !(self.shadow_strength.is_finite() && (0.0..=1.0).contains(&self.shadow_strength)) {
            return bad("shadow_strength", self.shadow_strength, "must be between 0 and 1");
        }
        for (name, v) in
            [("depth_bias", self.depth_bias), ("slope_bias", self.slope_bias), ("normal_bias", self.normal_bias)]
        {
            if !ShadowBias::texels_ok(v) {
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
        if !(1..=MAX_CONTACT_STEPS).contains(&self.contact_steps) {
            return bad("contact_steps", self.contact_steps, "must be between 1 and 64");
        }
        if !(self.contact_length.is_finite() && (0.0..=10.0).contains(&self.contact_length)) {
            return bad("contact_length", self.contact_length, "must be between 0 and 10 metres");
        }
        if !(self.contact_thickness.is_finite() && self.contact_thickness > 0.0 && self.contact_thickness <= 10.0) {
            return bad("contact_thickness", self.contact_thickness, "must be more than 0 and at most 10 metres");
        }
        if !(self.light_bleeding.is_finite() && (0.0..=0.9).contains(&self.light_bleeding)) {
            return bad("light_bleeding", self.light_bleeding, "must be a fraction between 0 and 0.9");
        }
        Ok(())
    }
}

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
