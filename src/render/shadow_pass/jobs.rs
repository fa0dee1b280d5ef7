//! The shadow pass's tiles drawn into the atlas: a pass a page (and colour), each tile filled
//! and then drawn, the frame submitted in parts between tiles on a software rasterizer.

use super::super::RenderError;
use super::super::frame::{FrameData, LayerKey};
use super::super::mesh::Drawables;
use super::super::parts::submit_and_wait;
use super::super::shadow_atlas::depth_texture;
use super::super::shadow_tiles::{Drawing, Job, PagePass, begin, page_passes};
use super::super::tile_fill::FillKind;
use super::super::timing::Stamps;
use super::ShadowPass;
use crate::shadow::distinct_pages;
use std::collections::HashSet;

impl ShadowPass {
    /// Records the jobs' passes (see [`ShadowPass::passes`]), each tile filled and then drawn.
    pub(super) fn encode_jobs(
        &self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        encoder: &mut wgpu::CommandEncoder,
        data: &FrameData,
        jobs: &[Job],
        with: Drawables<'_>,
        stamps: &mut Stamps<'_>,
    ) -> Result<(), RenderError> {
        let depth = depth_texture(self.maps.depth);
        let set = &self.sets[self.maps.depth as usize];
        // The fills' places in the order `prepare` wrote them: a static clear, then the tile's.
        let mut next_fill = 0..;
        let fills: Vec<(usize, usize)> = jobs
            .iter()
            .map(|j| {
                let first = next_fill.next().unwrap_or(0);
                if j.statics.is_some() { (first, next_fill.next().unwrap_or(0)) } else { (first, first) }
            })
            .collect();
        let drawing =
            Drawing { with, items: &data.items, layers: &self.layer_uniforms, instances: self.instances.bindings() };
        let statics = self.statics.as_ref();
        for page in distinct_pages(jobs.iter().filter(|j| j.statics.is_some()).map(|j| j.tile)) {
            let Some(target) = statics.and_then(|s| s.pages.layer_views.get(page as usize)) else { continue };
            let mut pass = begin(encoder, (target, None), false, stamps.next());
            for (job, &(fill, _)) in jobs.iter().zip(&fills).filter(|(j, _)| j.tile.page == page) {
                if let Some(calls) = &job.statics {
                    let fill = Some((&self.fill, (depth, FillKind::Clear(None)), fill, None));
                    drawing.tile(&mut pass, job, job.place(), fill, (set.get(None), calls));
                }
            }
        }
        let restore = statics
            .filter(|_| jobs.iter().any(|j| j.over_static))
            .map(|s| self.fill.statics(device, &s.pages.array_view));
        // A page none of whose tiles is kept this frame is cleared whole by its first pass (a
        // fill of memory: on a software rasterizer far cheaper than a triangle over each tile),
        // and its tiles then need no clear of their own.
        let drawn: HashSet<LayerKey> = jobs.iter().map(|j| j.layer.key).collect();
        let kept: HashSet<u32> =
            data.draws.iter().filter(|d| !drawn.contains(&d.key)).filter_map(|d| d.tile.map(|t| t.page)).collect();
        let mut cleared = HashSet::new();
        for PagePass { page, coloured, jobs: mine } in page_passes(jobs, self.part_draws) {
            let target = &self.maps.pages.layer_views[page as usize];
            let colour = coloured.then(|| &self.maps.moments.layer_views[page as usize]);
            let mut clear = !kept.contains(&page) && cleared.insert(page);
            let mut pass = None;
            for (i, submit) in mine {
                if submit {
                    drop(pass.take());
                    submit_and_wait((device, queue), encoder)?;
                }
                // Begun again after a submission, it keeps what the part before drew.
                let pass = pass.get_or_insert_with(|| {
                    begin(encoder, (target, colour), std::mem::take(&mut clear), stamps.next()).forget_lifetime()
                });
                let (job, (_, fill)) = (&jobs[i], fills[i]);
                let kind = job.fill_kind();
                let filled = cleared.contains(&page) && kind == FillKind::Clear(None);
                let fill = (!filled).then_some((&self.fill, (depth, kind), fill, restore.as_ref()));
                drawing.tile(pass, job, job.place(), fill, (set.get(job.colour), &job.calls));
            }
        }
        Ok(())
    }
}
