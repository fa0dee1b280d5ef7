//! Shadow tile sizes: each shadowed light's layers get texels in proportion to the share of the
//! screen its light covers (a sun's cascades the settings' size), kept in a size class with
//! hysteresis, then fitted to the shadow memory: the atlas of that many MiB ([`ShadowAtlas`])
//! must hold every layer, so where it cannot, the lights that show least are halved first.

use super::pages::{coarse_side, pool_capacity};
use crate::components::{Camera, ShadowMap, ShadowMethod, Transform};
use crate::light::clusters::Reach;
use crate::light::{Kind, LightSources, ShadowShape};
use crate::settings::{CascadeSettings, MapSettings, MomentBits, ShadowDepth, ShadowSettings, TileSizes};
use crate::shadow::{AtlasShape, MAX_PAGE, MIN_TILE, PAGE_TILE, TileNeed, fit_budget, size_class, texels_for};
use bevy_ecs::prelude::*;
use glam::Vec3;

/// What the device the shadows are drawn on can keep per texel: the renderer's news carries it and
/// the app keeps it in the world (until it has, the most any device keeps is assumed, so the
/// budget holds everywhere).
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShadowCaps {
    /// Moment maps can be 32-bit floats (GL cannot render into or filter them).
    pub full_float_moments: bool,
    /// Static copies of the depth are kept (GL cannot read depth back to put them in place).
    pub static_maps: bool,
}

impl Default for ShadowCaps {
    fn default() -> Self {
        ShadowCaps { full_float_moments: true, static_maps: true }
    }
}

/// The shadow atlas the lights' tiles are sized for: its shape and what a texel of it costs.
/// Written by [`size_shadow_maps`] (the pages the tiles need, within the memory budget); the
/// renderer makes its pages to this shape.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShadowAtlas {
    /// Its pages.
    pub shape: AtlasShape,
    /// Bytes each of its texels takes: depth, its static copy, a colour map.
    pub texel_bytes: u32,
}

impl ShadowAtlas {
    /// The atlas `settings` give on a device that can do `caps` when the lights use `methods`.
    #[must_use]
    pub fn for_settings(
        settings: &MapSettings,
        caps: ShadowCaps,
        methods: impl Iterator<Item = ShadowMethod>,
    ) -> ShadowAtlas {
        let texel_bytes = texel_bytes(settings, caps, methods);
        let page = MAX_PAGE.max(settings.shadow_map_size.next_power_of_two());
        let budget = u64::from(settings.shadow_memory) << 20;
        ShadowAtlas { shape: AtlasShape::for_budget(budget, texel_bytes, page), texel_bytes }
    }

    /// The memory its pages take, in bytes.
    #[must_use]
    pub fn bytes(&self) -> u64 {
        self.shape.texels() * u64::from(self.texel_bytes)
    }
}

/// Bytes a texel of the atlas takes with `settings` on a device that can do `caps` and lights
/// sampled with `methods`: the depth, a copy of it for the casters at rest (with the static
/// cache), and the widest colour map any of them keeps (moments or depth in colour; 32-bit
/// moments when a method needs them and the device has them), shared by the depth texels each
/// colour texel covers (moments resolved at a half or a quarter of the depth map's side), at
/// least a byte.
fn texel_bytes(settings: &MapSettings, caps: ShadowCaps, methods: impl Iterator<Item = ShadowMethod>) -> u32 {
    let depth = match settings.shadow_depth {
        ShadowDepth::Float32 => 4,
        ShadowDepth::Unorm16 => 2,
    };
    // Whether maps are kept this frame does not matter: the atlas stays as it is when it changes.
    let statics = if settings.static_cache && caps.static_maps { depth } else { 0 };
    let (mut moments, mut channels, mut in_colour) = (0, 0, 0);
    for m in methods {
        moments = moments.max(m.moment_bits());
        channels = channels.max(m.moment_count());
        in_colour = in_colour.max(m.colour_depth_bits());
    }
    let per_channel = match (moments, settings.moment_bits) {
        (0, _) => 0,
        // 32-bit floats, unless every moment method keeps half floats.
        (_, MomentBits::Half) if in_colour <= 16 => 2,
        (16, MomentBits::Auto) if in_colour <= 16 => 2,
        (_, MomentBits::Auto) if !caps.full_float_moments => 2,
        _ => 4,
    };
    let colour = if moments == 0 { in_colour / 8 } else { per_channel * channels };
    let scale = settings.moments_from.colour_scale(in_colour > 0);
    depth + statics + colour.div_ceil(scale * scale)
}

