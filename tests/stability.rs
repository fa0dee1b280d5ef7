//! Where shadow maps fail, each case held under its threshold at the default settings and shown
//! crossing it when its defence is taken away (zero bias, back faces only, no texel snapping, a
//! small map, culling to the camera's view, one coarse cascade, bind-pose bounds). The scenes and
//! numbers are in `src/eval/cases`; the truth is ray traced on the CPU.

mod common;

use umbra::components::ShadowMethod;
use umbra::eval::cases::budget::{threshold_sides, tile_shrink_sweep};
use umbra::eval::cases::{Score, case, skinned_caster_bounded};
use umbra::eval::measure::{Measurer, TruthSettings};
use umbra::settings::{CasterCulling, Settings, ShadowFaces};
use umbra::shadow::FitMode;

const SIZE: (u32, u32) = (256, 256);

fn measurer(gpu: &umbra::render::Gpu) -> Measurer<'_> {
    // The cases compare against the hard truth only, so no soft rays are cast.
    Measurer::new(gpu, SIZE, TruthSettings { soft_rays: 0, ..TruthSettings::default() })
}

/// Runs case `name` with the defaults and with `broken`; the first must stay under the case's
/// threshold, the second go over it.
fn holds_and_breaks(name: &str, broken: Settings) -> (Score, Score) {
    let gpu = common::gpu();
    let case = case(name).unwrap();
    let good = (case.run)(&mut measurer(&gpu), &Settings::default()).unwrap();
    let bad = (case.run)(&mut measurer(&gpu), &broken).unwrap();
    assert!(good.of > 100, "{name}: too few samples to judge ({good:?})");
    assert!(
        good.value() <= case.threshold,
        "{name} at the defaults: {:.5} > {} ({good:?})",
        good.value(),
        case.threshold
    );
    assert!(bad.value() > case.threshold, "{name} broken: {:.5} <= {} ({bad:?})", bad.value(), case.threshold);
    eprintln!("{name}: {:.5} at the defaults, {:.5} broken", good.value(), bad.value());
    (good, bad)
}

fn no_bias() -> Settings {
    Settings::default().with(|s| {
        s.shadow.depth_bias = 0.0;
        s.shadow.slope_bias = 0.0;
        s.shadow.normal_bias = 0.0;
    })
}

#[test]
fn acne_stays_off_an_open_plane_and_comes_back_without_bias() {
    let (_, bad) = holds_and_breaks("acne", no_bias());
    assert!(bad.value() > 0.2, "without bias the plane shadows itself: {bad:?}");
}

#[test]
fn shadows_stay_at_a_cubes_foot_and_come_loose_with_back_faces_only() {
    holds_and_breaks("peter-panning", Settings::default().with(|s| s.maps.shadow_faces = ShadowFaces::Back));
}

#[test]
fn a_creeping_camera_flips_no_shadow_but_unsnapped_cascades_shimmer() {
    let (good, _) = holds_and_breaks("shimmer", Settings::default().with(|s| s.cascade.fit_mode = FitMode::Unsnapped));
    assert_eq!(good.hits, 0, "snapped cascades keep every texel on the same world grid");
}

#[test]
fn thin_poles_cast_shadows_until_the_map_is_too_coarse() {
    holds_and_breaks("thin-casters", Settings::default().with(|s| s.maps.shadow_map_size = 256));
}

#[test]
fn a_caster_behind_the_camera_shadows_the_view_unless_culled_to_the_camera() {
    let (_, bad) = holds_and_breaks(
        "off-screen-caster",
        Settings::default().with(|s| s.maps.caster_culling = CasterCulling::CameraView),
    );
    assert_eq!(bad.value(), 1.0, "culled to the camera, the whole shadow is gone");
}

#[test]
fn degenerate_suns_give_no_garbage() {
    let (good, bad) = holds_and_breaks("degenerate-lights", no_bias());
    assert_eq!((good.garbage, bad.garbage), (0, 0), "no NaN, no value out of range");
}

#[test]
fn far_shadows_hold_across_cascade_seams_but_not_with_one_coarse_cascade() {
    holds_and_breaks(
        "far-field",
        Settings::default().with(|s| {
            s.cascade.cascades = 1;
            s.maps.shadow_map_size = 512;
        }),
    );
}

