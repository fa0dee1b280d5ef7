//! Update systems: small functions over components, run in order each fixed step.

mod animate;
mod camera;
mod casters;
mod layers;
mod lights;
mod pages;
mod shadow_sizes;
mod skeletal;

pub use animate::{bob, spin};
pub use camera::{ORBIT_DISTANCE, fly_camera, orbit_camera, orbit_facing, orbit_pose, switch_camera};
pub use casters::{CasterChanges, CasterState, CastersAtRest, REST_AFTER, Tracked, track_casters, update_bounds};
pub use lights::update_light_matrices;
pub use pages::{COARSE_SIDE, admit_limit, coarse_side, pool_capacity};
pub use shadow_sizes::{ShadowAtlas, ShadowCaps, coverage, size_shadow_maps};
pub use skeletal::{animate_models, follow_nodes, pose_parts, walk};
