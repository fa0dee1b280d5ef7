//! The shadow-map cache is invisible: 300 frames of random motion (a sun, two spots, a point
//! light, and a second point light that comes and goes) rendered once drawing every shadow map
//! every frame and once drawing only dirty lights' maps, the casters at rest kept in static
//! maps, give bit-identical pictures, and when nothing moves nothing is drawn.

mod common;

use common::gpu;
use glam::{Quat, Vec3};
use umbra::assets::{MeshLibrary, cube, plane};
use umbra::components::*;
use umbra::render::{HEADLESS_FORMAT, Image, Renderer, ShadowStats, render_headless};
use umbra::systems::CasterChanges;
use umbra::{App, Settings};
use wgpu::DownlevelFlags;

const FRAMES: usize = 300;
const SIZE: u32 = 128;

/// A small deterministic generator (xorshift) so a failure reproduces.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
    fn signed(&mut self) -> f32 {
        2.0 * self.next() - 1.0
    }
}

/// What moves during a stretch of frames.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Stretch {
    Still,
    OneCube,
    Cubes,
    Lights,
    Camera,
    Character,
    Everything,
}

/// The motion script: stretches of 8 to 40 frames, each with its own kind of motion, starting
/// and ending still.
fn script(rng: &mut Rng) -> Vec<Stretch> {
    let kinds = [
        Stretch::Still,
        Stretch::OneCube,
        Stretch::Cubes,
        Stretch::Lights,
        Stretch::Camera,
        Stretch::Character,
        Stretch::Everything,
    ];
    let mut frames = vec![Stretch::Still; 10];
    while frames.len() < FRAMES - 20 {
        let kind = kinds[(rng.next() * kinds.len() as f32) as usize % kinds.len()];
        let len = 8 + (rng.next() * 32.0) as usize;
        frames.extend(std::iter::repeat_n(kind, len));
    }
    frames.truncate(FRAMES - 20);
    frames.extend([Stretch::Still; 20]);
    frames
}

/// Frames at which a second point light is added and removed again.
const LAMP_COMES: usize = 100;
const LAMP_GOES: usize = 200;

struct World {
    app: App,
    cubes: Vec<bevy_ecs::entity::Entity>,
    /// The second point light while it is there.
    visitor: Option<bevy_ecs::entity::Entity>,
    /// Scene time: it runs only while the walking, skinned character moves.
    clock: f64,
}

fn build(reuse: bool, method: ShadowMethod) -> World {
    let settings = Settings::default().with(|s| {
        s.maps.shadow_map_size = 512;
        s.cascade.cascades = 3;
        s.maps.reuse_shadow_maps = reuse;
        s.maps.static_cache = reuse;
        s.shadow.method = method;
    });
    let mut app = App::empty(settings).unwrap();
    let (ground, block) = {
        let mut meshes = app.world.resource_mut::<MeshLibrary>();
        (meshes.add(plane(40.0)), meshes.add(cube(Vec3::splat(0.5))))
    };
    app.world.spawn((ground, Material::color(0.6, 0.6, 0.6), ShadowReceiver));
    let cubes = (0..6)
        .map(|i| {
            let at = Transform::from_xyz(-5.0 + 2.0 * i as f32, 1.0, -2.0 + (i % 3) as f32 * 2.0);
            app.world.spawn((block, at, Material::color(0.8, 0.4, 0.2), ShadowCaster, ShadowReceiver)).id()
        })
        .collect();
    let sun = DirectionalLight {
        direction: Vec3::new(-0.4, -1.0, -0.3),
        color: Vec3::ONE,
        intensity: 1.0,
        ..Default::default()
    };
    app.world.spawn((sun, ShadowMap::default()));
    for (x, cookie) in [(-3.0, Some(Cookie::Window)), (3.0, None)] {
        let spot = SpotLight {
            color: Vec3::new(0.4, 0.8, 1.0),
            intensity: 3.0,
            range: 14.0,
            inner_angle: 0.35,
            outer_angle: 0.45,
            ..Default::default()
        };
        let at = Transform::from_xyz(x, 6.0, 0.0).looking_to(Vec3::new(0.2, -1.0, 0.1));
        let mut light = app.world.spawn((spot, at, ShadowMap::default()));
        if let Some(c) = cookie {
            light.insert(c);
        }
    }
    let lamp = PointLight { color: Vec3::new(1.0, 0.8, 0.5), intensity: 3.0, range: 9.0, ..Default::default() };
    app.world.spawn((lamp, Transform::from_xyz(1.0, 2.5, 0.5), ShadowMap::default()));
    let character =
        std::sync::Arc::new(umbra::assets::parse_model(umbra::scene::CHARACTER_GLB, None, "character").unwrap());
    let walker = umbra::scene::spawn_model(&mut app.world, character, Transform::default(), Some(0));
    app.world.entity_mut(walker).insert(Walker {
        center: Vec3::new(0.0, 0.0, 1.0),
        radius: 2.0,
        speed: 1.35,
        phase: 0.0,
    });
    let eye = Vec3::new(0.0, 7.0, 13.0);
    app.world.spawn((
        Camera::default(),
        Transform::from_xyz(eye.x, eye.y, eye.z).looking_to(Vec3::new(0.0, 0.5, 0.0) - eye),
    ));
    app.resize(SIZE, SIZE);
    World { app, cubes, visitor: None, clock: 0.0 }
}

