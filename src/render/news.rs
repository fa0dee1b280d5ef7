//! What the renderer learns that the game needs, handed back as plain data: the renderer reads
//! the world and never writes into it; the app takes the news in ([`crate::App::hear`]).

use super::shadow_stats::ShadowStats;
use crate::shadow::{PageMarks, VisibleSamples};
use crate::systems::ShadowCaps;

/// What the renderer learned since the app last heard from it ([`super::Renderer::news`]).
#[derive(Clone, Debug, Default, PartialEq)]
#[must_use = "the app takes it in with App::hear, or it is lost"]
pub struct RenderNews {
    /// What this device keeps of shadows per texel: the app sizes shadow tiles for it.
    pub caps: ShadowCaps,
    /// What the last frame's shadow pass did, if a frame was drawn.
    pub stats: Option<ShadowStats>,
    /// What the camera saw, for the SDSM fit, when a depth reduction came back.
    pub seen: Option<VisibleSamples>,
    /// The pages paged lights' visible pixels asked for, when a marking came back.
    pub marks: Vec<PageMarks>,
    /// Messages for the user, oldest first.
    pub notices: Vec<String>,
}
