//! Extraction: the world's components turned into the structs the shaders read.
//!
//! Pure CPU code, so what the GPU is told can be tested without a GPU. Every light of
//! [`light_list`] becomes one [`GpuLight`], and its layers take the next slots of the shadow-map
//! array: slots are the renderer's business, not the world's.

use super::frame::{DrawItem, FrameData, FrameLight, LayerDraw, MAX_PLANAR, SHADOW_FADE, Shadowless};
use super::gpu_types::{Frame, GpuLayer, Object};
use super::planar::{ground, planar_draws};
use crate::components::*;
use crate::light::clusters::{ClusterView, LightGrid, Reach};
use crate::light::{Kind, Light, light_list};
use crate::settings::{CasterCulling, FrameSettings, ShadowSettings};
use crate::shadow::{Aabb, CUBE_FACES, CasterIndex, intersects_clip_volume, nearest_depth};
use crate::systems::CastersAtRest;
use bevy_ecs::prelude::*;
use bytemuck::Zeroable;
use glam::{Mat4, Vec3};

/// Steps of this frame's contact-shadow march: the settings' when shadows are on and a
/// shadowed light asks for contact shadows, else none (and no camera depth is drawn for it).
#[must_use]
fn contact_steps<'a>(settings: &ShadowSettings, mut lights: impl Iterator<Item = &'a Light>) -> u32 {
    if settings.enabled && lights.any(|l| l.shadowed && l.contact) { settings.contact_steps } else { 0 }
}

/// The shadow-map layers of one light, each with the casters inside its volume (and inside the
/// camera's view too, when `camera` is given: the camera-view culling shortcut).
///
/// A moment map takes the receivers that cast no shadow as well (the sample's ground): its
/// filtered edge is a mix of the caster's depth and what lies behind it, and if that is the far
/// plane rather than the receiver, Chebyshev's bound at the receiver lights most of the edge and
/// the shadow shrinks (on the plates test, VSM drew no soft edge at all). So in a moment method
/// a receiver shadows what lies behind it from the light; in the sample nothing does.
fn layer_draws(
    light: &Light,
    first_slot: usize,
    (items, index): (&[(DrawItem, Aabb)], &CasterIndex),
    camera: Option<&Mat4>,
) -> Vec<LayerDraw> {
    let Light { entity, label, method, shows, .. } = *light;
    let keep = |(item, bounds): &(DrawItem, Aabb)| {
        (item.caster || (method.moments() && item.object.receives_shadows == 1))
            && camera.is_none_or(|vp| intersects_clip_volume(vp, bounds))
    };
    light
        .layers
        .iter()
        .enumerate()
        .map(|(k, l)| LayerDraw {
            light: label,
            // A page is named by its slot, so it keeps its tile while it stays resident; its
            // names start past a coarse map's layers (a cube's six faces at most).
            key: (entity.to_bits(), l.page.map_or(k as u32, |p| CUBE_FACES.len() as u32 + p.slot)),
            slot: (first_slot + k) as u32,
            resolution: l.resolution,
            tile: None,
            fresh: false,
            shows,
            clip_from_world: l.clip_from_world,
            version: l.version,
            static_version: l.static_version,
            method,
            casters: index.inside(&l.clip_from_world).into_iter().filter(|&i| keep(&items[i])).collect(),
            page: l.page.map(|p| p.id),
        })
        .collect()
}

/// How near to a paged light at a point (`perspective`) the casters of its coarse map (`draws`:
/// its layers' draws, pages after the coarse map) come along its axis, for PCSS's blocker search
/// on pages (`coarse_penumbra` in lights.wgsl): a search as wide as a blocker at the map's near
/// plane would throw its penumbra is mostly empty round a thin caster, and so misses it. 0 (not
/// measured) for a sun, whose maps' near planes are fitted to its casters; `f32::MAX` where it
/// has no caster (nothing can be found).
fn nearest_caster(draws: &[LayerDraw], items: &[(DrawItem, Aabb)], perspective: bool) -> f32 {
    if !perspective {
        return 0.0;
    }
    draws
        .iter()
        .filter(|d| d.page.is_none())
        .filter_map(|d| nearest_depth(&d.clip_from_world, d.casters.iter().map(|&i| &items[i].1)))
        .fold(f32::INFINITY, f32::min)
        .min(f32::MAX)
}