fn apply(w: &mut World, frame: usize, stretch: Stretch, rng: &mut Rng) {
    let world = &mut w.app.world;
    if frame == LAMP_COMES {
        let lamp = PointLight { intensity: 2.0, range: 8.0, ..Default::default() };
        w.visitor = Some(world.spawn((lamp, Transform::from_xyz(-3.0, 1.5, 2.0), ShadowMap::default())).id());
    }
    if frame == LAMP_GOES
        && let Some(e) = w.visitor.take()
    {
        world.despawn(e);
    }
    let moves_cubes = matches!(stretch, Stretch::Cubes | Stretch::Everything);
    for (i, e) in w.cubes.iter().enumerate() {
        if moves_cubes || (stretch == Stretch::OneCube && i == 2) {
            let mut t = world.get_mut::<Transform>(*e).unwrap();
            t.translation += Vec3::new(rng.signed(), rng.signed(), rng.signed()) * 0.08;
            t.translation.y = t.translation.y.clamp(0.6, 3.0);
            t.rotation = Quat::from_rotation_y(rng.signed() * 0.1) * t.rotation;
        }
    }
    if matches!(stretch, Stretch::Lights | Stretch::Everything) {
        for mut sun in world.query::<&mut DirectionalLight>().iter_mut(world) {
            sun.direction = Quat::from_rotation_y(0.01) * sun.direction;
        }
        for (_, mut t) in world.query::<(&SpotLight, &mut Transform)>().iter_mut(world) {
            t.translation += Vec3::new(rng.signed(), 0.0, rng.signed()) * 0.05;
        }
        for (_, mut t) in world.query::<(&PointLight, &mut Transform)>().iter_mut(world) {
            t.translation += Vec3::new(rng.signed(), rng.signed(), rng.signed()) * 0.03;
        }
    }
    if matches!(stretch, Stretch::Character | Stretch::Everything) {
        w.clock += 1.0 / 60.0;
    }
    if matches!(stretch, Stretch::Camera | Stretch::Everything) {
        let mut q = world.query_filtered::<&mut Transform, bevy_ecs::query::With<Camera>>();
        let mut t = q.single_mut(world).unwrap();
        t.translation += Vec3::new(rng.signed() * 0.05, 0.0, rng.signed() * 0.05);
        t.rotation = Quat::from_rotation_y(rng.signed() * 0.01) * t.rotation;
    }
}

/// Plays the first `frames` of the script with every light sampled by `method` and returns each
/// frame with the shadow passes it took.
fn play(reuse: bool, method: ShadowMethod, frames: usize) -> Vec<(Image, ShadowStats, Stretch)> {
    play_counting(reuse, method, frames).into_iter().map(|(image, stats, stretch, _)| (image, stats, stretch)).collect()
}

/// [`play`], with how many casters came to rest or left it in each frame's update.
fn play_counting(reuse: bool, method: ShadowMethod, frames: usize) -> Vec<(Image, ShadowStats, Stretch, usize)> {
    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    let mut w = build(reuse, method);
    let mut rng = Rng(0xc0ffee);
    let stretches = script(&mut rng);
    let mut motion = Rng(0xbeef);
    stretches
        .into_iter()
        .take(frames)
        .enumerate()
        .map(|(frame, stretch)| {
            apply(&mut w, frame, stretch, &mut motion);
            let clock = w.clock;
            w.app.set_time(clock);
            let image = render_headless(&gpu, &mut renderer, &mut w.app, SIZE, SIZE).expect("no wgpu error");
            let settled = w.app.world.resource::<CasterChanges>().settled.len();
            (image, w.app.world.resource::<ShadowStats>().clone(), stretch, settled)
        })
        .collect()
}

