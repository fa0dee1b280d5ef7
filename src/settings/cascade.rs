//! The cascades' settings: how the sun's shadow is split along the view.

use super::{SettingsError, SettingsGroup, bad};
use crate::shadow::{FitMode, MAX_CASCADES};
use bevy_ecs::prelude::*;

/// How the sun's cascades cover the view.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct CascadeSettings {
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

impl Default for CascadeSettings {
    fn default() -> Self {
        CascadeSettings {
            shadow_distance: 60.0,
            cascades: 4,
            split_lambda: DEFAULT_SPLIT_LAMBDA,
            first_cascade_far: None,
            cascade_blend: 0.1,
            fit_mode: FitMode::Stable,
        }
    }
}

impl SettingsGroup for CascadeSettings {
    /// Checks every setting of the cascades; the first bad one is named in the error.
    fn validate(&self) -> Result<(), SettingsError> {
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
        if !(self.split_lambda.is_finite() && (0.0..=1.0).contains(&self.split_lambda)) {
            return bad("split_lambda", self.split_lambda, "must be between 0 (uniform) and 1 (logarithmic)");
        }
        if !(self.cascade_blend.is_finite() && (0.0..=0.5).contains(&self.cascade_blend)) {
            return bad("cascade_blend", self.cascade_blend, "must be a fraction between 0 and 0.5");
        }
        Ok(())
    }
}

named_choices!(FitMode, "a fit mode", Stable = "stable", Unsnapped = "unsnapped", Tight = "tight", Sdsm = "sdsm");