/// The culling hierarchy of the last frame's objects, kept to be refitted rather than built
/// afresh (see [`CasterIndex::refitted`]).
#[derive(Default)]
pub(super) struct KeptIndex(Option<CasterIndex>);

/// The objects of the world to draw, with their bounds, and the joint matrices they read; their
/// normal matrices only if they are to be lit (`lit`), not when only their shadows are drawn.
fn draw_items(world: &World, lit: bool) -> (Vec<(DrawItem, Aabb)>, Vec<Mat4>) {
    let mut joints = Vec::new();
    // None until a mesh has been spawned: nothing to draw.
    let Some(mut query) = world.try_query::<(
        Entity,
        &Mesh,
        &Transform,
        &WorldBounds,
        Option<&Material>,
        Option<&Joints>,
        Has<ShadowCaster>,
        Has<ShadowReceiver>,
    )>() else {
        return (Vec::new(), joints);
    };
    let library = world.resource::<crate::assets::MeshLibrary>();
    let at_rest = world.get_resource::<CastersAtRest>();
    let items = query
        .iter(world)
        .map(|(entity, mesh, t, bounds, material, skin, caster, receiver)| {
            let m = material.copied().unwrap_or_default();
            let world_from_local = t.matrix();
            let object = Object {
                world_from_local,
                normal_from_local: if lit { world_from_local.inverse().transpose() } else { Mat4::ZERO },
                base_color: m.base_color.extend(m.opacity),
                specular: m.specular,
                shininess: m.shininess.max(1.0),
                alpha_cutoff: m.alpha_mode.cutoff().unwrap_or(0.0),
                receives_shadows: receiver as u32,
                first_joint: joints.len() as u32,
                ..Object::zeroed()
            };
            joints.extend(skin.map_or(&[][..], |s| &s.0));
            let item = DrawItem {
                mesh: *mesh,
                object,
                caster,
                // Joints move only a mesh that has influences; any other is drawn rigid.
                skinned: skin.is_some() && library.get(*mesh).is_some_and(|m| m.skin.is_some()),
                texture: m.texture,
                alpha: m.alpha_mode,
                double_sided: m.double_sided,
                at_rest: caster && at_rest.is_some_and(|r| r.0.contains(&entity)),
            };
            (item, bounds.0)
        })
        .collect();
    (items, joints)
}

/// Reads the world into the data one frame needs. Without a camera nothing is drawn.
#[must_use]
pub fn extract(world: &World) -> FrameData {
    read_world(world, true, &mut KeptIndex::default())
}

/// [`extract`] for a frame that draws the shadow maps and nothing else: what only the main pass
/// reads (normal matrices, the draw order, planar shadows, the ground's flags) is left out, so
/// that with tens of thousands of objects the shadow pass does not pay for a picture it never
/// draws.
#[must_use]
pub fn extract_shadow_maps(world: &World) -> FrameData {
    read_world(world, false, &mut KeptIndex::default())
}

