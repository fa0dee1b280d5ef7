//! Measuring the shadows: ground truth by ray casting, metrics, benchmarks and charts. Play uses
//! it only off the frame loop: [`live`] measures on a worker thread for the error overlay.

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
pub mod texels;
pub mod truth;
pub mod tune;

use crate::AppError;
use crate::render::RenderError;

/// Why a bench could not run.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// A setting is out of range or a model does not load.
    #[error(transparent)]
    App(#[from] AppError),
    /// Rendering failed.
    #[error(transparent)]
    Render(#[from] RenderError),
}

/// The median of `values` (NaN when empty).
pub(crate) fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied().unwrap_or(f64::NAN)
}
