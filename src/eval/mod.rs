//! Measuring the shadows: benchmarks now; ground truth, metrics and charts to come. Never used
//! while playing.

pub mod bench;
