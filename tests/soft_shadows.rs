//! The filters, PCSS and the moment maps against the ray-traced truth: every method's shadow
//! where the truth puts it, and PCSS's penumbra as wide as a 10 cm light makes it: narrow where a caster is close to the
//! ground, wide where it is high (contact hardening).

mod common;

use bevy_ecs::prelude::{Entity, With};
use common::*;
use glam::Vec3;
use umbra::assets::{MeshLibrary, cube, plane};
use umbra::components::*;
use umbra::eval::{metrics, truth};
use umbra::render::{HEADLESS_FORMAT, Renderer, render_debug_frame};
use umbra::{App, Settings};

fn grey() -> Material {
    Material { specular: 0.0, shininess: 1.0, ..Material::color(0.6, 0.6, 0.6) }
}

/// Height of the low plate (over x < 0) and of the high one (over x > 0).
const LOW: f32 = 0.25;
const HIGH: f32 = 2.0;

/// A spot light (10 cm across) 4 m over the ground shining down on two thin plates, one low and
/// one high, seen from straight above. The penumbra of a plate's edge is 2 R h / (4 - h) wide:
/// 1.3 cm for the low one, 20 cm for the high one.
fn plates(method: ShadowMethod) -> App {
    plates_with(Settings::default().with(|s| s.shadow.method = method))
}

fn plates_with(settings: Settings) -> App {
    let mut app = App::empty(settings).unwrap();
    let (ground, block) = {
        let mut meshes = app.world.resource_mut::<MeshLibrary>();
        (meshes.add(plane(40.0)), meshes.add(cube(Vec3::splat(0.5))))
    };
    app.world.spawn((ground, Transform::default(), grey(), ShadowReceiver));
    for (x, h) in [(-1.2, LOW), (1.2, HIGH)] {
        let t = Transform::from_xyz(x, h, 0.0).with_scale(Vec3::new(1.0, 0.02, 1.6));
        app.world.spawn((block, t, grey(), ShadowCaster));
    }
    let spot = SpotLight { range: 12.0, intensity: 4.0, inner_angle: 0.7, outer_angle: 0.8, ..Default::default() };
    let at = Transform::from_translation(Vec3::new(0.0, 4.0, 0.0)).looking_to(Vec3::NEG_Y);
    app.world.spawn((spot, at, ShadowMap::default()));
    app.world.spawn(camera_at(Vec3::new(0.0, 5.0, 0.01), Vec3::ZERO));
    app.resize(SIZE, SIZE);
    app
}

/// What one method gives on the plates' ground against the truth (32 rays over the light).
struct Seen {
    tally: metrics::Tally,
    /// Ground pixels partly lit (0.05..0.95) under the low plate's side and the high one's, as
    /// rendered and as the soft truth has them.
    partial_low: usize,
    partial_high: usize,
    truth_low: usize,
    truth_high: usize,
    /// Pixels the light reaches whose visibility is not a number in 0..=1.
    out_of_range: usize,
}

fn measure(method: ShadowMethod) -> Seen {
    measure_app(plates(method), method.name())
}

fn measure_app(mut app: App, name: &str) -> Seen {
    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    app.set_time(0.0);
    let frame = render_debug_frame(&gpu, &mut renderer, &mut app, SIZE, SIZE).unwrap();
    drop((renderer, gpu));
    let truth = truth::truth_of(&mut app.world, &frame, truth::SizeOverride::default(), 32);
    let on_ground = |i: usize| frame.covered(i) && frame.position[i].y.abs() < 1e-3;
    let tally = metrics::tally(&frame, &truth[0], 0, on_ground);
    let partial = |v: f32| (0.05..0.95).contains(&v);
    let count = |high: bool, of: &dyn Fn(usize) -> Option<f32>| {
        (0..truth[0].len())
            .filter(|&i| on_ground(i) && (frame.position[i].x > 0.0) == high && of(i).is_some_and(partial))
            .count()
    };
    let rendered = |i: usize| metrics::rendered(&frame, 0, i);
    let soft = |i: usize| truth[0][i].map(|t| t.soft);
    let seen = Seen {
        tally,
        partial_low: count(false, &rendered),
        partial_high: count(true, &rendered),
        truth_low: count(false, &soft),
        truth_high: count(true, &soft),
        out_of_range: (0..truth[0].len()).filter(|&i| metrics::out_of_range(&frame, 0, i)).count(),
    };
    eprintln!(
        "{}: misclassified {:.4} %, MAE soft {:.4}; partly lit pixels low/high {}/{} (truth {}/{})",
        name,
        100.0 * seen.tally.misclassified(),
        seen.tally.mae_soft(),
        seen.partial_low,
        seen.partial_high,
        seen.truth_low,
        seen.truth_high
    );
    seen
}

