//! Measuring the shadows: ground truth by ray casting, metrics, benchmarks and charts. Never
//! used while playing.

pub mod bench;
pub mod cases;
pub mod chart;
pub mod cost;
pub mod gallery;
pub mod measure;
pub mod metrics;
pub mod results;
pub mod sweep;
pub mod truth;
pub mod tune;