#[test]
fn a_character_far_from_its_bind_pose_keeps_its_shadow_unless_bounded_by_the_bind_pose() {
    let gpu = common::gpu();
    let case = case("skinned-caster").unwrap();
    let good = skinned_caster_bounded(&mut measurer(&gpu), &Settings::default(), false).unwrap();
    let bad = skinned_caster_bounded(&mut measurer(&gpu), &Settings::default(), true).unwrap();
    assert!(good.of > 100 && good.value() <= case.threshold, "{good:?}");
    assert!(bad.value() > case.threshold, "{bad:?}");
}

#[test]
fn probes_make_the_same_shadow_tests_as_the_pixels_they_sit_on() {
    // The shimmer case reads shadows at fixed points through probes; at the points the measuring
    // view shows, the probes must give exactly what the pixels gave.
    let gpu = common::gpu();
    let mut renderer = umbra::render::Renderer::new(&gpu, umbra::render::HEADLESS_FORMAT).unwrap();
    let mut app = umbra::App::new(Settings::default()).unwrap();
    app.resize(SIZE.0, SIZE.1);
    app.set_time(6.0);
    let frame = umbra::render::render_debug_frame(&gpu, &mut renderer, &mut app, SIZE.0, SIZE.1).unwrap();
    let picked: Vec<usize> = (0..frame.position.len()).filter(|&i| frame.covered(i)).step_by(37).collect();
    let points: Vec<umbra::assets::Vertex> = picked
        .iter()
        .map(|&i| {
            umbra::assets::Vertex::new(frame.position[i].truncate().to_array(), frame.normal[i].truncate().to_array())
        })
        .collect();
    let probed = umbra::render::probe_visibility(&gpu, &mut renderer, &mut app, &points).unwrap();
    let shadowed = picked.iter().filter(|&&i| (0.0..0.5).contains(&frame.visibility[0][i])).count();
    assert!(picked.len() > 500 && shadowed > 20, "{} points, {shadowed} in the sun's shadow", picked.len());
    assert_eq!(probed.len(), frame.visibility.len(), "a column per light");
    for (light, (column, pixels)) in probed.iter().zip(&frame.visibility).enumerate() {
        for (k, &i) in picked.iter().enumerate() {
            assert!((column[k] - pixels[i]).abs() < 1e-5, "light {light}, pixel {i}: {} vs {}", column[k], pixels[i]);
        }
    }
}

#[test]
fn a_point_lights_shadow_holds_across_its_cube_seams_but_not_without_seam_handling() {
    holds_and_breaks("cube-seams", Settings::default().with(|s| s.maps.cube_seams = false));
}

#[test]
fn filters_stay_inside_their_atlas_tile_but_darken_its_rim_without_the_guard() {
    let (good, bad) = holds_and_breaks("atlas-seams", Settings::default().with(|s| s.maps.atlas_guard = false));
    assert_eq!(good.hits, 0, "nothing shades the open ground");
    assert!(bad.value() > 0.1, "past the tile's edge the filter reads an empty page: {bad:?}");
}

#[test]
fn a_170_degree_spot_is_shadowed_to_its_rim_but_not_through_one_map() {
    let one_map = Settings::default().with(|s| s.maps.spot_map_limit = 85f32.to_radians());
    holds_and_breaks("wide-spot", one_map);
}

#[test]
fn a_wide_filter_leaves_a_lit_slope_lit_but_darkens_it_without_the_receiver_plane() {
    holds_and_breaks("soft-acne", Settings::default().with(|s| s.shadow.receiver_plane = false));
}

#[test]
fn pcss_penumbrae_harden_towards_a_poles_foot_but_not_with_a_fixed_kernel() {
    holds_and_breaks("contact-hardening", Settings::default().with(|s| s.shadow.pcss_blocker_search = false));
}

#[test]
fn a_variance_map_keeps_light_from_leaking_between_stacked_casters_but_not_without_bleeding_reduction() {
    holds_and_breaks("light-bleeding", Settings::default().with(|s| s.shadow.light_bleeding = 0.0));
}