#[test]
fn every_method_puts_the_plates_shadows_where_the_truth_does() {
    let mut bilinear_mae = None;
    let full_floats = gpu().full_float_moments();
    for &method in ShadowMethod::ALL {
        if method.colour_depth_bits() > 16 && !full_floats {
            continue; // R32F needs 32-bit float colour targets (GL has none)
        }
        let seen = measure(method);
        if method == ShadowMethod::Bilinear {
            bilinear_mae = Some(seen.tally.mae_soft());
        }
        assert!(seen.tally.pixels > 30_000, "{method:?}: {} ground pixels", seen.tally.pixels);
        // A visibility is a share of light: never above 1 (the failure cases count such a pixel
        // as garbage, a whole case lost), however the filter's weights round.
        assert_eq!(seen.out_of_range, 0, "{method:?}: visibility outside 0..=1");
        // Edges are the only place a method can be wrong here: a few hundred pixels of 65,000.
        assert!(seen.tally.misclassified() < 0.01, "{method:?}: {:.4} misclassified", seen.tally.misclassified());
        // And each draws the edge it should: a comparison per texel none partly lit, a filter that
        // spreads its taps a soft band along the high plate's edge (bilinear's band is under a pixel).
        let partial = seen.partial_low + seen.partial_high;
        match method {
            ShadowMethod::Nearest => assert_eq!(partial, 0, "nearest draws partly lit pixels"),
            m if m.spreads() || m.moments() => {
                assert!(seen.partial_high > 50, "{m:?}: {} partly lit pixels", seen.partial_high)
            }
            _ => {}
        }
        // A blurred moment map is a filter too: nearer the soft truth than the hard comparison,
        // in the precision the method asks for. (Where only half floats can be drawn, GL, MSM's
        // four plain powers of the depth lose too much: 0.0092 against bilinear's 0.0058 here.)
        if method.moments() && (full_floats || method.moment_bits() == 16) {
            let hard = bilinear_mae.expect("bilinear comes first");
            assert!(
                seen.tally.mae_soft() < hard,
                "{method:?}: {:.4} against bilinear {hard:.4}",
                seen.tally.mae_soft()
            );
        }
    }
}

#[test]
fn pcss_penumbrae_grow_with_the_casters_height_as_the_truths_do() {
    let bilinear = measure(ShadowMethod::Bilinear);
    let pcss = measure(ShadowMethod::Pcss);
    // The truth itself: the high plate's penumbra is many times the low one's.
    assert!(bilinear.truth_high > 4 * bilinear.truth_low.max(1), "the scene lost its point");
    // A fixed filter draws both edges alike; PCSS widens the high one's as the light does.
    assert!(pcss.partial_high > 4 * pcss.partial_low.max(1), "PCSS: {} / {}", pcss.partial_high, pcss.partial_low);
    let (got, want) = (pcss.partial_high as f64, pcss.truth_high as f64);
    assert!((got / want - 1.0).abs() < 0.5, "PCSS's wide penumbra has {got} pixels, the truth's {want}");
    assert!(bilinear.partial_high < bilinear.truth_high / 2, "bilinear draws a soft edge after all");
    // And so it is at most half as wrong against the soft truth.
    assert!(
        pcss.tally.mae_soft() <= 0.5 * bilinear.tally.mae_soft(),
        "PCSS {:.4} against bilinear {:.4}",
        pcss.tally.mae_soft(),
        bilinear.tally.mae_soft()
    );
}

#[test]
fn the_receiver_plane_is_each_lights_own() {
    // PCF 5x5 on an open plane under a sun 20° up: with the receiver plane off in the settings
    // the lit plane darkens itself (soft acne); the sun's own bias turning it back on gives
    // exactly what the default gives.
    use umbra::eval::cases::scenes::{ground, sun_direction};
    let plane = |settings: &Settings| {
        let view = (Vec3::new(0.0, 5.0, 10.0), Vec3::new(0.0, 0.0, -2.0));
        let mut app = ground(settings, 80.0, true, sun_direction(20.0, 30.0), view).unwrap();
        app.resize(SIZE, SIZE);
        app
    };
    let pcf5 = Settings::default().with(|s| s.shadow.method = ShadowMethod::Pcf5);
    let flat_settings = pcf5.clone().with(|s| s.shadow.receiver_plane = false);
    let with = measure_app(plane(&pcf5), "pcf5");
    let flat = measure_app(plane(&flat_settings), "pcf5 flat");
    let mut own = plane(&flat_settings);
    let sun = own.world.query_filtered::<Entity, With<DirectionalLight>>().single(&own.world).unwrap();
    own.world.entity_mut(sun).insert(ShadowBias { receiver_plane: true, ..ShadowBias::default() });
    let own = measure_app(own, "pcf5 flat, the sun's own plane");
    assert!(flat.tally.mae_soft() > 2.0 * with.tally.mae_soft(), "the plane makes no difference here");
    assert_eq!(own.tally.mae_soft(), with.tally.mae_soft(), "the light's own plane is not used");
}

