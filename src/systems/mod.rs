//! Update systems: small functions over components, run in order each fixed step.

mod animate;
mod camera;
mod lights;
mod skeletal;

pub use animate::{bob, spin};
pub use camera::fly_camera;
pub use lights::{CasterChanges, CasterState, light_order, track_casters, update_bounds, update_light_matrices};
pub use skeletal::{animate_models, pose_parts, walk};
