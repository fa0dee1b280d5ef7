//! A point light: light from a small sphere every way, shadowed through a cube of six maps.

use super::clusters::Reach;
use super::{Emitter, Kind, KindGpu, LIGHT_POINT, LayerContext, LayerFit, PagedFit, ShadowShape, SizeControl, Source};
use crate::components::{PointLight, ShadowMethod, Transform};
use crate::settings::{LightMaps, MapSettings};
use crate::shadow::light_range;
use bevy_ecs::prelude::*;
use glam::{Vec3, Vec4};

/// Texels a side of each face of a paged point light's coarse cube: a fallback while its pages
/// come (six 64² faces, 96 KiB: a bobbing lamp redraws them every frame, so they are kept small).
pub const POINT_COARSE: u32 = 64;

/// Light from `position` every way, out to `range`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// Where the light is.
    pub position: Vec3,
    /// Distance where it fades to nothing.
    pub range: f32,
    /// Radius of its sphere.
    pub radius: f32,
}

impl Point {
    /// The point light of `entity`'s component at `transform`, its range made sensible.
    pub(super) fn source(entity: Entity, light: &PointLight, transform: &Transform) -> Source {
        let point =
            Point { position: transform.translation, range: light_range(light.range), radius: light.radius.max(0.0) };
        Source { entity, kind: super::LightKind::Point(point), color: light.color * light.intensity }
    }
}

impl Kind for Point {
    fn word(&self) -> &'static str {
        "point"
    }

    /// A cube, paged where the settings ask for virtual light maps and the method reads depth.
    fn shape(&self, settings: &MapSettings, method: ShadowMethod) -> ShadowShape {
        let paged = settings.light_maps == LightMaps::Virtual && method.pages();
        if paged { ShadowShape::Pages } else { ShadowShape::Cube }
    }

    /// Its cube in pages (see [`LayerContext::cube_pages`]).
    fn pages(&self, context: &LayerContext, coarse: u32, _: Option<(f32, f32)>) -> Option<PagedFit> {
        Some(context.cube_pages(self.position, self.range, coarse))
    }

    /// Six faces of at most [`POINT_COARSE`].
    fn coarse_map(&self, _: &MapSettings, coarse: u32) -> (u32, u32) {
        (6, coarse.min(POINT_COARSE))
    }

    fn layers(&self, context: &LayerContext, resolution: u32) -> Vec<LayerFit> {
        context.cube(self.position, self.range, resolution)
    }

    fn penumbra_size(&self) -> f32 {
        self.radius
    }

    fn size_control(&self) -> SizeControl {
        SizeControl { value: self.radius, label: "radius (m)", max: 1.0 }
    }

    fn set_size(&self, world: &mut World, entity: Entity, radius: f32) {
        if let Some(mut point) = world.get_mut::<PointLight>(entity) {
            point.radius = radius;
        }
    }

    fn reach(&self) -> Reach {
        Reach::Sphere { centre: self.position, radius: self.range }
    }

    fn gpu(&self) -> KindGpu {
        KindGpu { code: LIGHT_POINT, position: self.position, range: self.range, ..KindGpu::default() }
    }

    /// A sphere seen from a receiver is a disc facing it.
    fn emitter(&self) -> Emitter {
        Emitter::Local { position: self.position, range: self.range, radius: self.radius, facing: None, cos_cone: -1.0 }
    }

    fn homogeneous(&self) -> Vec4 {
        self.position.extend(1.0)
    }

    fn volume_colour(&self, _: usize) -> [f32; 4] {
        [0.3, 0.9, 1.0, 1.0]
    }
}
