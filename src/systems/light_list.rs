//! Every light of the scene, of any kind, in one order: the order the renderer lights with, the
//! measuring view reports, the truth casts rays to, `tune` tunes and bias files list. Nothing
//! else in umbra counts lights by kind.

use crate::components::{
    Cookie, DirectionalLight, PointLight, ShadowBias, ShadowMap, ShadowMethod, SpotLight, Transform,
};
use crate::settings::Settings;
use crate::shadow::{light_range, spot_cone};
use bevy_ecs::prelude::*;
use glam::Vec3;

/// Most lights the renderer lights with; lights beyond them (in [`light_list`] order) are left
/// dark, and said so once.
pub const MAX_LIGHTS: usize = 16;

/// What a light is, where it is and how big: everything that shapes its light and its shadow.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// Parallel light travelling along `direction` from a disc `angular_radius` radians across.
    Sun {
        /// Unit direction the light travels.
        direction: Vec3,
        /// Half the angle its disc covers.
        angular_radius: f32,
    },
    /// Light from `position` along `direction` inside a cone, out to `range`.
    Spot {
        /// Where the light is.
        position: Vec3,
        /// Unit direction it shines.
        direction: Vec3,
        /// Distance where it fades to nothing.
        range: f32,
        /// Half angle of full light.
        inner: f32,
        /// Half angle beyond which nothing is lit (already clamped by [`spot_cone`]).
        outer: f32,
        /// Radius of its disc.
        radius: f32,
    },
    /// Light from `position` every way, out to `range`.
    Point {
        /// Where the light is.
        position: Vec3,
        /// Distance where it fades to nothing.
        range: f32,
        /// Radius of its sphere.
        radius: f32,
    },
}

/// How a light's shadow is laid out in layers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShadowShape {
    /// One orthographic layer per cascade.
    Cascades,
    /// One perspective layer.
    Single,
    /// Six perspective layers, one per cube face.
    Cube,
}

impl LightKind {
    /// How its shadow is laid out: a spot wider than `spot_map_limit` (the widest half angle one
    /// map shadows, [`Settings::spot_map_limit`]) takes a cube, as a point light does.
    pub fn shadow_shape(&self, spot_map_limit: f32) -> ShadowShape {
        match self {
            LightKind::Sun { .. } => ShadowShape::Cascades,
            LightKind::Spot { outer, .. } if *outer <= spot_map_limit => ShadowShape::Single,
            LightKind::Spot { .. } | LightKind::Point { .. } => ShadowShape::Cube,
        }
    }

    /// Its name's first word: "sun", "spot" or "point".
    pub fn word(&self) -> &'static str {
        match self {
            LightKind::Sun { .. } => "sun",
            LightKind::Spot { .. } => "spot",
            LightKind::Point { .. } => "point",
        }
    }
}

/// A light's name: its kind and its number among the lights of that kind ("sun", "sun 2",
/// "spot 1", "point 1"). Bias files and reports use it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LightLabel {
    /// "sun", "spot" or "point".
    pub kind: &'static str,
    /// 1 for the first light of its kind.
    pub number: usize,
}

impl std::fmt::Display for LightLabel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.kind, self.number) {
            ("sun", 1) => write!(f, "sun"),
            (kind, n) => write!(f, "{kind} {n}"),
        }
    }
}

/// One light as the renderer, the truth and the tools see it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneLight {
    /// Its entity.
    pub entity: Entity,
    /// Its name.
    pub label: LightLabel,
    /// Its kind, pose and size.
    pub kind: LightKind,
    /// How its shadow is laid out.
    pub shape: ShadowShape,
    /// Linear RGB colour times intensity.
    pub color: Vec3,
    /// It casts a shadow (it has a [`ShadowMap`]).
    pub shadowed: bool,
    /// Its shadow bias (its own, or the settings').
    pub bias: ShadowBias,
    /// How its shadow map is sampled (its own, or the settings').
    pub method: ShadowMethod,
    /// The image its light is thrown through (spot lights only).
    pub cookie: Option<Cookie>,
}