#[test]
fn drawing_only_dirty_shadow_maps_gives_the_same_frames_and_skips_every_layer_when_still() {
    let every = play(false, ShadowMethod::default(), FRAMES);
    let counted = play_counting(true, ShadowMethod::default(), FRAMES);
    let settling = counted.iter().filter(|c| c.3 > 0).count();
    let cached: Vec<_> = counted.into_iter().map(|(image, stats, stretch, _)| (image, stats, stretch)).collect();
    let (mut drawn, mut still_frames) = (0, 0);
    for (i, ((a, full, stretch), (b, stats, _))) in every.iter().zip(&cached).enumerate() {
        // 3 cascades, 2 spots and a point light's 6 faces, and 6 more while the visitor is there.
        let layers = 3 + 2 + 6 + if (LAMP_COMES..LAMP_GOES).contains(&i) { 6 } else { 0 };
        assert!(a == b, "frame {i} ({stretch:?}) differs between redrawing everything and the cache");
        assert_eq!(full.drawn(), layers, "frame {i}: without the cache every layer is drawn");
        assert_eq!(stats.drawn() + stats.kept(), layers, "frame {i}: every layer is drawn or kept");
        if *stretch == Stretch::Still && i > 0 && i != LAMP_COMES && i != LAMP_GOES {
            still_frames += 1;
            assert_eq!(stats.kept(), layers, "frame {i}: nothing moved, so every layer is kept");
        }
        drawn += stats.drawn();
    }
    assert!(still_frames >= 30, "the script has only {still_frames} still frames");
    let walking = cached.iter().filter(|(_, _, s)| *s == Stretch::Character).count();
    assert!(walking >= 10, "the script walks the character for only {walking} frames");
    let all: u32 = every.iter().map(|(_, full, _)| full.drawn()).sum();
    assert!(drawn > 0 && drawn < all * 3 / 4, "the cache drew {drawn} of {all} layers");
    // The visitor arrives with nothing drawn: every one of its faces is drawn.
    let (_, came, _) = &cached[LAMP_COMES];
    let visitor = came.lights.iter().find(|l| l.light.to_string() == "point 2").expect("the visitor");
    assert_eq!((visitor.drawn, visitor.kept), (6, 0), "new, so every face is drawn");
    // The frames are not all alike: something really moved.
    assert!(every.windows(2).filter(|w| w[0].0 != w[1].0).count() > FRAMES / 3);
    // Casters came to rest and left it again, and dirty layers were drawn over static maps where
    // the device can copy depth (GL cannot: there every dirty layer is drawn whole).
    assert!(settling >= 4, "casters came to rest or left it in only {settling} frames");
    let over_static: u32 = cached.iter().map(|(_, s, _)| s.from_static()).sum();
    let copies =
        gpu().adapter.get_downlevel_capabilities().flags.contains(DownlevelFlags::DEPTH_TEXTURE_AND_BUFFER_COPIES);
    if copies {
        assert!(over_static > drawn / 4, "{over_static} of {drawn} drawn layers came from static maps");
    } else {
        assert_eq!(over_static, 0);
    }
}

#[test]
fn a_kept_moment_map_is_not_blurred_again_and_looks_the_same() {
    // The first stretches: still frames, then motion of one kind or another.
    let frames = 120;
    let every = play(false, ShadowMethod::Evsm, frames);
    let cached = play(true, ShadowMethod::Evsm, frames);
    let mut still = 0;
    for (i, ((a, full, stretch), (b, stats, _))) in every.iter().zip(&cached).enumerate() {
        assert!(a == b, "frame {i} ({stretch:?}) differs between redrawing everything and the cache");
        // Every light uses moments: each layer drawn is blurred, and only those.
        assert_eq!(full.blurred(), full.drawn(), "frame {i}: without the cache every layer is blurred");
        assert_eq!(stats.blurred(), stats.drawn(), "frame {i}: the cache blurs what it draws");
        if *stretch == Stretch::Still && i > 0 {
            still += 1;
            assert_eq!(stats.blurred(), 0, "frame {i}: nothing moved, so nothing is blurred");
        }
    }
    assert!(still >= 9, "only {still} still frames");
    assert!(cached.iter().any(|(_, s, _)| s.blurred() > 0 && s.kept() > 0), "no frame both blurs and keeps");
}

#[test]
fn a_new_moment_method_or_blur_redraws_the_maps_it_changes() {
    let gpu = gpu();
    let frame = |w: &mut World, renderer: &mut Renderer| {
        w.app.set_time(0.0);
        render_headless(&gpu, renderer, &mut w.app, SIZE, SIZE).expect("no wgpu error")
    };
    // What each setting looks like drawn from nothing.
    let fresh = |method, blur| {
        let mut w = build(true, method);
        w.app.world.resource_mut::<umbra::settings::MapSettings>().moment_blur = blur;
        frame(&mut w, &mut Renderer::new(&gpu, HEADLESS_FORMAT).unwrap())
    };
    let mut w = build(true, ShadowMethod::Vsm);
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    frame(&mut w, &mut renderer);
    // Nothing moves between the frames: no layer is dirty, yet what the maps hold changed.
    for (method, blur) in [(ShadowMethod::Msm, 2), (ShadowMethod::Msm, 5), (ShadowMethod::Evsm, 5)] {
        let settings = w.app.settings().with(|s| (s.shadow.method, s.maps.moment_blur) = (method, blur));
        w.app.set_settings(&settings).unwrap();
        let image = frame(&mut w, &mut renderer);
        assert!(image == fresh(method, blur), "{method:?} with blur {blur} differs from a fresh start");
        let stats = w.app.world.resource::<ShadowStats>();
        assert_eq!(stats.kept(), 0, "{method:?} with blur {blur}: every layer holds old moments ({stats})");
    }
}
