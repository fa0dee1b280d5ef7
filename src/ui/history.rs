//! The last few seconds of frame times and GPU pass times, for the panel's numbers and graph.

use crate::render::PassTimes;
use std::collections::VecDeque;

/// Samples kept of each series: four seconds at 60 frames a second.
pub const KEPT: usize = 240;

/// Rolling frame and pass times.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct History {
    /// Wall-clock time of each frame, in milliseconds, oldest first.
    pub frames: VecDeque<f32>,
    /// GPU time of the shadow and the main pass of the frames whose stamps came back, in
    /// milliseconds, oldest first.
    pub passes: VecDeque<(f32, f32)>,
}

fn push<T>(series: &mut VecDeque<T>, value: T) {
    if series.len() == KEPT {
        series.pop_front();
    }
    series.push_back(value);
}

impl History {
    /// Adds one frame that took `ms` milliseconds (not a finite, positive time: left out).
    pub fn frame(&mut self, ms: f32) {
        if ms.is_finite() && ms > 0.0 {
            push(&mut self.frames, ms);
        }
    }

    /// Adds the pass times of one frame.
    pub fn passes(&mut self, times: PassTimes) {
        let (shadow, main) = (times.shadow_ms as f32, times.main_ms as f32);
        if shadow.is_finite() && main.is_finite() {
            push(&mut self.passes, (shadow.max(0.0), main.max(0.0)));
        }
    }

    /// Frames per second over the frames of the last second (0 with none).
    #[must_use]
    pub fn fps(&self) -> f32 {
        let mut spent = 0.0;
        let mut frames = 0;
        for ms in self.frames.iter().rev() {
            if spent >= 1000.0 {
                break;
            }
            spent += ms;
            frames += 1;
        }
        if spent > 0.0 { frames as f32 * 1000.0 / spent } else { 0.0 }
    }

    /// The median of the last `n` values of a series (`None` when empty).
    #[must_use]
    pub fn median(series: impl DoubleEndedIterator<Item = f32>, n: usize) -> Option<f32> {
        let mut last: Vec<f32> = series.rev().take(n).collect();
        last.sort_by(f32::total_cmp);
        last.get(last.len() / 2).copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn it_keeps_the_last_samples_and_counts_frames_per_second() {
        let mut h = History::default();
        for _ in 0..KEPT + 10 {
            h.frame(20.0);
        }
        assert_eq!(h.frames.len(), KEPT);
        assert!((h.fps() - 50.0).abs() < 1e-3, "{}", h.fps());
        h.frame(f32::NAN);
        h.frame(-1.0);
        h.frame(0.0);
        assert_eq!(h.frames.len(), KEPT, "nonsense times are left out");
        assert_eq!(History::default().fps(), 0.0);
    }

    #[test]
    fn pass_times_and_medians() {
        let mut h = History::default();
        for (s, m) in [(1.0, 5.0), (3.0, 4.0), (2.0, f64::NAN), (2.0, 6.0)] {
            h.passes(PassTimes { shadow_ms: s, main_ms: m });
        }
        assert_eq!(h.passes.len(), 3, "a NaN frame is left out");
        assert_eq!(History::median(h.passes.iter().map(|p| p.0), 3), Some(2.0));
        assert_eq!(History::median(h.passes.iter().map(|p| p.1), 2), Some(6.0));
        assert_eq!(History::median(std::iter::empty(), 5), None);
    }
}
