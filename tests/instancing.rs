//! Instanced drawing is invisible: the sample scene with a field of cubes, rendered with every
//! depth-only layer's rigid casters drawn one call per mesh and with one call per caster, gives
//! bit-identical frames, in far fewer calls.

mod common;

use common::{SIZE, gpu};
use umbra::components::ShadowMethod;
use umbra::render::{HEADLESS_FORMAT, Image, Renderer, ShadowStats, render_headless};
use umbra::scene::RING_CUBES;
use umbra::settings::ShadowFaces;
use umbra::{App, Settings};

/// Frames of the scene at a few times, with the shadow passes each took.
fn frames(settings: Settings) -> Vec<(Image, ShadowStats)> {
    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    let mut app = App::new(settings).unwrap();
    app.resize(SIZE, SIZE);
    [0.0, 0.4, 1.7]
        .into_iter()
        .map(|t| {
            app.set_time(t);
            let image = render_headless(&gpu, &mut renderer, &mut app, SIZE, SIZE).expect("no wgpu error");
            (image, app.world.resource::<ShadowStats>().clone())
        })
        .collect()
}

/// Draw calls one by one and instanced, after checking the frames are the same.
fn compare(base: Settings) -> (u32, u32) {
    let field = base.with(|s| s.scene.cubes = RING_CUBES + 600);
    let one_by_one = frames(field.clone().with(|s| s.maps.instancing = false));
    let instanced = frames(field.with(|s| s.maps.instancing = true));
    for (i, ((a, sa), (b, sb))) in one_by_one.iter().zip(&instanced).enumerate() {
        assert!(a.pixels == b.pixels, "frame {i}: instanced drawing changed the picture");
        assert_eq!((sa.drawn(), sa.kept()), (sb.drawn(), sb.kept()), "frame {i}: the same layers drawn");
    }
    let calls = |f: &[(Image, ShadowStats)]| f.iter().map(|(_, s)| s.calls()).sum::<u32>();
    (calls(&one_by_one), calls(&instanced))
}

#[test]
fn instanced_and_one_by_one_drawing_give_the_same_frames() {
    let base = Settings::default();
    let (a, b) = compare(base.clone());
    assert!(b > 0 && a > 10 * b, "instancing takes far fewer calls: {b} against {a}");
    // Culling the faces towards the light is part of each batch's pipeline.
    let (a, b) = compare(base.with(|s| s.maps.shadow_faces = ShadowFaces::Back));
    assert!(b > 0 && a > 10 * b, "{b} against {a}");
}

#[test]
fn layers_drawn_as_colour_targets_draw_one_by_one_and_moments_from_depth_are_batched() {
    let vsm = Settings::default().with(|s| s.shadow.method = ShadowMethod::Vsm);
    let (a, b) = compare(vsm.clone().with(|s| s.maps.moments_from = umbra::settings::MomentSource::Colour));
    assert_eq!(a, b, "no layer drawn as a colour target is batched");
    // Resolved from depth (the default), a moment layer is drawn depth-only, instanced like any.
    let (a, b) = compare(vsm);
    assert!(b > 0 && a > 10 * b, "moment layers drawn depth-only take far fewer calls: {b} against {a}");
}

#[test]
fn the_shadow_pass_bench_draws_the_same_casters_in_as_many_calls_at_any_size() {
    let gpu = gpu();
    let settings = Settings::default().with(|s| s.maps.shadow_map_size = 128);
    let sizes = [10, RING_CUBES + 400];
    let rows = umbra::eval::passes::run(&gpu, &settings, &sizes, 1, |_| {}).expect("the bench runs");
    assert_eq!(rows.len(), 2);
    let (small, big) = (&rows[0], &rows[1]);
    assert_eq!((small.cubes, big.cubes), (sizes[0], sizes[1]));
    assert!(
        big.inside > small.inside + 400,
        "the field's cubes are inside the cascades: {} {}",
        small.inside,
        big.inside
    );
    assert_eq!(small.calls, big.calls, "instanced: the calls do not grow with the casters");
    for r in &rows {
        assert!(r.umbra_ms > 0.0 && r.bare_ms > 0.0 && r.ratio().is_finite(), "{r:?}");
        assert_eq!(r.layers, 12, "four cascades, two spots, the lantern's six faces");
    }
    let dir = common::scratch("shadow-pass");
    umbra::eval::passes::chart(&dir.join("scale"), "test", &rows).expect("the chart is written");
    assert!(std::fs::metadata(dir.join("scale.png")).is_ok_and(|m| m.len() > 1000));
}