/// The lights of `world` in [`light_list`] order: suns, then spots, then point lights, each kind
/// in the order its entities were made; at most [`MAX_LIGHTS`].
pub fn light_list(world: &mut World) -> Vec<SceneLight> {
    let settings = world.get_resource::<Settings>().cloned().unwrap_or_default();
    let mut kinds: Vec<(Entity, LightKind, Vec3)> = Vec::new();
    let mut suns = world.query::<(Entity, &DirectionalLight)>();
    let mut found: Vec<_> = suns
        .iter(world)
        .map(|(e, l)| {
            let direction = l.direction.try_normalize().unwrap_or(Vec3::NEG_Y);
            (e, LightKind::Sun { direction, angular_radius: l.angular_radius.max(0.0) }, l.color * l.intensity)
        })
        .collect();
    sort_by_entity(&mut found);
    kinds.extend(found);
    let mut spots = world.query::<(Entity, &SpotLight, &Transform)>();
    let mut found: Vec<_> = spots
        .iter(world)
        .map(|(e, l, t)| {
            let (inner, outer) = spot_cone(l.inner_angle, l.outer_angle);
            let kind = LightKind::Spot {
                position: t.translation,
                direction: t.forward().try_normalize().unwrap_or(Vec3::NEG_Y),
                range: light_range(l.range),
                inner,
                outer,
                radius: l.radius.max(0.0),
            };
            (e, kind, l.color * l.intensity)
        })
        .collect();
    sort_by_entity(&mut found);
    kinds.extend(found);
    let mut points = world.query::<(Entity, &PointLight, &Transform)>();
    let mut found: Vec<_> = points
        .iter(world)
        .map(|(e, l, t)| {
            let kind =
                LightKind::Point { position: t.translation, range: light_range(l.range), radius: l.radius.max(0.0) };
            (e, kind, l.color * l.intensity)
        })
        .collect();
    sort_by_entity(&mut found);
    kinds.extend(found);

    let mut counts = std::collections::HashMap::new();
    kinds
        .into_iter()
        .take(MAX_LIGHTS)
        .map(|(entity, kind, color)| {
            let number = counts.entry(kind.word()).and_modify(|n| *n += 1).or_insert(1);
            SceneLight {
                entity,
                label: LightLabel { kind: kind.word(), number: *number },
                kind,
                shape: kind.shadow_shape(settings.spot_map_limit),
                color,
                shadowed: world.get::<ShadowMap>(entity).is_some(),
                bias: world.get::<ShadowBias>(entity).copied().unwrap_or_else(|| settings.shadow_bias()),
                method: world.get::<ShadowMethod>(entity).copied().unwrap_or(settings.method),
                cookie: world.get::<Cookie>(entity).copied(),
            }
        })
        .collect()
}

fn sort_by_entity<T>(found: &mut [(Entity, T, Vec3)]) {
    found.sort_by_key(|(e, _, _)| e.index());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lights_come_suns_first_with_their_own_names_and_defaults() {
        let mut world = World::new();
        world.insert_resource(Settings::default());
        let spot = world.spawn((SpotLight::default(), Transform::default(), ShadowMap::default())).id();
        let point = world.spawn((PointLight::default(), Transform::from_xyz(0.0, 3.0, 0.0))).id();
        let sun = world.spawn((DirectionalLight::default(), ShadowMap::default(), ShadowMethod::Pcf5)).id();
        let wide = SpotLight { outer_angle: 1.2, ..Default::default() };
        let bias = ShadowBias { constant: 2.0, slope: 0.0, normal: 1.0, scale: 0.0, receiver_plane: true };
        let second = world.spawn((wide, Transform::default(), ShadowMap::default(), bias)).id();
        let lights = light_list(&mut world);
        let order: Vec<Entity> = lights.iter().map(|l| l.entity).collect();
        assert_eq!(order, vec![sun, spot, second, point]);
        let names: Vec<String> = lights.iter().map(|l| l.label.to_string()).collect();
        assert_eq!(names, vec!["sun", "spot 1", "spot 2", "point 1"]);
        assert_eq!(lights[0].method, ShadowMethod::Pcf5);
        assert_eq!(lights[1].method, Settings::default().method, "the settings' method by default");
        assert_eq!((lights[1].bias, lights[2].bias), (Settings::default().shadow_bias(), bias));
        assert!(!lights[3].shadowed);
        let shapes: Vec<ShadowShape> = lights.iter().map(|l| l.shape).collect();
        assert_eq!(shapes, vec![ShadowShape::Cascades, ShadowShape::Single, ShadowShape::Cube, ShadowShape::Cube]);
    }

    #[test]
    fn no_more_than_the_renderer_takes() {
        let mut world = World::new();
        for _ in 0..MAX_LIGHTS + 3 {
            world.spawn((PointLight::default(), Transform::default()));
        }
        assert_eq!(light_list(&mut world).len(), MAX_LIGHTS);
    }
}
