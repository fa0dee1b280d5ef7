//! Shadow math with no GPU in it: bounds, frusta, cascades and light-space fitting.
//!
//! Everything here is a pure function of its arguments so it can be tested exhaustively and
//! reused by the renderer, the ECS systems and the evaluation harness alike.

mod atlas;
mod bounds;
mod cascade;
mod cube_pages;
mod cull;
mod fit;
mod frustum_pages;
mod page_pool;
mod page_space;
mod pages;
mod planar;
mod poisson;
mod sdsm;
#[cfg(test)]
pub(crate) mod test_rng;
mod tile_size;
mod updates;

pub use atlas::{Atlas, AtlasShape, MAX_PAGE, MIN_TILE, Placed, Tile, distinct_pages};
pub use bounds::{Aabb, ClipVolume, MAX_WORLD_EXTENT, frustum_corners, intersects_clip_volume, nearest_depth};
pub use cascade::{
    FitMode, MAX_CASCADES, SceneBounds, SunScene, ViewFrustum, blend_bands, depth_step, fit_cascade, fit_seen,
    fit_slice, geometric_splits, split_depths,
};
pub use cube_pages::{CUBE_ACROSS, CUBE_FACE_PAGES, CubePages};
pub use cull::CasterIndex;
pub use fit::{
    CUBE_FACES, LightProjection, MAX_MAP_HALF_ANGLE, MAX_SPOT_HALF_ANGLE, MIN_SPOT_HALF_ANGLE, cube_face,
    cube_face_projection, cube_projections, depth_terms, light_range, light_view, near_plane, spot_cone,
    spot_projection, view_distance,
};
pub use frustum_pages::{FrustumPages, MAX_FRUSTUM_PAGES, pages_for};
pub use page_pool::{
    Change, LightPage, MAX_FINER, MAX_PRESSURE, POOL_FILL, PRESSURE_SLACK, PagePool, PoolKey, Pressure, Residency,
    Resident,
};
pub use page_space::PageSpace;
pub use pages::{
    Clipmap, FINEST_TEXEL_LOG2, MARK_WORDS, MAX_PAGE_LEVELS, MIN_GRAZE, PAGE_BORDER, PAGE_GRID, PAGE_TEXELS, PAGE_TILE,
    PageId, PageMarks, PageRange, Window, depth_range, levels_for, wanted_texel,
};
pub use planar::{GROUND_PLANE, PLANAR_LIFT, flat_from_world, lights_plane};
pub use poisson::{poisson_disc, wgsl_array};
pub use sdsm::{SDSM_BINS, SDSM_WORDS, VisibleSamples, bin_of, bin_start, from_order_key, initial_words, order_key};
pub use tile_size::{HYSTERESIS, TileNeed, fit_budget, size_class, texels_for};
pub use updates::{MAX_STALE, TileState, Update, plan_updates};
