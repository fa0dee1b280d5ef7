//! The shadow pass's layers whose moments are resolved from multisampled depth
//! ([`super::super::moment_samples`]): each drawn into the one scratch and resolved from it
//! before the next.

use super::super::frame::FrameData;
use super::super::mesh::Drawables;
use super::super::moment_blur::{MomentInput, MomentTile, MomentWork};
use super::super::moment_samples::SampleScratch;
use super::super::shadow_atlas::depth_texture;
use super::super::shadow_stats::ShadowStats;
use super::super::shadow_tiles::{Drawing, Job, begin};
use super::super::timing::Stamps;
use super::{ShadowPass, multisampled};

impl ShadowPass {
    /// The resolve of multisampled `tile` from the scratch, its terms at `index` in what the
    /// blur wrote, blurred by `radius`.
    fn sampled_work<'a>(
        &'a self,
        scratch: &'a SampleScratch,
        tile: &'a MomentTile,
        index: usize,
        radius: u32,
    ) -> MomentWork<'a> {
        let input = MomentInput::Samples { depth: &scratch.view, layers: &self.layer_uniforms };
        MomentWork { maps: &self.maps.moments, tiles: std::slice::from_ref(tile), first: index, radius, input }
    }

    /// The passes the multisampled jobs' moment `tiles` (their terms from `first` on) take, each
    /// drawn and then resolved and blurred by `radius`; counts those the dispatch makes in
    /// `stats`.
    pub(super) fn sampled_passes(
        &self,
        (tiles, first): (&[MomentTile], usize),
        radius: u32,
        stats: &mut ShadowStats,
    ) -> usize {
        let (Some(b), Some(scratch)) = (&self.blur, &self.scratch) else { return 0 };
        let mut passes = 0;
        for (i, tile) in tiles.iter().enumerate() {
            let work = self.sampled_work(scratch, tile, first + i, radius);
            passes += 1 + b.passes(&work);
            stats.moments_in_compute += u32::from(b.in_compute(&work));
        }
        passes
    }

    /// Makes sure the multisampled scratch holds the largest moment tile of `sampled`.
    pub(super) fn ensure_scratch(&mut self, device: &wgpu::Device, sampled: &[Job]) {
        let Some(samples) = sampled.first().map(|j| j.samples) else { return };
        let side = sampled.iter().map(|j| self.moment_tile(j).tile.size).max().unwrap_or(1);
        let format = depth_texture(self.maps.depth);
        if self.scratch.as_ref().is_none_or(|s| !s.fits(samples, side, format)) {
            self.scratch = Some(SampleScratch::new(device, samples, side, format));
        }
    }

    /// Draws each of the `sampled` jobs into the multisampled scratch at its moment `tiles`'
    /// size and resolves its moments from it (their terms from `first` on in what the blur
    /// wrote), blurred by `radius`: one job after another, as they share the scratch.
    pub(super) fn encode_sampled(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        (data, with): (&FrameData, Drawables<'_>),
        (sampled, tiles, first): (&[Job], &[MomentTile], usize),
        radius: u32,
        stamps: &mut Stamps<'_>,
    ) {
        let (Some(blur), Some(scratch)) = (&self.blur, &self.scratch) else { return };
        let set = &self.sets[self.maps.depth as usize];
        let drawing =
            Drawing { with, items: &data.items, layers: &self.layer_uniforms, instances: self.instances.bindings() };
        for (i, (job, tile)) in sampled.iter().zip(tiles).enumerate() {
            {
                let mut pass = begin(encoder, (&scratch.view, None), true, stamps.next());
                let pipelines = &set.multisampled[multisampled(job.samples)];
                drawing.tile(&mut pass, job, (0, 0, tile.tile.size), None, (pipelines, &job.calls));
            }
            blur.encode(device, encoder, self.sampled_work(scratch, tile, first + i, radius), stamps);
        }
    }
}