/// [`extract`] (with `main_pass`) or [`extract_shadow_maps`], refitting the culling hierarchy
/// `kept` from the last frame and keeping this frame's there.
///
/// # Panics
/// If `world` lacks a group of settings (a world not made by [`crate::App`]); the renderer
/// refuses such a world before it gets here.
pub(super) fn read_world(world: &World, main_pass: bool, kept: &mut KeptIndex) -> FrameData {
    let settings = FrameSettings::of(world).expect("a world made by umbra::App holds every group of settings");
    let aspect = world.resource::<Viewport>().aspect();
    let viewport = *world.resource::<Viewport>();
    let (clip_from_world, eye, forward, depths, pixel_angle) = world
        .try_query::<(&Camera, &Transform)>()
        .and_then(|mut q| q.iter(world).next().map(|(c, t)| (*c, *t)))
        .map_or((Mat4::ZERO, Vec3::ZERO, Vec3::NEG_Z, (0.1, 1.0), 0.0), |(c, t)| {
            let pixel_angle = c.pixel_angle(viewport.height);
            (c.view_proj(&t, aspect), t.translation, t.forward(), (c.near, c.far), pixel_angle)
        });
    let (mut items, joints) = draw_items(world, main_pass);
    let cull_to = (settings.maps.caster_culling == CasterCulling::CameraView).then_some(&clip_from_world);
    let bounds: Vec<Aabb> = items.iter().map(|(_, b)| *b).collect();
    let index = match kept.0.take() {
        Some(last) => last.refitted(&bounds),
        None => CasterIndex::new(&bounds),
    };
    let draw_order =
        if main_pass { draw_order(&items, eye, &in_view(&index, &bounds, &clip_from_world)) } else { Vec::new() };
    let (mut lights, mut layers, mut draws, mut methods) = (Vec::new(), Vec::new(), Vec::new(), 0);
    let mut shadowless = Vec::new();
    for light in light_list(world) {
        let mut nearest = 0.0;
        // A planar light has no layers (its shadow is drawn over the ground instead).
        let count = if light.method != ShadowMethod::Planar { light.layers.len() } else { 0 };
        if count > 0 {
            // With shadows off the pipeline holds no sampling code at all: on a software
            // rasterizer a wide filter's code slows every fragment even where it never runs.
            if settings.shadow.enabled {
                methods |= 1 << light.method as u32;
            }
            let drawn = draws.len();
            draws.extend(layer_draws(&light, layers.len(), (&items, &index), cull_to));
            // Where a light at a point is; nothing for one infinitely far away (w = 0). A light at
            // a point sees in perspective, every layer of it: its map or faces, or its pages.
            let at = light.kind.homogeneous();
            if light.reads_coarser_pages(settings.shadow.pcss_blocker_search) {
                nearest = nearest_caster(&draws[drawn..], &items, at.w > 0.0);
            }
            let origin = (at.truncate() * at.w).to_array();
            layers.extend(light.layers.iter().map(|l| GpuLayer {
                clip_from_world: l.clip_from_world,
                texel_base: l.texel.x,
                texel_per_metre: l.texel.y,
                far: l.far,
                blend: l.blend,
                depth_terms: l.depth.to_array(),
                method: light.method as u32,
                perspective: (at.w > 0.0) as u32,
                bleed: settings.shadow.light_bleeding,
                origin,
                ..GpuLayer::zeroed()
            }));
        }
        let first_layer = (layers.len() - count) as u32;
        let (layer_count, nearest_caster) = (count as u32, nearest);
        lights.push(FrameLight { light, first_layer, layer_count, planar_ground: false, page_word: 0, nearest_caster });
    }
    // The clustered light lists, for the main pass only.
    let (grid, clusters) = if main_pass {
        let reaches: Vec<Reach> = lights.iter().map(|l| l.light.kind.reach()).collect();
        let view = ClusterView::new(clip_from_world, (eye, forward.normalize_or(Vec3::NEG_Z)), depths, &reaches);
        (LightGrid::build(&view, &reaches), (view.near, view.far))
    } else {
        (LightGrid::default(), (0.1, 1.0))
    };
    let frame = Frame {
        clip_from_world,
        camera_position: eye.to_array(),
        shadow_distance: settings.cascade.shadow_distance,
        camera_forward: forward.to_array(),
        fade_start: settings.cascade.shadow_distance * (1.0 - SHADOW_FADE),
        ambient: settings.view.ambient,
        shadow_strength: settings.shadow.shadow_strength,
        shadows_on: settings.shadow.enabled as u32,
        cascade_debug: settings.view.cascade_debug as u32,
        light_count: lights.len() as u32,
        atlas_guard: settings.maps.atlas_guard as u32,
        page_fallback: settings.maps.page_fallback as u32,
        cluster_near: clusters.0,
        cluster_far: clusters.1,
        cube_seams: settings.maps.cube_seams as u32,
        depth_bias_metres: settings.shadow.depth_bias_metres,
        pcss_search: settings.shadow.pcss_blocker_search as u32,
        toon_bands: settings.view.toon_bands,
        texel_view: settings
            .view
            .texel_density
            .as_ref()
            .and_then(|name| lights.iter().position(|l| l.light.label.to_string() == *name))
            .map_or(0, |i| i as u32 + 1),
        contact_steps: contact_steps(settings.shadow, lights.iter().map(|l| &l.light)),
        contact_length: settings.shadow.contact_length,
        contact_thickness: settings.shadow.contact_thickness,
        camera_near: depths.0,
        camera_far: depths.1,
        pixel_angle,
        ..Frame::zeroed()
    };
    if main_pass
        && settings.view.ground_grid
        && let Some(g) = ground(&items)
    {
        items[g].0.object.ground_grid = 1;
    }
    let mut planar = if settings.shadow.enabled && main_pass {
        planar_draws(&lights, &items, settings.shadow.planar_ground)
    } else {
        Vec::new()
    };
    for dropped in planar.drain(MAX_PLANAR.min(planar.len())..) {
        shadowless.push((lights[dropped.uniform.light as usize].light.label, Shadowless::StencilFull));
    }
    // With planar shadows on the ground for lights that keep their maps, the ground leaves
    // those maps unread (`planar_receiver`, `planar_ground`).
    if settings.shadow.enabled && settings.shadow.planar_ground && main_pass {
        for p in &planar {
            let light = &mut lights[p.uniform.light as usize];
            light.planar_ground = light.layer_count > 0;
        }
        if let Some(g) = ground(&items) {
            items[g].0.object.planar_receiver = 1;
        }
    }
    kept.0 = Some(index);
    let items = items.into_iter().map(|(item, _)| item).collect();
    FrameData {
        frame,
        lights,
        layers,
        items,
        draws,
        clip_from_world,
        joints,
        draw_order,
        methods,
        planar,
        grid,
        shadowless,
        page_words: Vec::new(),
    }
}

