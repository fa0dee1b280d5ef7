//! A light's layers from one update to the next: each layer's projection as its kind fits it, and
//! the versions of what it holds, new whenever a caster moved through it (so the renderer draws
//! it again) or the layer itself changed.

use super::casters::CasterChanges;
use crate::components::ShadowLayer;
use crate::light::LayerFit;
use crate::shadow::{Aabb, ClipVolume, frustum_corners};
use std::sync::atomic::{AtomicU64, Ordering};

/// A number never handed out before in this process: the version of a layer's new contents.
pub(super) fn next_version() -> u64 {
    static NEXT: AtomicU64 = AtomicU64::new(1);
    NEXT.fetch_add(1, Ordering::Relaxed)
}

/// True when one of `changes` lies inside the clip volume of `clip_from_world`: it passes the
/// clip-space test and meets the volume's world box.
///
/// The world box is tried first, with six comparisons: with ten thousand moving cubes most
/// changes miss most layers' boxes, and the clip-space test of each would be most of the
/// update's time. It also turns away a box beside a cone's far corners, which no clip plane
/// alone does; a box outside the world box is outside the volume, so no layer a change
/// reaches is missed.
pub(super) fn touches(clip_from_world: &glam::Mat4, changes: &[Aabb]) -> bool {
    let reach = Aabb::from_points(frustum_corners(clip_from_world));
    let volume = ClipVolume::new(clip_from_world);
    changes.iter().any(|b| (!reach.is_usable() || reach.intersects(b)) && volume.intersects(b))
}

/// A light's layers fitted as `fits`, from its `old` ones: each keeps its version unless it is
/// dirty, and its static version unless the casters at rest inside it changed (or the layer
/// itself did).
pub(super) fn fitted_layers(
    old: &[ShadowLayer],
    fits: &[LayerFit],
    resolution: u32,
    forced: bool,
    changes: &CasterChanges,
) -> Vec<ShadowLayer> {
    fits.iter()
        .enumerate()
        .map(|(i, LayerFit { projection: fit, far, blend })| {
            let old = old.get(i).filter(|o| o.clip_from_world == fit.view_proj && o.resolution == resolution);
            let anew = forced || old.is_none();
            let dirty = anew || touches(&fit.view_proj, &changes.moved);
            let resettled = anew || touches(&fit.view_proj, &changes.settled);
            let (version, static_version) = match old {
                Some(o) => (
                    if dirty { next_version() } else { o.version },
                    if resettled { next_version() } else { o.static_version },
                ),
                None => (next_version(), next_version()),
            };
            ShadowLayer {
                clip_from_world: fit.view_proj,
                texel: fit.texel,
                resolution,
                far: *far,
                blend: *blend,
                depth: crate::shadow::depth_terms(&fit.proj),
                dirty,
                version,
                static_version,
                page: None,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shadow::intersects_clip_volume;
    use glam::{Mat4, Vec3};

    #[test]
    fn a_change_beside_a_layer_leaves_it_clean_and_one_inside_dirties_it() {
        let spot = glam::camera::rh::proj::directx::perspective(std::f32::consts::FRAC_PI_2, 1.0, 0.1, 10.0);
        // Past the cone's far edge, beside its far corner.
        let beside = Aabb::new(Vec3::new(10.5, -0.5, -11.0), Vec3::new(11.5, 0.5, -9.0));
        assert!(intersects_clip_volume(&spot, &beside), "the clip-space test alone passes it");
        assert!(!touches(&spot, &[beside]));
        let inside = Aabb::new(Vec3::new(-0.5, -0.5, -5.0), Vec3::new(0.5, 0.5, -4.0));
        assert!(touches(&spot, &[beside, inside]));
        assert!(!touches(&spot, &[]));
        // A volume with no world box to speak of is left to the clip-space test.
        assert_eq!(touches(&Mat4::ZERO, &[inside]), intersects_clip_volume(&Mat4::ZERO, &inside));
    }
}