#[test]
fn evsm_and_msm_leak_less_light_than_vsm_between_stacked_casters_without_bleeding_reduction() {
    let gpu = common::gpu();
    let case = case("light-bleeding").unwrap();
    let leak = |method| {
        let settings = Settings::default().with(|s| {
            s.shadow.method = method;
            s.shadow.light_bleeding = 0.0;
        });
        let score = (case.run)(&mut measurer(&gpu), &settings).unwrap();
        eprintln!("{method:?}: {:.4} of the shadow across the edge leaks ({score:?})", score.value());
        score.value()
    };
    let [vsm, evsm, evsm2, msm, hausdorff] =
        [ShadowMethod::Vsm, ShadowMethod::Evsm, ShadowMethod::Evsm2, ShadowMethod::Msm, ShadowMethod::MsmHausdorff]
            .map(leak);
    // The case's own threshold is 1 %; here VSM leaks 5 to 9 % and the others none, but MSM's
    // plain powers of the depth need 32-bit floats: in half floats (GL) it leaks 38 %.
    assert!(vsm > case.threshold, "VSM leaks here without bleeding reduction: {vsm}");
    assert!(evsm < vsm / 4.0, "VSM {vsm}, EVSM {evsm}");
    // EVSM2 is EVSM's positive half: never tighter than both halves together.
    assert!(evsm <= evsm2, "EVSM {evsm}, EVSM2 {evsm2}");
    if gpu.full_float_moments() {
        assert!(msm < vsm / 4.0, "VSM {vsm}, MSM {msm}");
        // Hausdorff's bound knows the depths lie in 0..1: never looser than Hamburger's.
        assert!(hausdorff <= msm, "MSM Hamburger {msm}, Hausdorff {hausdorff}");
    }
}

#[test]
fn evsms_negative_warp_keeps_a_ledges_shadowed_end_dark_where_the_positive_warp_alone_lights_it() {
    let positive_only = Settings::default().with(|s| s.shadow.method = ShadowMethod::Evsm2);
    let (_, evsm2) = holds_and_breaks("ledge-bleeding", positive_only);
    let gpu = common::gpu();
    let case = case("ledge-bleeding").unwrap();
    let light = |method| {
        let score = (case.run)(&mut measurer(&gpu), &Settings::default().with(|s| s.shadow.method = method)).unwrap();
        eprintln!("{method:?}: mean false light {:.4} on the ledge's end ({score:?})", score.value());
        score.value()
    };
    let [pcf5, vsm, evsm, msm, hausdorff] =
        [ShadowMethod::Pcf5, ShadowMethod::Vsm, ShadowMethod::Evsm, ShadowMethod::Msm, ShadowMethod::MsmHausdorff]
            .map(light);
    let evsm2 = evsm2.value();
    // The ground's share of a 5x5 footprint leaks by any filter; Chebyshev on plain depths lets
    // in more than that share, the positive warp alone more still (here every pixel it reaches is
    // fully lit), both warps together less than the plain filter.
    assert!(evsm2 > vsm && vsm > pcf5, "EVSM2 {evsm2}, VSM {vsm}, PCF 5x5 {pcf5}");
    assert!(evsm < pcf5 && evsm2 > 4.0 * evsm, "EVSM {evsm}, EVSM2 {evsm2}, PCF 5x5 {pcf5}");
    assert!(evsm <= case.threshold && msm <= case.threshold, "EVSM {evsm}, MSM {msm}");
    // Hausdorff's bound knows the depths lie in 0..1: never looser than Hamburger's (up to the
    // rounding of a pixel or two).
    assert!(hausdorff <= msm + 1e-3, "MSM Hamburger {msm}, Hausdorff {hausdorff}");
}

#[test]
fn a_spots_error_grows_as_its_tile_shrinks_and_passes_the_threshold_near_the_predicted_side() {
    // With every tile held at 32², the spot's edges land half a 17 cm texel off.
    holds_and_breaks("tile-shrink", Settings::default().with(|s| s.maps.shadow_map_size = 32));
    let gpu = common::gpu();
    let sides = [32, 64, 128, 256, 512, 1024];
    let points = tile_shrink_sweep(&mut measurer(&gpu), &Settings::default(), &sides).unwrap();
    for p in &points {
        eprintln!("{:>5}²: predicted {:.3} %, measured {:.3} %", p.side, p.predicted * 100.0, p.measured * 100.0);
    }
    let threshold = case("tile-shrink").unwrap().threshold;
    // Where the error is well above a pixel's grain, halving the tile about doubles it, as the
    // edge model says, and the model is within a factor of two of what is measured.
    for w in points.windows(2).filter(|w| w[1].predicted >= threshold / 2.0) {
        assert!(w[0].measured > 1.3 * w[1].measured, "{w:?}");
    }
    for p in points.iter().filter(|p| p.predicted >= threshold / 2.0) {
        assert!((0.5..=2.0).contains(&(p.measured / p.predicted)), "{p:?}");
    }
    let (measured, predicted) = threshold_sides(&points, threshold);
    let (measured, predicted) = (f64::from(measured.unwrap()), predicted.unwrap());
    eprintln!("passes the threshold at {measured}² measured, {predicted:.0}² predicted");
    assert!(measured / 2.0 <= predicted && predicted <= measured, "{measured} against {predicted}");
}

