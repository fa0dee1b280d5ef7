//! A spot light: light from a point inside a cone, shadowed through one perspective map, or
//! through a cube when its cone is wider than one map holds well.

use super::clusters::Reach;
use super::{Emitter, Kind, KindGpu, LIGHT_SPOT, LayerContext, LayerFit, PagedFit, ShadowShape, SizeControl, Source};
use crate::components::{ShadowMethod, SpotLight, Transform};
use crate::settings::{LightMaps, MapSettings};
use crate::shadow::{FrustumPages, MAX_FRUSTUM_PAGES, PageSpace, light_range, spot_cone, spot_projection};
use bevy_ecs::prelude::*;
use glam::{Vec3, Vec4};

/// Texels a side of a paged spot's coarse map: a fallback while its pages come (a 256² map
/// holds the shape of a shadow a few metres across, in 256 KiB).
pub const SPOT_COARSE: u32 = 256;

/// Light from `position` along `direction` inside a cone, out to `range`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spot {
    /// Where the light is.
    pub position: Vec3,
    /// Unit direction it shines.
    pub direction: Vec3,
    /// Distance where it fades to nothing.
    pub range: f32,
    /// Half angle of full light.
    pub inner: f32,
    /// Half angle beyond which nothing is lit (already clamped by [`spot_cone`]).
    pub outer: f32,
    /// Radius of its disc.
    pub radius: f32,
}

impl Spot {
    /// The spot of `entity`'s component at `transform`, its cone and range made sensible.
    pub(super) fn source(entity: Entity, light: &SpotLight, transform: &Transform) -> Source {
        let (inner, outer) = spot_cone(light.inner_angle, light.outer_angle);
        let spot = Spot {
            position: transform.translation,
            direction: transform.forward().try_normalize().unwrap_or(Vec3::NEG_Y),
            range: light_range(light.range),
            inner,
            outer,
            radius: light.radius.max(0.0),
        };
        Source { entity, kind: super::LightKind::Spot(spot), color: light.color * light.intensity }
    }
}