#[test]
fn moment_maps_resolved_from_depth_at_every_size_put_the_shadows_where_drawn_ones_do() {
    use umbra::settings::MomentSource;
    let vsm = |moments_from: MomentSource| {
        let app = plates_with(Settings::default().with(|s| {
            s.shadow.method = ShadowMethod::Vsm;
            s.maps.moments_from = moments_from;
        }));
        measure_app(app, moments_from.name())
    };
    let drawn = vsm(MomentSource::Colour);
    for &source in MomentSource::ALL.iter().filter(|s| s.from_depth()) {
        let seen = vsm(source);
        assert!(seen.tally.misclassified() < 0.01, "{source:?}: {:.4} misclassified", seen.tally.misclassified());
        // The blur runs over moment texels: a smaller map draws a wider soft band.
        assert!(seen.partial_high >= drawn.partial_high * 9 / 10, "{source:?}: {} partly lit", seen.partial_high);
        if source == MomentSource::Depth {
            // The same moments of the same depths, made in another pass: the same picture to a
            // few pixels of 65,000 (a shifted or a wrong resolve moves whole edges).
            let apart = seen.tally.mae_soft() - drawn.tally.mae_soft();
            assert!(
                apart.abs() < 2e-4,
                "resolved {:.5} against drawn {:.5}",
                seen.tally.mae_soft(),
                drawn.tally.mae_soft()
            );
            let wrong = |s: &Seen| s.tally.misclassified() * s.tally.pixels as f64;
            assert!((wrong(&seen) - wrong(&drawn)).abs() < 40.0, "misclassified pixels apart");
        }
    }
}

#[test]
fn moments_made_in_compute_are_those_of_the_full_screen_passes() {
    use umbra::settings::{MomentResolve, MomentSource};
    let with = |method: ShadowMethod, moments_from: MomentSource, compute: bool, blur: u32| {
        Settings::default().with(|s| {
            s.shadow.method = method;
            s.maps.moments_from = moments_from;
            s.maps.moment_resolve = if compute { MomentResolve::Compute } else { MomentResolve::Passes };
            s.maps.moment_blur = blur;
        })
    };
    let cases = [
        (ShadowMethod::Vsm, MomentSource::Depth),
        (ShadowMethod::Vsm, MomentSource::Half),
        (ShadowMethod::Vsm, MomentSource::Quarter),
        (ShadowMethod::Msm, MomentSource::Depth),
        // Half-float pairs: made in compute only where the adapter stores them.
        (ShadowMethod::Evsm2, MomentSource::Depth),
    ];
    let full_floats = gpu().full_float_moments();
    for (method, source) in cases {
        let name = format!("{} {}", method.name(), source.name());
        let passes = measure_app(plates_with(with(method, source, false, 2)), &format!("{name} passes"));
        let compute = measure_app(plates_with(with(method, source, true, 2)), &format!("{name} compute"));
        // The same means and weights: the same picture in full floats. In half floats the passes
        // round the resolved moments and the rows' blur to the map's format before the next step,
        // which the dispatch does not (it keeps them in shared memory): never worse there.
        let apart = compute.tally.mae_soft() - passes.tally.mae_soft();
        let close = if full_floats { apart.abs() < 2e-4 } else { apart < 2e-4 };
        assert!(close, "{name}: compute {:.5} against passes {apart:+.5}", compute.tally.mae_soft());
        let wrong = |s: &Seen| s.tally.misclassified() * s.tally.pixels as f64;
        assert!((wrong(&compute) - wrong(&passes)).abs() < 10.0, "{name}: misclassified pixels apart");
    }
    // The dispatch is what made them where the device computes (four channels always, VSM's two
    // 32-bit floats where it has full floats: WebGPU guarantees storing both); never past its
    // widest blur.
    let gpu = gpu();
    let computes = gpu.adapter.get_downlevel_capabilities().flags.contains(wgpu::DownlevelFlags::COMPUTE_SHADERS);
    let runs = [
        (ShadowMethod::Msm, true, 2, computes),
        (ShadowMethod::Vsm, true, 2, computes && full_floats),
        (ShadowMethod::Msm, false, 2, false),
        (ShadowMethod::Msm, true, 9, false),
    ];
    for (method, compute, blur, expected) in runs {
        if method == ShadowMethod::Vsm && !expected {
            continue; // half-float pairs: stored in compute only where the adapter allows it
        }
        let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
        let mut app = plates_with(with(method, MomentSource::Depth, compute, blur));
        app.set_time(0.0);
        app.hear(renderer.news());
        let texture = gpu.target("compute", (SIZE, SIZE), HEADLESS_FORMAT).unwrap();
        renderer.render(&gpu, &app.world, &texture.create_view(&Default::default()), SIZE, SIZE).unwrap();
        let made = renderer.news().stats.map_or(0, |s| s.moments_in_compute);
        assert_eq!(made > 0, expected, "{method:?}, compute {compute}, blur {blur}: {made} layers made in compute");
    }
}

