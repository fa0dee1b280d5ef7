//! Measuring the shadows: ground truth by ray casting, metrics, benchmarks and charts. Play uses
//! it only off the frame loop: [`live`] measures on a worker thread for the error overlay.

pub mod bench;
pub mod cases;
pub mod chart;
pub mod config;
pub mod cost;
pub mod gallery;
pub mod live;
pub mod many;
pub mod measure;
pub mod metrics;
pub mod passes;
pub mod results;
pub mod sweep;
pub mod sweep_options;
pub mod truth;
pub mod tune;
