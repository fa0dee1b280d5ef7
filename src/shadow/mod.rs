//! Shadow math with no GPU in it: bounds, frusta and light-space fitting.
//!
//! Everything here is a pure function of its arguments so it can be tested exhaustively and
//! reused by the renderer, the ECS systems and (later) the evaluation harness alike.

mod bounds;
mod fit;

pub use bounds::{Aabb, frustum_corners};
pub use fit::{LightProjection, fit_directional, light_view, spot_projection};
