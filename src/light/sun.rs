//! The sun: parallel light from a disc far away, shadowed through cascades fitted to the
//! camera's view (or to what it saw, with the SDSM fit).

use super::clusters::Reach;
use super::{
    CameraView, Emitter, Kind, KindGpu, LIGHT_SUN, LayerContext, LayerFit, PagedFit, ShadowShape, SizeControl, Source,
};
use crate::components::{DirectionalLight, ShadowMethod};
use crate::settings::{MapSettings, SunMaps};
use crate::shadow::{
    Clipmap, FitMode, PageSpace, SunScene, ViewFrustum, VisibleSamples, blend_bands, depth_range, fit_seen, fit_slice,
    geometric_splits, split_depths,
};
use bevy_ecs::prelude::*;
use glam::{Vec3, Vec4};

/// A sun's cascades in the light-volume view, in the cascade tints' order.
const CASCADE_COLOURS: [[f32; 4]; 4] =
    [[1.0, 0.3, 0.3, 1.0], [0.3, 1.0, 0.3, 1.0], [0.35, 0.45, 1.0, 1.0], [1.0, 0.9, 0.25, 1.0]];

/// Parallel light travelling along `direction` from a disc `angular_radius` radians across.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sun {
    /// Unit direction the light travels.
    pub direction: Vec3,
    /// Half the angle its disc covers.
    pub angular_radius: f32,
}

impl Sun {
    /// The sun of `entity`'s component: its direction made unit (straight down if it has none).
    pub(super) fn source(entity: Entity, light: &DirectionalLight) -> Source {
        let direction = light.direction.try_normalize().unwrap_or(Vec3::NEG_Y);
        let kind = super::LightKind::Sun(Sun { direction, angular_radius: light.angular_radius.max(0.0) });
        Source { entity, kind, color: light.color * light.intensity }
    }
}

impl Kind for Sun {
    fn word(&self) -> &'static str {
        "sun"
    }

    fn first_unnumbered(&self) -> bool {
        true
    }

    /// Cascades, or a virtual map where the settings ask for one and the method reads depth.
    fn shape(&self, settings: &MapSettings, method: ShadowMethod) -> ShadowShape {
        if settings.sun_maps == SunMaps::Virtual && method.pages() { ShadowShape::Pages } else { ShadowShape::Cascades }
    }

    /// One stable cascade over the whole shadow distance, `coarse` texels a side.
    fn coarse_map(&self, _: &MapSettings, coarse: u32) -> (u32, u32) {
        (1, coarse)
    }

    /// One layer per cascade, fitted to its slice of the camera's view; none without a camera.
    fn layers(&self, context: &LayerContext, resolution: u32) -> Vec<LayerFit> {
        context.view.map_or_else(Vec::new, |view| cascades(self.direction, view, context, resolution))
    }

    /// The clipmap round the camera, its depth range holding every caster; the coarse map is a
    /// stable cascade over the whole shadow distance.
    fn pages(&self, context: &LayerContext, coarse: u32, depth: Option<(f32, f32)>) -> Option<PagedFit> {
        let CameraView { camera, transform, aspect } = context.view?;
        let settings = context.cascade;
        let sun = SunScene::from_boxes(self.direction, context.scene.iter().copied());
        let depth = depth_range(depth, sun.depth_extent());
        let mut clipmap = Clipmap::new(self.direction, settings.shadow_distance, depth);
        // The guards taken away, to show what they guard against: no border round the pages
        // without the atlas guard, and a grid that follows the camera when unsnapped.
        clipmap.border = if context.maps.atlas_guard { clipmap.border } else { 0 };
        if settings.fit_mode == FitMode::Unsnapped {
            clipmap = clipmap.centred_on(transform.translation);
        }
        let frustum =
            ViewFrustum { position: transform.translation, rotation: transform.rotation, fov_y: camera.fov_y, aspect };
        let slice = (camera.near, camera.shadow_far(settings.shadow_distance));
        let coarse_side = coarse;
        let projection = fit_slice(&sun, &frustum, slice, FitMode::Stable, coarse_side);
        let (space, camera) = (PageSpace::Clipmap(clipmap), transform.translation);
        let coarse = vec![LayerFit { projection, far: slice.1, blend: 0.0 }];
        Some(PagedFit { space, camera, coarse, coarse_side })
    }

    fn penumbra_size(&self) -> f32 {
        self.angular_radius.min(1.5).tan()
    }

    fn size_control(&self) -> SizeControl {
        SizeControl { value: self.angular_radius.to_degrees(), label: "disc radius (°)", max: 5.0 }
    }

    fn set_size(&self, world: &mut World, entity: Entity, degrees: f32) {
        if let Some(mut sun) = world.get_mut::<DirectionalLight>(entity) {
            sun.angular_radius = degrees.to_radians();
        }
    }

    fn reach(&self) -> Reach {
        Reach::Everywhere
    }

    fn gpu(&self) -> KindGpu {
        KindGpu { code: LIGHT_SUN, direction: self.direction, ..KindGpu::default() }
    }

    fn emitter(&self) -> Emitter {
        Emitter::Distant { towards: -self.direction, angular_radius: self.angular_radius }
    }

    fn homogeneous(&self) -> Vec4 {
        (-self.direction).extend(0.0)
    }

    fn volume_colour(&self, layer: usize) -> [f32; 4] {
        CASCADE_COLOURS[layer % CASCADE_COLOURS.len()]
    }
}

/// The sun's cascades for the camera: each projection with the view depth where it ends and the
/// width of its blend band. With the SDSM fit and what the camera saw, the splits span the view
/// depths seen and each box holds its slice's visible pixels (a slice where nothing was seen is
/// fitted stable).
fn cascades(direction: Vec3, view: CameraView, context: &LayerContext, res: u32) -> Vec<LayerFit> {
    let (settings, CameraView { camera, transform, aspect }) = (context.cascade, view);
    let frustum =
        ViewFrustum { position: transform.translation, rotation: transform.rotation, fov_y: camera.fov_y, aspect };
    let far = camera.shadow_far(settings.shadow_distance);
    let seen: Option<&VisibleSamples> = context.seen.filter(|_| settings.fit_mode == FitMode::Sdsm);
    let seen_depths = seen.and_then(|s| s.depths).map(|(n, f)| (n.max(camera.near), f.min(far))).filter(|(n, f)| n < f);
    let count = settings.cascades as usize;
    let depths = match (seen_depths, settings.first_cascade_far) {
        (Some((n, f)), _) => split_depths(n, f, count, settings.split_lambda),
        (None, Some(first)) => geometric_splits(camera.near, first, far, count),
        (None, None) => split_depths(camera.near, far, count, settings.split_lambda),
    };
    let bands = blend_bands(&depths, settings.cascade_blend);
    let sun = SunScene::from_boxes(direction, context.scene.iter().copied());
    (0..bands.len())
        .map(|i| {
            // A cascade starts inside the previous one's blend band, so both cover the band.
            let start = if i == 0 { depths[0] } else { depths[i] - bands[i - 1] };
            let slice = (start, depths[i + 1]);
            let seen_box = seen.map(|s| s.slice_box(slice, &sun.light_from_world())).filter(|b| !b.is_empty());
            let projection = match seen_box {
                Some(b) => fit_seen(&sun, &b, res),
                None => fit_slice(&sun, &frustum, slice, settings.fit_mode, res),
            };
            LayerFit { projection, far: depths[i + 1], blend: bands[i] }
        })
        .collect()
}
