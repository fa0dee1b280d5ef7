//! What the shadow pass did in a frame, per light: layers drawn, kept, left stale by the update
//! budget, blurred, and the calls and static copies they took. The renderer hands it back with its
//! news ([`super::RenderNews`]) and the app keeps it in the world ([`ShadowStats`]) for the title
//! bar, the panel and the bench.

use crate::light::LightLabel;
use bevy_ecs::prelude::*;

/// Shadow passes of one frame: per light, how many layers were drawn and how many kept.
#[derive(Resource, Clone, Debug, Default, PartialEq, Eq)]
pub struct ShadowStats {
    /// One entry per light, in layer order.
    pub lights: Vec<LightPasses>,
    /// Texels of the tiles drawn this frame.
    pub texels: u64,
    /// Moment layers made from depth this frame by the compute dispatch (resolved and blurred
    /// together; see [`crate::settings::MapSettings::moment_resolve`]).
    pub moments_in_compute: u32,
    /// The pages of virtual maps among the layers, every paged light's together.
    pub pages: PagePasses,
}

/// What the shadow pass did with the pages of virtual maps in a frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PagePasses {
    /// Pages drawn this frame (new, or a caster moved through them).
    pub drawn: u32,
    /// Pages kept from an earlier frame (stale ones among them).
    pub kept: u32,
    /// Pages out of date but left waiting by the update budget (sampled as last drawn).
    pub stale: u32,
}

/// One light's shadow passes in a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LightPasses {
    /// Which light.
    pub light: LightLabel,
    /// Layers drawn this frame.
    pub drawn: u32,
    /// Layers whose map was kept from an earlier frame (stale ones among them).
    pub kept: u32,
    /// Layers out of date but left waiting by the update budget (sampled as last drawn).
    pub stale: u32,
    /// Frames the longest waiting of them has waited.
    pub waited: u32,
    /// Moment layers blurred this frame.
    pub blurred: u32,
    /// Draw calls this frame's layers took (an instanced batch is one).
    pub calls: u32,
    /// Layers drawn over a copy of their static map (only their moving casters drawn).
    pub from_static: u32,
}

impl ShadowStats {
    /// Layers drawn this frame, all lights together.
    pub fn drawn(&self) -> u32 {
        self.lights.iter().map(|l| l.drawn).sum()
    }

    /// Layers kept this frame, all lights together.
    pub fn kept(&self) -> u32 {
        self.lights.iter().map(|l| l.kept).sum()
    }

    /// Layers left stale this frame, all lights together.
    pub fn stale(&self) -> u32 {
        self.lights.iter().map(|l| l.stale).sum()
    }

    /// Lights with a layer left stale this frame.
    pub fn stale_lights(&self) -> usize {
        self.lights.iter().filter(|l| l.stale > 0).count()
    }

    /// Frames the longest waiting layer has waited.
    pub fn waited(&self) -> u32 {
        self.lights.iter().map(|l| l.waited).max().unwrap_or(0)
    }

    /// Draw calls of this frame's layers, all lights together.
    pub fn calls(&self) -> u32 {
        self.lights.iter().map(|l| l.calls).sum()
    }

    /// Moment layers blurred this frame, all lights together.
    pub fn blurred(&self) -> u32 {
        self.lights.iter().map(|l| l.blurred).sum()
    }

    /// Counts a layer of `light` (a page of its virtual map, if `page`): drawn or kept, and if it
    /// was left `waits` frames stale.
    pub(super) fn count(&mut self, (light, page): (LightLabel, bool), drawn: bool, waits: Option<u32>) {
        if page {
            let p = &mut self.pages;
            (p.drawn, p.kept, p.stale) =
                (p.drawn + drawn as u32, p.kept + !drawn as u32, p.stale + waits.is_some() as u32);
        }
        if self.lights.last().is_none_or(|l| l.light != light) {
            let zero =
                LightPasses { light, drawn: 0, kept: 0, stale: 0, waited: 0, blurred: 0, calls: 0, from_static: 0 };
            self.lights.push(zero);
        }
        let entry = self.lights.last_mut().expect("pushed above");
        if drawn {
            entry.drawn += 1
        } else {
            entry.kept += 1
        }
        if let Some(frames) = waits {
            entry.stale += 1;
            entry.waited = entry.waited.max(frames);
        }
    }

    pub(super) fn count_texels(&mut self, texels: u64) {
        self.texels += texels;
    }

    /// Layers drawn over a copy of their static map, all lights together.
    pub fn from_static(&self) -> u32 {
        self.lights.iter().map(|l| l.from_static).sum()
    }

    pub(super) fn count_static(&mut self, light: LightLabel, over_static: bool) {
        if let Some(entry) = self.lights.iter_mut().find(|l| l.light == light) {
            entry.from_static += over_static as u32;
        }
    }

    pub(super) fn count_calls(&mut self, light: LightLabel, calls: usize) {
        if let Some(entry) = self.lights.iter_mut().find(|l| l.light == light) {
            entry.calls += calls as u32;
        }
    }

    pub(super) fn count_blur(&mut self, light: LightLabel) {
        if let Some(entry) = self.lights.iter_mut().find(|l| l.light == light) {
            entry.blurred += 1;
        }
    }
}

/// Lights the title lists one by one; past this many it gives totals.
const LISTED: usize = 4;

impl std::fmt::Display for ShadowStats {
    /// "sun 1/3 · spot 1 0/1": layers drawn / kept, per light (all lights together past a few),
    /// then the layers left stale, if any.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.lights.len() <= LISTED {
            for (i, l) in self.lights.iter().enumerate() {
                write!(f, "{}{} {}/{}", if i > 0 { " · " } else { "" }, l.light, l.drawn, l.kept)?;
            }
        } else {
            write!(f, "{}/{} of {} lights", self.drawn(), self.kept(), self.lights.len())?;
        }
        if self.stale() > 0 {
            let (layers, lights, waited) = (self.stale(), self.stale_lights(), self.waited());
            write!(f, " · {layers} stale of {lights} lights (oldest {waited} frames)")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_title_lists_a_few_lights_totals_many_and_names_the_stale() {
        let label = |number| LightLabel { word: "lamp", number, bare: false };
        let mut stats = ShadowStats::default();
        stats.count((label(1), false), true, None);
        stats.count((label(1), true), false, Some(3));
        assert_eq!(stats.to_string(), "lamp 1 1/1 · 1 stale of 1 lights (oldest 3 frames)");
        for n in 2..=6 {
            stats.count((label(n), false), false, None);
        }
        assert_eq!(stats.to_string(), "1/6 of 6 lights · 1 stale of 1 lights (oldest 3 frames)");
        assert_eq!((stats.stale(), stats.waited()), (1, 3));
        assert_eq!(stats.pages, PagePasses { drawn: 0, kept: 1, stale: 1 }, "the one page counted apart");
    }
}
