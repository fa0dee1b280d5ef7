//! CPU costs of a frame at scale, with criterion (`cargo bench --bench cpu`): the update
//! schedule on the stress scene (10,000 animated cubes, the character and the lights), the
//! per-layer culling of its casters (the hierarchy against testing every box), reading the world
//! into a frame's draws, and loading the character's glTF file.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use umbra::shadow::{CasterIndex, intersects_clip_volume};
use umbra::{App, Settings};

/// The stress scene: ten thousand cubes beside the sample's lights and character.
const STRESS_CUBES: u32 = 10_000;

fn stress_app() -> App {
    let mut app = App::new(Settings::default().with(|s| s.scene.cubes = STRESS_CUBES)).expect("the stress scene");
    app.set_time(1.0);
    app
}

/// One fixed step of the update schedule: animation, camera, posing, bounds, caster tracking and
/// every light's layers with their dirty flags.
fn update(c: &mut Criterion) {
    let mut app = stress_app();
    c.bench_function("update schedule, 10,000 animated cubes", |b| b.iter(|| app.step()));
}

/// Every layer's casters, from the hierarchy and by testing every box, on the stress scene.
fn culling(c: &mut Criterion) {
    let mut app = stress_app();
    let data = umbra::render::extract(&app.world);
    let bounds: Vec<_> = app.world.query::<&umbra::components::WorldBounds>().iter(&app.world).map(|b| b.0).collect();
    let volumes: Vec<_> = data.draws.iter().map(|d| d.clip_from_world).collect();
    let mut group = c.benchmark_group(format!("culling {} layers", volumes.len()));
    group.bench_function(BenchmarkId::new("hierarchy, build and walk", bounds.len()), |b| {
        b.iter(|| {
            let index = CasterIndex::new(black_box(&bounds));
            volumes.iter().map(|v| index.inside(v).len()).sum::<usize>()
        })
    });
    group.bench_function(BenchmarkId::new("hierarchy, build", bounds.len()), |b| {
        b.iter(|| CasterIndex::new(black_box(&bounds)).len())
    });
    let mut kept = Some(CasterIndex::new(&bounds));
    group.bench_function(BenchmarkId::new("hierarchy, refit", bounds.len()), |b| {
        b.iter(|| kept = kept.take().map(|k| k.refitted(black_box(&bounds))))
    });
    let index = CasterIndex::new(&bounds);
    group.bench_function(BenchmarkId::new("hierarchy, walk", bounds.len()), |b| {
        b.iter(|| volumes.iter().map(|v| index.inside(v).len()).sum::<usize>())
    });
    group.bench_function(BenchmarkId::new("every box", bounds.len()), |b| {
        b.iter(|| {
            let test = |v| bounds.iter().filter(|bb| intersects_clip_volume(v, bb)).count();
            volumes.iter().map(test).sum::<usize>()
        })
    });
    group.finish();
    // The renderer refits last frame's hierarchy; `extract` alone builds it afresh each time.
    let name = "extract a frame (hierarchy built afresh), 10,000 cubes";
    c.bench_function(name, |b| b.iter(|| umbra::render::extract(&app.world).draws.len()));
}

/// Parsing the character's glTF (binary) file into a model.
fn gltf(c: &mut Criterion) {
    c.bench_function("load character.glb", |b| {
        b.iter(|| umbra::assets::parse_model(black_box(umbra::scene::CHARACTER_GLB), None, "character.glb").unwrap())
    });
}

criterion_group!(benches, update, culling, gltf);
criterion_main!(benches);