/// Which objects the camera may see: those whose box meets its view volume, and those whose box
/// is not usable (where they are is unknown, so they are drawn).
fn in_view(index: &CasterIndex, bounds: &[Aabb], clip_from_world: &Mat4) -> Vec<bool> {
    let mut seen: Vec<bool> = bounds.iter().map(|b| !b.is_usable()).collect();
    for i in index.inside(clip_from_world) {
        seen[i] = true;
    }
    seen
}

/// The main pass's order of the objects the camera may see (`seen`, by object): opaque and masked
/// objects front to back, then blended ones back to front, so each blends over what is behind it.
/// The rest are not drawn: with 100,000 objects mostly out of view, a software rasterizer kept
/// hundreds of megabytes for draws that made no pixel.
///
/// Front to back lets the depth test reject hidden fragments before they are shaded. Objects are
/// ranked by the distance from `eye` to the farthest corner of their bounds, which puts near,
/// small objects first and the ground, which reaches farthest, last: on the sample scene this
/// shades about a fifth fewer fragments than drawing the ground first (measured: the main pass
/// at 1280x720 on the software rasterizer took 20% longer when the ground came first).
fn draw_order(items: &[(DrawItem, Aabb)], eye: Vec3, seen: &[bool]) -> Vec<usize> {
    let farthest = |b: &Aabb| b.corners().iter().map(|c| c.distance_squared(eye)).fold(0.0f32, f32::max);
    let centre = |b: &Aabb| b.center().distance_squared(eye);
    let blended = |i: &usize| items[*i].0.alpha == AlphaMode::Blend;
    let shown = || (0..items.len()).filter(|&i| seen[i]);
    let mut solid: Vec<(f32, usize)> = shown().filter(|i| !blended(i)).map(|i| (farthest(&items[i].1), i)).collect();
    solid.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut back: Vec<(f32, usize)> = shown().filter(blended).map(|i| (centre(&items[i].1), i)).collect();
    back.sort_by(|a, b| b.0.total_cmp(&a.0));
    solid.into_iter().chain(back).map(|(_, i)| i).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::Settings;

    #[test]
    fn lights_and_their_layers_are_carried_over_in_slot_order() {
        let mut app = crate::App::new(Settings::default()).unwrap();
        app.set_time(0.0);
        let data = extract(&app.world);
        let ground = data.items.iter().filter(|i| !i.caster).count();
        assert_eq!(ground, 1, "only the ground is not a caster");
        assert!(data.items.iter().all(|i| i.object.receives_shadows == 1), "all sample surfaces receive");
        // Every light's layers follow the one before's: slots are handed out in light order.
        let mut next = 0;
        for light in data.gpu_lights() {
            assert_eq!(light.first_layer, next);
            next += light.layer_count;
        }
        assert_eq!(next as usize, data.layers.len());
        let slots: Vec<u32> = data.draws.iter().map(|d| d.slot).collect();
        assert_eq!(slots, (0..next).collect::<Vec<_>>());
        assert_eq!(data.frame.light_count as usize, data.lights.len());
        assert_eq!(data.labels()[0].to_string(), "sun");
        assert_eq!(data.lights[0].layer_count, Settings::default().cascade.cascades);
        assert_eq!(data.methods, 1 << Settings::default().shadow.method as u32);
        assert_ne!(data.clip_from_world, Mat4::ZERO);
    }

    #[test]
    fn a_light_at_a_point_sees_in_perspective_through_every_layer_paged_or_not() {
        for light_maps in crate::settings::LightMaps::ALL {
            let settings = Settings::default().with(|s| s.maps.light_maps = *light_maps);
            let mut app = crate::App::new(settings).unwrap();
            app.set_time(0.0);
            let data = extract(&app.world);
            for light in &data.lights {
                let at_a_point = light.light.kind.homogeneous().w > 0.0;
                let layers = light.first_layer as usize..(light.first_layer + light.layer_count) as usize;
                assert!(!layers.is_empty(), "{} is shadowed", light.light.label);
                for layer in &data.layers[layers] {
                    assert_eq!(layer.perspective == 1, at_a_point, "{} with {light_maps:?}", light.light.label);
                }
            }
        }
    }

    #[test]
    fn solid_objects_are_drawn_front_to_back_and_blended_ones_last_from_the_farthest() {
        let item = |alpha| DrawItem {
            mesh: Mesh(0),
            object: Object::zeroed(),
            caster: true,
            skinned: false,
            texture: None,
            alpha,
            double_sided: false,
            at_rest: false,
        };
        let at = |z: f32| Aabb::new(Vec3::new(0.0, 0.0, z), Vec3::new(1.0, 1.0, z + 1.0));
        let ground = Aabb::new(Vec3::new(-40.0, 0.0, -40.0), Vec3::new(40.0, 0.0, 40.0));
        let items = [
            (item(AlphaMode::Blend), at(-2.0)),
            (item(AlphaMode::Opaque), ground),
            (item(AlphaMode::Opaque), at(-9.0)),
            (item(AlphaMode::Blend), at(-8.0)),
            (item(AlphaMode::Mask { cutoff: 0.5 }), at(-1.0)),
            (item(AlphaMode::Blend), at(-5.0)),
        ];
        // The ground reaches farthest: it comes after the boxes, though its centre is nearest.
        let all = [true; 6];
        assert_eq!(draw_order(&items, Vec3::new(0.0, 2.0, 0.0), &all), vec![4, 2, 1, 3, 5, 0]);
        let unseen = [true, true, false, true, false, true];
        assert_eq!(draw_order(&items, Vec3::new(0.0, 2.0, 0.0), &unseen), vec![1, 3, 5, 0]);
    }

    #[test]
    fn the_main_pass_leaves_out_what_the_camera_cannot_see_and_keeps_what_it_cannot_place() {
        // A camera at the origin looking down -Z: a box ahead, one behind, one far to the side,
        // one past the far plane, and one whose box is not finite.
        let camera = Camera { near: 0.1, far: 50.0, ..Camera::default() };
        let clip_from_world = camera.view_proj(&Transform::default(), 1.0);
        let at = |x: f32, z: f32| Aabb::new(Vec3::new(x, 0.0, z), Vec3::new(x + 1.0, 1.0, z + 1.0));
        let bounds = [at(0.0, -5.0), at(0.0, 5.0), at(40.0, -5.0), at(0.0, -80.0), Aabb::new(Vec3::NAN, Vec3::NAN)];
        let seen = in_view(&CasterIndex::new(&bounds), &bounds, &clip_from_world);
        assert_eq!(seen, vec![true, false, false, false, true]);
    }

    #[test]
    fn each_layer_draws_only_the_casters_inside_its_volume() {
        let mut app = crate::App::new(Settings::default()).unwrap();
        app.set_time(0.0);
        let bounds: Vec<Aabb> = app.world.query::<(&Mesh, &WorldBounds)>().iter(&app.world).map(|(_, b)| b.0).collect();
        let data = extract(&app.world);
        for layer in &data.draws {
            for (i, item) in data.items.iter().enumerate() {
                let inside = item.caster && intersects_clip_volume(&layer.clip_from_world, &bounds[i]);
                assert_eq!(layer.casters.contains(&i), inside, "{} slot {} item {i}", layer.light, layer.slot);
            }
        }
        // The spot lights see only part of the scene: culling leaves casters out of their layers.
        let casters = data.items.iter().filter(|i| i.caster).count();
        let spot = data.draws.iter().find(|l| l.light.to_string() == "spot 1").unwrap();
        assert!(!spot.casters.is_empty() && spot.casters.len() < casters, "{} of {casters}", spot.casters.len());
    }

    #[test]
    fn a_frame_of_shadow_maps_alone_draws_the_same_layers_and_leaves_the_picture_out() {
        let settings = Settings::default().with(|s| {
            s.shadow.planar_ground = true;
            s.view.ground_grid = true;
        });
        let mut app = crate::App::new(settings).unwrap();
        app.set_time(0.5);
        let full = extract(&app.world);
        let shadows = extract_shadow_maps(&app.world);
        assert_eq!(shadows.draws, full.draws);
        assert_eq!(shadows.layers, full.layers);
        assert_eq!(shadows.joints, full.joints);
        let placed = |d: &FrameData| d.items.iter().map(|i| (i.mesh, i.object.world_from_local)).collect::<Vec<_>>();
        assert_eq!(placed(&shadows), placed(&full));
        assert!(!full.draw_order.is_empty() && !full.planar.is_empty());
        assert!(shadows.draw_order.is_empty() && shadows.planar.is_empty());
        assert!(shadows.items.iter().all(|i| i.object.normal_from_local == Mat4::ZERO && i.object.ground_grid == 0));
    }

    #[test]
    fn the_march_runs_only_when_shadows_are_on_and_a_shadowed_light_asks_for_it() {
        let steps = |settings: Settings| {
            let mut app = crate::App::new(settings).unwrap();
            app.set_time(0.0);
            extract(&app.world).frame.contact_steps
        };
        let on = Settings::default().with(|s| s.shadow.contact_shadows = true);
        assert_eq!(steps(Settings::default()), 0);
        assert_eq!(steps(on.clone()), on.shadow.contact_steps);
        assert_eq!(steps(on.with(|s| s.shadow.enabled = false)), 0);
    }
}