/// What a light surrounding the camera covers: twice a light filling the screen from outside,
/// so that a cube's faces, each of which may fill the screen, get the largest tiles.
const INSIDE: f32 = 2.0;

/// The radius of the disc `reach` covers on screen, as a share of the screen's half height (at
/// most 1 from outside, `INSIDE` when the camera is inside it, 0 when it is wholly behind the
/// camera, infinite for a light that reaches everywhere).
#[must_use]
pub fn coverage(reach: Reach, (eye, forward): (Vec3, Vec3), tan_half_fov: f32) -> f32 {
    let Reach::Sphere { centre, radius } = reach else { return f32::INFINITY };
    let to = centre - eye;
    let distance = to.length();
    if distance <= radius {
        return INSIDE;
    }
    if to.dot(forward) < -radius {
        return 0.0;
    }
    // The sphere's silhouette is a cone of half angle asin(r / d) from the eye.
    let tan = radius / (distance * distance - radius * radius).sqrt();
    (tan / tan_half_fov.max(1e-4)).min(1.0)
}

/// Sizes every shadowed light's layers for this frame (see the module's notes) and writes the
/// atlas they are sized for.
#[allow(clippy::too_many_arguments)]
pub fn size_shadow_maps(
    settings: Res<MapSettings>,
    shadow: Res<ShadowSettings>,
    cascade: Res<CascadeSettings>,
    atlas: Option<ResMut<ShadowAtlas>>,
    caps: Option<Res<ShadowCaps>>,
    cameras: Query<(&Camera, &Transform)>,
    lights: LightSources,
    mut maps: Query<(&mut ShadowMap, Option<&ShadowMethod>)>,
) {
    let sources: Vec<_> = lights.all().into_iter().filter(|s| maps.contains(s.entity)).collect();
    let method = |e: Entity| maps.get(e).ok().and_then(|(_, m)| m.copied()).unwrap_or(shadow.method);
    let caps = caps.map_or_else(ShadowCaps::default, |c| *c);
    let shape = ShadowAtlas::for_settings(&settings, caps, sources.iter().map(|s| method(s.entity)));
    let shape_bytes = shape.texel_bytes;
    let view = cameras.iter().next().map(|(c, t)| ((t.translation, t.forward()), (c.fov_y * 0.5).tan()));
    // No tile is larger than a page.
    let largest = settings.shadow_map_size.min(shape.shape.page);
    let mut classes = Vec::with_capacity(sources.len());
    let mut shows = Vec::with_capacity(sources.len());
    let mut coarse = 0;
    let mut paged = Vec::with_capacity(sources.len());
    let mut needs: Vec<TileNeed> = sources
        .iter()
        .map(|s| {
            let shape = s.kind.shape(&settings, method(s.entity));
            paged.push(shape == ShadowShape::Pages);
            let layers = match shape {
                ShadowShape::Cascades => cascade.cascades,
                ShadowShape::Single => 1,
                ShadowShape::Cube => 6,
                ShadowShape::Pages => {
                    // Its coarse map, never smaller than a tile; the pool that every paged light
                    // shares is counted once, below.
                    let (layers, side) = s.kind.coarse_map(&settings, coarse_side(&settings));
                    coarse = coarse.max(side);
                    shows.push(view.map_or(0.0, |(at, tan)| coverage(s.kind.reach(), at, tan)));
                    classes.push(0);
                    return TileNeed { layers, side: side.max(MIN_TILE), priority: f32::INFINITY };
                }
            };
            let covered = view.map_or(0.0, |(at, tan)| coverage(s.kind.reach(), at, tan));
            shows.push(covered);
            if covered.is_infinite() {
                // Everywhere: a sun's cascades keep the settings' size while anything can shrink.
                classes.push(0);
                return TileNeed { layers, side: largest, priority: f32::INFINITY };
            }
            let current = maps.get(s.entity).map_or(0, |(m, _)| m.wanted);
            let single = shape == ShadowShape::Single;
            let class = match settings.tile_sizes {
                TileSizes::Screen => {
                    size_class(current, texels_for(covered, single, largest), largest, settings.tile_hysteresis)
                }
                TileSizes::Fixed => largest.max(MIN_TILE).ilog2(),
                TileSizes::Bevy => (if single { largest } else { largest / 2 }).max(MIN_TILE).ilog2(),
            };
            classes.push(class);
            let side = (1u32 << class).min(largest);
            TileNeed { layers, side, priority: covered * covered * s.color.max_element().max(1e-3) }
        })
        .collect();
    if coarse > 0 {
        let pool = pool_capacity(&settings, shape_bytes, PAGE_TILE);
        needs.push(TileNeed { layers: pool, side: PAGE_TILE, priority: f32::INFINITY });
    }
    let sides = fit_budget(&needs, shape.shape.texels());
    let fitted = fitted(atlas.as_deref(), shape, (&needs, &sides), coarse);
    // A paged light's pages are the pool's, at the pool's side.
    let pool_side = if coarse > 0 { sides.last().copied().unwrap_or(PAGE_TILE) } else { PAGE_TILE };
    let lights = sources.iter().zip(sides).zip(classes).zip(shows).zip(paged);
    for ((((source, side), class), shows), paged) in lights {
        let side = if paged { pool_side } else { side };
        if let Ok((mut map, _)) = maps.get_mut(source.entity)
            && (map.resolution, map.wanted, map.shows) != (side, class, shows)
        {
            (map.resolution, map.wanted, map.shows) = (side, class, shows);
        }
    }
    if let Some(mut atlas) = atlas
        && *atlas != fitted
    {
        *atlas = fitted;
    }
}

