//! Measuring the shadows: ground truth by ray casting, metrics, benchmarks and charts. Never
//! used while playing.

pub mod bench;
pub mod metrics;
pub mod truth;
