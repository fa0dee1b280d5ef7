//! What the renderer reads back of the camera's depth: the SDSM fit's reduction and the
//! marking of virtual pages, each a compute pass over the depth, read without waiting.

use super::super::Gpu;
use super::super::depth_reduction::{DepthReduction, frame_reduction};
use super::super::frame::FrameData;
use super::super::page_marks::PageMarking;
use super::Renderer;
use bevy_ecs::world::World;

impl Renderer {
    /// Adds what the last depth reduction read back (if it has arrived; with `wait`, waits for
    /// the one under way) to the news, for the SDSM fit's next update.
    pub(super) fn take_samples(&mut self, gpu: &Gpu, wait: bool) {
        if let Some(samples) = self.reduction.as_mut().and_then(|r| r.poll(&gpu.device, wait)) {
            self.news.seen = Some(samples);
        }
        if let Some(marking) = self.marking.as_mut() {
            self.news.marks.extend(marking.poll(&gpu.device, wait));
        }
    }

    /// Marks the pages the camera's pixels need of the paged lights (see
    /// [`super::page_marks`]); says once where the device cannot, and the paged lights then read
    /// their coarse maps alone.
    pub(super) fn mark_pages(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        data: &FrameData,
        depth: (&wgpu::TextureView, (u32, u32)),
    ) {
        if !self.computes {
            if !std::mem::replace(&mut self.marks_told, true) {
                let why = "virtual shadow maps mark their pages in a compute pass, which this device lacks: \
                           paged lights read their coarse maps alone";
                self.news.notices.push(why.to_string());
            }
            return;
        }
        let marking = self.marking.get_or_insert_with(|| PageMarking::new(&gpu.device));
        marking.encode((&gpu.device, &gpu.queue), encoder, depth, data);
    }

    /// Reduces the camera's depth buffer for the SDSM fit, binned along the view and in the
    /// first sun's light space; says once where the device cannot run it.
    pub(super) fn reduce_depth(
        &mut self,
        gpu: &Gpu,
        world: &World,
        encoder: &mut wgpu::CommandEncoder,
        data: &FrameData,
        (depth, size): (&wgpu::TextureView, (u32, u32)),
    ) {
        if !self.computes {
            if !std::mem::replace(&mut self.sdsm_told, true) {
                let why = "the sdsm fit needs compute shaders, which this device lacks: cascades are fitted stable";
                self.news.notices.push(why.to_string());
            }
            return;
        }
        let Some((reduce, binning)) = frame_reduction(world, data, size) else { return };
        let reduction = self.reduction.get_or_insert_with(|| DepthReduction::new(&gpu.device));
        reduction.encode((&gpu.device, &gpu.queue), encoder, depth, reduce, binning);
    }
}
