//! A pass drawn in parts. A software rasterizer bins a pass's draws ahead of drawing them and
//! holds what it binned until it is drawn: with the main pass drawn whole, a frame of 100,000
//! objects at 1280x720 peaked at 1.15 to 1.5 GB resident (lavapipe and GL llvmpipe alike; 0.71 GB
//! with llvmpipe drawing as it bins, `LP_NUM_THREADS=0`), in parts of 4,096 draws at 0.87 to 0.90
//! GB (`tests/scene_memory.rs`). On such an adapter the main pass is drawn in parts of at most
//! [`PART_DRAWS`] draws, each submitted and waited for before the next is recorded; the first
//! clears the targets, the others draw onto what the earlier ones left. A GPU draws a pass whole.
//! The shadow pass is cut the same way between its tiles ([`submits_before`]): a model of 20,000
//! primitives drew each of its layers' 20,000 calls in one submission, 1.26 GB resident on
//! lavapipe at 1280x720 (`tests/primitive_memory.rs`).

use super::{Gpu, RenderError};
use std::ops::Range;

/// Most draws a part of the main pass holds on a software rasterizer: one that bins a pass's
/// draws ahead of drawing them holds what it binned until it is drawn, so a pass of many draws is
/// drawn in parts, each submitted and waited for (see `src/render/parts.rs`).
pub const PART_DRAWS: usize = 4_096;

/// How many times a main pass part's draws the shadow pass submits at most at once, cut
/// between tiles: a tile's draws bin into fewer of the rasterizer's tiles than a frame's, every
/// cut costs a wait, and with many lights paged a frame draws thousands of pages of a few
/// casters each. A model's layers of 20,000 calls are each cut apart all the same.
pub const SHADOW_PARTS_LARGER: usize = 4;

/// One part of a pass: the draws `draws` of its list.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Part {
    /// The draws of the pass's list it makes.
    pub draws: Range<usize>,
    /// It starts the pass (clears the targets).
    pub first: bool,
    /// It ends the pass (draws what comes after the list, and may leave the depth).
    pub last: bool,
}

impl Part {
    /// The parts of a pass of `draws` draws, at most `most` each (0: no limit); always at least
    /// one, the first and the last.
    #[must_use]
    pub fn split(draws: usize, most: usize) -> Vec<Part> {
        let most = if most == 0 { usize::MAX } else { most };
        let count = draws.div_ceil(most).max(1);
        (0..count)
            .map(|i| {
                let start = i.saturating_mul(most);
                Part { draws: start..start.saturating_add(most).min(draws), first: i == 0, last: i + 1 == count }
            })
            .collect()
    }

    /// Starts the part: one other than the first submits what `encoder` holds, waits for it
    /// and starts a new encoder.
    pub fn begin(&self, gpu: &Gpu, encoder: &mut wgpu::CommandEncoder) -> Result<(), RenderError> {
        if self.first {
            return Ok(());
        }
        submit_and_wait((&gpu.device, &gpu.queue), encoder)
    }

    /// How the part loads an attachment cleared to `clear`: cleared by the first, kept after.
    #[must_use]
    pub fn load<T>(&self, clear: T) -> wgpu::LoadOp<T> {
        if self.first { wgpu::LoadOp::Clear(clear) } else { wgpu::LoadOp::Load }
    }

    /// How the part stores an attachment the pass keeps only if `kept`: stored for the next part.
    #[must_use]
    pub fn store(&self, kept: bool) -> wgpu::StoreOp {
        if kept || !self.last { wgpu::StoreOp::Store } else { wgpu::StoreOp::Discard }
    }
}

/// Submits what `encoder` holds, waits for the device to finish it and starts `encoder` anew.
pub fn submit_and_wait(
    (device, queue): (&wgpu::Device, &wgpu::Queue),
    encoder: &mut wgpu::CommandEncoder,
) -> Result<(), RenderError> {
    let fresh = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame, part") });
    queue.submit([std::mem::replace(encoder, fresh).finish()]);
    super::wait::wait_for(device)
}

/// Before which of a list of jobs (their draws each, in the order they are recorded) what was
/// recorded so far is submitted and waited for, so that no submission holds more than `most`
/// draws unless one job alone does (`most` 0: never).
#[must_use]
pub fn submits_before(draws: &[usize], most: usize) -> Vec<bool> {
    let mut held = 0usize;
    let submit = |&d: &usize| {
        let now = most > 0 && held > 0 && held.saturating_add(d) > most;
        held = if now { d } else { held.saturating_add(d) };
        now
    };
    draws.iter().map(submit).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pass of `draws` draws in one part.
    fn whole(draws: usize) -> Part {
        Part { draws: 0..draws, first: true, last: true }
    }

    #[test]
    fn a_pass_splits_into_parts_that_cover_its_draws_once_in_order() {
        let parts = Part::split(40_000, 16_384);
        assert_eq!(parts.len(), 3);
        assert_eq!(
            parts.iter().map(|p| p.draws.clone()).collect::<Vec<_>>(),
            [0..16_384, 16_384..32_768, 32_768..40_000]
        );
        assert_eq!(
            parts.iter().map(|p| (p.first, p.last)).collect::<Vec<_>>(),
            [(true, false), (false, false), (false, true)]
        );
        assert_eq!(Part::split(PART_DRAWS, PART_DRAWS), [whole(PART_DRAWS)]);
        assert_eq!(Part::split(0, PART_DRAWS), [whole(0)], "an empty pass still clears");
        assert_eq!(Part::split(7, 0), [whole(7)], "no limit");
        assert_eq!(Part::split(usize::MAX, usize::MAX), [whole(usize::MAX)]);
        assert_eq!(Part::split(3, 1).len(), 3);
    }

    #[test]
    fn only_the_first_part_clears_and_only_the_last_may_drop_what_it_drew() {
        let [first, last] =
            [Part { draws: 0..1, first: true, last: false }, Part { draws: 1..2, first: false, last: true }];
        assert_eq!(first.load(1.0), wgpu::LoadOp::Clear(1.0));
        assert_eq!(last.load(1.0), wgpu::LoadOp::Load);
        assert_eq!(first.store(false), wgpu::StoreOp::Store);
        assert_eq!(last.store(false), wgpu::StoreOp::Discard);
        assert_eq!(last.store(true), wgpu::StoreOp::Store);
    }

    #[test]
    fn jobs_are_submitted_in_runs_of_at_most_the_limit_unless_one_alone_is_more() {
        assert_eq!(submits_before(&[3, 3, 3, 3], 6), [false, false, true, false]);
        assert_eq!(submits_before(&[3, 4, 2], 6), [false, true, false]);
        // A job over the limit is submitted alone: after what came before, and before the next.
        assert_eq!(submits_before(&[1, 20, 1], 6), [false, true, true]);
        assert_eq!(submits_before(&[20, 20], 6), [false, true]);
        // Empty jobs never start a submission; no limit, or no jobs, submit nothing.
        assert_eq!(submits_before(&[0, 6, 0, 0], 6), [false, false, false, false]);
        assert_eq!(submits_before(&[3, usize::MAX, 3], 0), [false; 3]);
        assert_eq!(submits_before(&[usize::MAX, usize::MAX], 6), [false, true]);
        assert!(submits_before(&[], 6).is_empty());
    }
}
