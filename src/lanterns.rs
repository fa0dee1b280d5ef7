//! Lanterns (`--lanterns N`): the many-lights sample. Shadowed lights hang over the ring and the
//! field of cubes on a sunflower spiral, about one per 7 m² of ground, each under a small dark
//! cap: two in three are point lights, the rest spots looking down, and one in four bobs on its
//! rope, so its shadow is redrawn every frame while the others keep theirs. The sun sets to a
//! dusk glow ([`DUSK`]) so the lanterns light the scene.

use crate::assets::{MeshLibrary, cube};
use crate::components::{Bob, Material, PointLight, ShadowMap, SpotLight, Transform};
use bevy_ecs::prelude::*;
use glam::{Vec2, Vec3};

/// The sun's intensity when lanterns hang (the sample's sun is 1).
pub const DUSK: f32 = 0.3;

/// Most lanterns the sample hangs.
pub const MAX_LANTERNS: u32 = 4096;

/// Ground each lantern has to itself, in m².
const AREA_EACH: f32 = 7.0;

/// How high a lantern hangs, in metres (before its bob).
const HANG: f32 = 3.0;

/// Where lantern `i` of the spiral hangs over the ground (its x and z): the sunflower's even
/// spread, nearest the middle first, so more lanterns only add to the rim.
#[must_use]
pub fn lantern_spot(i: u32) -> Vec2 {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let radius = (AREA_EACH * (i as f32 + 0.5) / std::f32::consts::PI).sqrt();
    let angle = golden * i as f32;
    Vec2::new(angle.cos(), angle.sin()) * radius
}

/// A lantern's light.
enum Lantern {
    Point(PointLight),
    Spot(SpotLight),
}

/// Lantern `i`'s light, colour spread by the golden ratio between warm white and amber.
fn lantern(i: u32) -> Lantern {
    let g = (i as f32 * 0.618_034).fract();
    let color = Vec3::new(1.0, 0.75 + 0.15 * g, 0.45 + 0.3 * g);
    if i % 3 == 2 {
        Lantern::Spot(SpotLight {
            color,
            intensity: 1.6,
            range: 6.0,
            inner_angle: 0.55,
            outer_angle: 0.75,
            ..Default::default()
        })
    } else {
        Lantern::Point(PointLight { color, intensity: 0.8, range: 4.5, ..Default::default() })
    }
}

/// Hangs `n` lanterns (see the module's notes) in `world`, which must hold a [`MeshLibrary`].
pub fn spawn_lanterns(world: &mut World, n: u32) {
    let cap = world.resource_mut::<MeshLibrary>().add(cube(Vec3::splat(0.5)));
    let iron = Material { specular: 0.3, shininess: 16.0, ..Material::color(0.12, 0.11, 0.10) };
    for i in 0..n {
        let spot = lantern_spot(i);
        let g = (i as f32 * 0.618_034).fract();
        let at = Vec3::new(spot.x, HANG + 0.5 * g, spot.y);
        let bob = (i % 4 == 1).then_some(Bob { base_y: at.y, amplitude: 0.25, frequency: 1.0 + g, phase: 6.0 * g });
        let light = Transform::from_translation(at);
        // The cap sits just above the light and casts no shadow: it would hide its own light.
        let cap_at = Transform::from_translation(at + Vec3::Y * 0.15).with_scale(Vec3::new(0.25, 0.1, 0.25));
        let mut cap_entity = world.spawn((cap, cap_at, iron));
        if let Some(bob) = bob {
            cap_entity.insert(Bob { base_y: bob.base_y + 0.15, ..bob });
        }
        let mut light_entity = match lantern(i) {
            Lantern::Point(p) => world.spawn((p, light, ShadowMap::default())),
            Lantern::Spot(s) => world.spawn((s, light.looking_to(Vec3::NEG_Y), ShadowMap::default())),
        };
        if let Some(bob) = bob {
            light_entity.insert(bob);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::ShadowCaster;

    #[test]
    fn lanterns_spread_evenly_point_and_spot_mixed_some_moving_none_casting() {
        let mut world = World::new();
        world.insert_resource(MeshLibrary::default());
        spawn_lanterns(&mut world, 64);
        let points = world.query::<&PointLight>().iter(&world).count();
        let spots = world.query::<&SpotLight>().iter(&world).count();
        assert_eq!((points, spots), (43, 21));
        let shadowed = world.query::<&ShadowMap>().iter(&world).count();
        assert_eq!(shadowed, 64);
        let bobbing = world.query_filtered::<(), (With<Bob>, With<ShadowMap>)>().iter(&world).count();
        assert_eq!(bobbing, 16);
        assert_eq!(world.query::<&ShadowCaster>().iter(&world).count(), 0, "the caps cast nothing");
        // Even spread: no two closer than a metre and a half, and the disc grows as the root.
        let spots: Vec<Vec2> = (0..256).map(lantern_spot).collect();
        for (i, a) in spots.iter().enumerate() {
            assert!(spots[i + 1..].iter().all(|b| a.distance(*b) > 1.5), "lantern {i} crowded");
        }
        let reach = |n: u32| (0..n).map(|i| lantern_spot(i).length()).fold(0.0, f32::max);
        assert!((reach(256) / reach(64) - 2.0).abs() < 0.1);
    }
}
