//! Each light's own settings as the command line, the panel's command lines and bias files give
//! them, by the light's name: applied to the scene's lights once, when the app starts.

use crate::components::{ShadowBias, ShadowMethod};

/// One of a light's own settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightSetting {
    /// Its own sampling method.
    Method(ShadowMethod),
    /// Its own bias.
    Bias(ShadowBias),
    /// Its size: a sun's disc radius in degrees, a spot's or point light's radius in metres.
    Size(f32),
    /// It casts no shadow.
    NoShadow,
    /// Its shadow test adds contact shadows (or not).
    Contact(bool),
}

/// One bias per light, by the light's name (a bias file's, `umbra tune` writes them).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LightBiases(pub Vec<(String, ShadowBias)>);