impl Kind for Spot {
    fn word(&self) -> &'static str {
        "spot"
    }

    /// One map, unless its cone is wider than `spot_map_limit` (the widest half angle one map
    /// shadows): then a cube, as a point light has. Either is paged where the settings ask for
    /// virtual light maps and the method reads depth.
    fn shape(&self, settings: &MapSettings, method: ShadowMethod) -> ShadowShape {
        if settings.light_maps == LightMaps::Virtual && method.pages() {
            ShadowShape::Pages
        } else if self.outer <= settings.spot_map_limit {
            ShadowShape::Single
        } else {
            ShadowShape::Cube
        }
    }

    /// Its one map in pages of [`MAX_FRUSTUM_PAGES`] a side at the finest level (a pixel far
    /// away or seen small reads a coarser level, so the finest costs only what is asked of it);
    /// the coarse map is the whole map, `coarse` texels a side and at most [`SPOT_COARSE`]. A
    /// cone too wide for one map is paged as a point light's cube.
    fn pages(&self, context: &LayerContext, coarse: u32, _: Option<(f32, f32)>) -> Option<PagedFit> {
        if self.outer > context.maps.spot_map_limit {
            return Some(context.cube_pages(self.position, self.range, coarse));
        }
        let map = |resolution| spot_projection(self.position, self.direction, self.outer, self.range, resolution);
        let mut pages = FrustumPages::new(map(1), MAX_FRUSTUM_PAGES);
        // Without the atlas guard, no border round the pages (as the sun's).
        pages.border = if context.maps.atlas_guard { pages.border } else { 0 };
        let camera = context.view.map_or(Vec3::ZERO, |v| v.transform.translation);
        let coarse_side = coarse.min(SPOT_COARSE);
        let coarse = vec![LayerFit::everywhere(map(coarse_side))];
        Some(PagedFit { space: PageSpace::Frustum(pages), camera, coarse, coarse_side })
    }

    /// One map of at most [`SPOT_COARSE`], or a cube's six faces of at most
    /// [`super::POINT_COARSE`] for a cone too wide for one map.
    fn coarse_map(&self, settings: &MapSettings, coarse: u32) -> (u32, u32) {
        if self.outer > settings.spot_map_limit {
            (6, coarse.min(super::POINT_COARSE))
        } else {
            (1, coarse.min(SPOT_COARSE))
        }
    }

    fn layers(&self, context: &LayerContext, resolution: u32) -> Vec<LayerFit> {
        match self.shape(&context.maps.unpaged(), ShadowMethod::default()) {
            ShadowShape::Single => {
                let cone = spot_projection(self.position, self.direction, self.outer, self.range, resolution);
                vec![LayerFit::everywhere(cone)]
            }
            _ => context.cube(self.position, self.range, resolution),
        }
    }

    fn penumbra_size(&self) -> f32 {
        self.radius
    }

    fn size_control(&self) -> SizeControl {
        SizeControl { value: self.radius, label: "radius (m)", max: 1.0 }
    }

    fn set_size(&self, world: &mut World, entity: Entity, radius: f32) {
        if let Some(mut spot) = world.get_mut::<SpotLight>(entity) {
            spot.radius = radius;
        }
    }

    /// The smallest sphere round the cone's lit part (every point within `range` of the light
    /// and `outer` of its axis): for a narrow cone, the sphere through the light and the rim of
    /// its cap; for a wide one, the sphere round the rim.
    fn reach(&self) -> Reach {
        let (r, cos) = (self.range, self.outer.cos());
        let (along, radius) = if cos > std::f32::consts::FRAC_1_SQRT_2 {
            (r / (2.0 * cos), r / (2.0 * cos))
        } else {
            (r * cos, r * self.outer.sin())
        };
        Reach::Sphere { centre: self.position + self.direction * along, radius }
    }

    fn gpu(&self) -> KindGpu {
        let cos_outer = self.outer.cos();
        KindGpu {
            code: LIGHT_SPOT,
            position: self.position,
            range: self.range,
            direction: self.direction,
            cos_outer,
            cos_inner: self.inner.cos().max(cos_outer + 1e-4),
            // The cookie is thrown through the cone's own projection, shadowed or not.
            cookie_from_world: Some(
                spot_projection(self.position, self.direction, self.outer, self.range, 1).view_proj,
            ),
        }
    }

    fn emitter(&self) -> Emitter {
        Emitter::Local {
            position: self.position,
            range: self.range,
            radius: self.radius,
            facing: Some(self.direction),
            cos_cone: self.outer.cos(),
        }
    }

    fn homogeneous(&self) -> Vec4 {
        self.position.extend(1.0)
    }

    fn volume_colour(&self, _: usize) -> [f32; 4] {
        [1.0, 0.6, 0.15, 1.0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shadow::test_rng::Rng;

    #[test]
    fn its_reach_holds_every_point_it_lights_and_is_no_larger_than_its_range() {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        for outer in [0.05f32, 0.3, 0.7, std::f32::consts::FRAC_PI_4, 1.0, 1.4, std::f32::consts::FRAC_PI_2] {
            let direction = rng.point(1.0).normalize_or(Vec3::NEG_Y);
            let spot = Spot { position: rng.point(5.0), direction, range: 7.0, inner: 0.0, outer, radius: 0.1 };
            let Reach::Sphere { centre, radius } = spot.reach() else { panic!("a spot reaches a sphere") };
            assert!(radius <= spot.range * (1.0 + 1e-5), "{outer}: {radius}");
            for _ in 0..2000 {
                let p = spot.position + rng.point(spot.range);
                let d = p - spot.position;
                let lit = d.length() <= spot.range && d.normalize_or_zero().dot(direction) >= outer.cos();
                if lit {
                    assert!(p.distance(centre) <= radius * (1.0 + 1e-4), "{outer}: {p} outside");
                }
            }
        }
    }
}