#[test]
fn a_tile_keeps_its_size_as_the_camera_creeps_across_a_class_edge_and_flickers_without_hysteresis() {
    holds_and_breaks("tile-resize", Settings::default().with(|s| s.maps.tile_hysteresis = 0.0));
}

#[test]
fn a_starved_budget_redraws_every_spot_within_its_turn_and_bounds_how_wrong_it_gets_meanwhile() {
    let (good, bad) = holds_and_breaks("starved-budget", Settings::default().with(|s| s.maps.max_stale = 1000));
    assert!(bad.garbage > 0, "without the overdue rule the spots that show least never get their turn: {bad:?}");
    // And meanwhile their shadows stay where their posts were, further off every frame.
    let share = |s: Score| s.hits as f64 / s.of.max(1) as f64;
    eprintln!("misclassified {:.2} % with the rule, {:.2} % without", share(good) * 100.0, share(bad) * 100.0);
    assert!(share(bad) > 1.5 * share(good), "{good:?} against {bad:?}");
}

#[test]
fn contact_shadows_leave_no_halo_behind_a_thin_bar_unless_surfaces_are_taken_thick() {
    // Taken 10 m thick, the bar 8 m in front of the ground hides the ground's march.
    holds_and_breaks("contact-halos", Settings::default().with(|s| s.shadow.contact_thickness = 10.0));
}

#[test]
fn contact_shadows_miss_a_caster_past_the_screens_edge_and_never_darken_what_they_cannot_see() {
    let gpu = common::gpu();
    let [whole, cut] = umbra::eval::cases::contact_edge(&mut measurer(&gpu), &Settings::default()).unwrap();
    eprintln!("contact-edge: {whole:?} lit seen whole, {cut:?} cut by the screen's edge");
    assert!(whole.of > 100 && cut.of > 100, "too few samples: {whole:?} {cut:?}");
    // With the wall in view the march closes the gap the bias opens (a march too short to reach
    // the wall leaves it open: the closing is the march's doing).
    assert!(whole.value() < 0.05, "seen whole, contact shadows should close the gap: {whole:?}");
    let short = Settings::default().with(|s| s.shadow.contact_length = 0.01);
    let [open, _] = umbra::eval::cases::contact_edge(&mut measurer(&gpu), &short).unwrap();
    assert!(open.value() > 0.5, "the bias should open a gap: {open:?}");
    // With the wall past the screen's edge the march leaves the screen first: a step off screen is
    // taken as lit, so the gap stays open (were it taken as blocked, every screen edge would
    // draw a false shadow).
    assert!(cut.value() > 0.5, "cut by the edge, the march cannot see the cube: {cut:?}");
}

#[test]
fn contact_shadows_close_the_gap_a_large_bias_opens_at_a_cubes_foot() {
    // A slope bias of 30 texels pushes the ground's lookups past the cube's side. (A normal bias
    // opens no gap here: it lifts a ground point straight up, still under the cube's shadow.)
    let gpu = common::gpu();
    let case = case("peter-panning").unwrap();
    let biased = Settings::default().with(|s| s.shadow.slope_bias = 30.0);
    let gap = (case.run)(&mut measurer(&gpu), &biased).unwrap();
    let closed = (case.run)(&mut measurer(&gpu), &biased.with(|s| s.shadow.contact_shadows = true)).unwrap();
    eprintln!("peter-panning at slope bias 30: {:.4} without contact shadows, {:.4} with", gap.value(), closed.value());
    assert!(gap.value() > case.threshold, "the bias should open a gap: {gap:?}");
    assert!(closed.value() <= case.threshold, "contact shadows should close it: {closed:?}");
}