/// The atlas the tiles of `needs` at `sides` take within `budget` ([`AtlasShape::holding`]),
/// or the `current` one while it holds them within the budget and is no more than four times
/// what they need: an atlas made anew draws every layer again, so it does not follow every
/// light that comes and goes. A paged light's need counts its coarse map in pages; `coarse` is
/// that map's side (0: none), which a page of the atlas must hold whole.
fn fitted(
    current: Option<&ShadowAtlas>,
    budget: ShadowAtlas,
    (needs, sides): (&[TileNeed], &[u32]),
    coarse: u32,
) -> ShadowAtlas {
    let tile = |side: u32| u64::from(side.next_power_of_two()).pow(2);
    let used: u64 = needs.iter().zip(sides).map(|(n, &s)| u64::from(n.layers) * tile(s)).sum();
    let largest = sides.iter().map(|s| s.next_power_of_two()).max().unwrap_or(MIN_TILE).max(coarse);
    let fitted = ShadowAtlas { shape: budget.shape.holding(used, largest), ..budget };
    match current {
        Some(c)
            if c.texel_bytes == budget.texel_bytes
                && c.shape.page >= largest
                && c.shape.texels() >= fitted.shape.texels()
                && c.shape.texels() <= budget.shape.texels()
                && c.shape.texels() / 4 <= fitted.shape.texels() =>
        {
            *c
        }
        _ => fitted,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::{DirectionalLight, PointLight, SpotLight};
    use crate::settings::MomentSource;
    use crate::settings::Settings;
    use bevy_ecs::system::RunSystemOnce;

    #[test]
    fn a_texel_costs_its_depth_its_static_copy_and_its_widest_colour_map() {
        let d = Settings::default().with(|s| s.maps.static_cache = true);
        let bytes = |s: &Settings, m: &[ShadowMethod]| texel_bytes(&s.maps, ShadowCaps::default(), m.iter().copied());
        assert_eq!(bytes(&d, &[ShadowMethod::Bilinear]), 8);
        assert_eq!(bytes(&Settings::default(), &[ShadowMethod::Pcf3]), 4, "no static copies by default");
        assert_eq!(bytes(&d, &[ShadowMethod::Evsm]), 16, "half-float moments");
        assert_eq!(bytes(&d, &[ShadowMethod::Vsm, ShadowMethod::Evsm]), 24, "32-bit moments for VSM");
        assert_eq!(bytes(&d, &[ShadowMethod::RadialR16f]), 10);
        assert_eq!(bytes(&d, &[ShadowMethod::Evsm, ShadowMethod::DepthR32f]), 24, "R32F makes the moments 32-bit");
        let d16 = d.clone().with(|s| s.maps.shadow_depth = ShadowDepth::Unorm16);
        assert_eq!(bytes(&d16, &[ShadowMethod::Bilinear]), 4);
        // GL: half-float moments, no static copies.
        let gl = ShadowCaps { full_float_moments: false, static_maps: false };
        assert_eq!(texel_bytes(&d.maps, gl, [ShadowMethod::Vsm].into_iter()), 8);
        // Two moments take two channels, unless a method beside them keeps four.
        assert_eq!(bytes(&d, &[ShadowMethod::Vsm]), 16);
        assert_eq!(bytes(&d, &[ShadowMethod::Evsm2]), 12);
        assert_eq!(bytes(&d, &[ShadowMethod::Vsm, ShadowMethod::Msm]), 24);
        // Moments at half the side share a colour texel among four depth texels, at a quarter
        // among sixteen; depth in colour keeps every texel.
        let half = d.clone().with(|s| s.maps.moments_from = MomentSource::Half);
        assert_eq!(bytes(&half, &[ShadowMethod::Evsm]), 8 + 2);
        assert_eq!(bytes(&half, &[ShadowMethod::Vsm]), 8 + 2);
        assert_eq!(bytes(&half, &[ShadowMethod::Vsm, ShadowMethod::RadialR16f]), 8 + 8);
        let quarter = d.clone().with(|s| s.maps.moments_from = MomentSource::Quarter);
        assert_eq!(bytes(&quarter, &[ShadowMethod::Evsm]), 8 + 1);
    }

    #[test]
    fn the_default_atlas_is_256_mib_of_four_pages_at_most() {
        let atlas = ShadowAtlas::for_settings(
            &MapSettings::default(),
            ShadowCaps::default(),
            [ShadowMethod::Bilinear].into_iter(),
        );
        assert_eq!(atlas.shape, AtlasShape { page: 4096, pages: 4 });
        assert_eq!(atlas.bytes(), 256 << 20);
    }

    #[test]
    fn a_near_lamp_gets_more_texels_than_a_far_one_and_the_sun_its_own() {
        let mut world = World::new();
        Settings::default().put(&mut world).unwrap();
        world.insert_resource(ShadowAtlas::for_settings(
            &MapSettings::default(),
            ShadowCaps::default(),
            std::iter::empty(),
        ));
        world.spawn((Camera::default(), Transform::from_xyz(0.0, 2.0, 0.0).looking_to(Vec3::NEG_Z)));
        let lamp = |z: f32| (PointLight { range: 3.0, ..Default::default() }, Transform::from_xyz(0.0, 2.0, z));
        let near = world.spawn((lamp(-6.0), ShadowMap::default())).id();
        let far = world.spawn((lamp(-60.0), ShadowMap::default())).id();
        let behind = world.spawn((lamp(40.0), ShadowMap::default())).id();
        let sun = world.spawn((DirectionalLight::default(), ShadowMap::default())).id();
        world.run_system_once(size_shadow_maps).unwrap();
        let side = |world: &World, e| world.get::<ShadowMap>(e).unwrap().resolution;
        let side = |e| side(&world, e);
        assert_eq!(side(sun), Settings::default().maps.shadow_map_size);
        assert!(side(near) >= 4 * side(far), "{} against {}", side(near), side(far));
        assert_eq!(side(behind), crate::shadow::MIN_TILE);
        // A tiny budget: everything shrinks, the sun last.
        world.resource_mut::<crate::settings::MapSettings>().shadow_memory = 16;
        world.run_system_once(size_shadow_maps).unwrap();
        let side = |e| world.get::<ShadowMap>(e).unwrap().resolution;
        let atlas = *world.resource::<ShadowAtlas>();
        assert!(atlas.bytes() <= 16 << 20, "{atlas:?}");
        let used: u64 = [(sun, 4), (near, 6), (far, 6), (behind, 6)]
            .iter()
            .map(|&(e, n)| n * u64::from(side(e).next_power_of_two()).pow(2))
            .sum();
        assert!(used <= atlas.shape.texels(), "{used} texels in {:?}", atlas.shape);
    }

    #[test]
    fn paged_lights_keep_their_coarse_maps_and_share_one_pool() {
        let mut world = World::new();
        let settings = Settings::default().with(|s| {
            s.maps.light_maps = crate::settings::LightMaps::Virtual;
            s.maps.sun_maps = crate::settings::SunMaps::Virtual;
        });
        settings.put(&mut world).unwrap();
        // An atlas too small to keep: the one made holds what the lights need.
        world.insert_resource(ShadowAtlas { shape: AtlasShape { page: 128, pages: 1 }, texel_bytes: 4 });
        world.spawn((Camera::default(), Transform::from_xyz(0.0, 2.0, 0.0).looking_to(Vec3::NEG_Z)));
        world.spawn((DirectionalLight::default(), ShadowMap::default()));
        world.spawn((SpotLight::default(), Transform::from_xyz(0.0, 2.0, -5.0), ShadowMap::default()));
        let lamp = PointLight { range: 3.0, ..Default::default() };
        for k in 0..100 {
            world.spawn((lamp, Transform::from_xyz(k as f32, 2.0, -10.0), ShadowMap::default()));
        }
        world.run_system_once(size_shadow_maps).unwrap();
        let atlas = *world.resource::<ShadowAtlas>();
        // The pool once (32 MiB of 64² depth pages), the sun's 1024² coarse map, the spot's 256²
        // and each lamp's six 64² faces: 2048 + 256 + 16 + 600 tiles of 64².
        let tiles = 2048 + 256 + 16 + 100 * 6;
        assert!(atlas.shape.texels() >= tiles * 64 * 64, "{atlas:?}");
        assert!(atlas.bytes() < 2 * tiles * 64 * 64 * 4, "about what they need, not a pool each: {atlas:?}");
        let mut maps = world.query::<&ShadowMap>();
        assert!(maps.iter(&world).all(|m| m.resolution == PAGE_TILE), "a paged light's pages are the pool's");
    }

    #[test]
    fn the_baselines_size_every_lamp_alike_wherever_it_is() {
        let mut world = World::new();
        let settings = Settings::default().with(|s| {
            s.maps.tile_sizes = TileSizes::Bevy;
            s.maps.shadow_memory = 4096;
        });
        settings.put(&mut world).unwrap();
        world.spawn((Camera::default(), Transform::from_xyz(0.0, 2.0, 0.0).looking_to(Vec3::NEG_Z)));
        let far = PointLight { range: 3.0, ..Default::default() };
        let lamp = world.spawn((far, Transform::from_xyz(0.0, 2.0, -60.0), ShadowMap::default())).id();
        let spot = world.spawn((SpotLight::default(), Transform::from_xyz(0.0, 2.0, 40.0), ShadowMap::default())).id();
        let side = |world: &mut World, e| {
            world.run_system_once(size_shadow_maps).unwrap();
            world.get::<ShadowMap>(e).unwrap().resolution
        };
        assert_eq!((side(&mut world, lamp), side(&mut world, spot)), (1024, 2048), "Bevy's defaults");
        world.resource_mut::<crate::settings::MapSettings>().tile_sizes = TileSizes::Fixed;
        assert_eq!((side(&mut world, lamp), side(&mut world, spot)), (2048, 2048), "umbra before the atlas");
    }
}