#[test]
fn moments_resolved_from_multisampled_depth_put_the_shadows_where_the_truth_does() {
    use umbra::settings::{MomentResolve, MomentSource};
    let with = |method: ShadowMethod, moments_from: MomentSource, samples: u32, resolve: MomentResolve| {
        plates_with(Settings::default().with(|s| {
            s.shadow.method = method;
            s.maps.moments_from = moments_from;
            s.maps.moment_samples = samples;
            s.maps.moment_resolve = resolve;
            s.maps.moment_blur = 0;
        }))
    };
    let seen = |method: ShadowMethod, source: MomentSource, samples: u32, resolve: MomentResolve| {
        let name = format!("{} {} {samples}x {}", method.name(), source.name(), resolve.name());
        measure_app(with(method, source, samples, resolve), &name)
    };
    // The plates turned 30° about the vertical, so their edges cross the map's texels aslant.
    let turned = |source: MomentSource, samples: u32| {
        let mut app = with(ShadowMethod::Vsm, source, samples, MomentResolve::Passes);
        let mut plates = app.world.query_filtered::<&mut Transform, With<ShadowCaster>>();
        for mut t in plates.iter_mut(&mut app.world) {
            t.rotation = glam::Quat::from_rotation_y(0.5);
        }
        measure_app(app, &format!("turned vsm {} {samples}x", source.name()))
    };
    let wrong = |s: &Seen| s.tally.misclassified() * s.tally.pixels as f64;
    // A moment texel of one depth sample puts an aslant edge on the texels' stairs; of four
    // samples (4x MSAA, which every device but GL allows), nearer where the edge crosses it.
    let (one, four) = (turned(MomentSource::Depth, 1), turned(MomentSource::Depth, 4));
    let counts = {
        let gpu = gpu();
        umbra::render::sample_counts(&gpu.adapter, gpu.device.features())
    };
    if counts & 4 == 0 {
        // Not allowed: one sample a texel instead, the same picture.
        assert_eq!(wrong(&four), wrong(&one));
        eprintln!("SKIPPED the rest: this device resolves no moments from multisampled depth");
        return;
    }
    assert!(wrong(&four) * 2.0 < wrong(&one), "4x: {} pixels wrong, 1x: {}", wrong(&four), wrong(&one));
    // At half the side, four samples a texel either way: 2x2 depth texels or 4x MSAA.
    let (half, half4) = (turned(MomentSource::Half, 1), turned(MomentSource::Half, 4));
    assert!((wrong(&half) - wrong(&half4)).abs() < 10.0, "depth/2 1x {} against 4x {}", wrong(&half), wrong(&half4));
    let (vsm, half, passes) = (ShadowMethod::Vsm, MomentSource::Half, MomentResolve::Passes);
    let four = seen(vsm, half, 4, passes);
    let msm = seen(ShadowMethod::Msm, half, 4, passes);
    for s in [&four, &msm] {
        assert!(s.tally.misclassified() < 0.01, "{:.4} misclassified", s.tally.misclassified());
    }
    // The dispatch resolves the samples as the passes do.
    let compute = seen(vsm, half, 4, MomentResolve::Compute);
    let apart = compute.tally.mae_soft() - four.tally.mae_soft();
    assert!(apart.abs() < 2e-4, "compute {:.5} against passes {apart:+.5}", compute.tally.mae_soft());
}
