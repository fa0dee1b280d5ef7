//! Depth formats against their precision: walls square to a spot at 1 m to 32 m, lit, so any
//! shadow on them is the map's rounding outgrowing the bias (`src/eval/cases/precision.rs`); and
//! the multiplicative offset of seed 001 on its own against the open plane's acne.

mod common;

use umbra::components::ShadowMethod;
use umbra::eval::cases::precision::{WALL_DISTANCES, d16_acne_distance, precision_by_distance};
use umbra::eval::cases::{Score, case};
use umbra::eval::measure::{Measurer, TruthSettings};
use umbra::settings::{Settings, ShadowDepth};

const SIZE: (u32, u32) = (320, 180);

/// Each wall's share of false shadow under `settings`, nearest first.
fn walls(settings: Settings) -> Vec<Score> {
    let gpu = common::gpu();
    let mut m = Measurer::new(&gpu, SIZE, TruthSettings { soft_rays: 0, ..TruthSettings::default() });
    let scores = precision_by_distance(&mut m, &settings).unwrap();
    let shown: Vec<String> = scores.iter().map(|s| format!("{:.4} of {}", s.value(), s.of)).collect();
    eprintln!(
        "{:?} {:?} {}: {shown:?}",
        settings.maps.shadow_depth, settings.shadow.method, settings.maps.shadow_map_size
    );
    for s in &scores {
        assert!(s.of > 100, "too few pixels on a wall to judge: {scores:?}");
    }
    scores
}

fn threshold() -> f64 {
    case("precision").unwrap().threshold
}

#[test]
fn a_32_bit_depth_holds_every_wall_and_16_bits_fail_past_the_predicted_distance() {
    let good = walls(Settings::default());
    assert!(good.iter().all(|s| s.value() <= threshold()), "32-bit float depth: {good:?}");
    let d16 = walls(Settings::default().with(|s| s.maps.shadow_depth = ShadowDepth::Unorm16));
    let predicted = d16_acne_distance(2048);
    for (d, s) in WALL_DISTANCES.iter().zip(&d16) {
        if *d < predicted {
            assert!(s.value() <= threshold(), "16-bit depth at {d} m, before {predicted:.1} m: {s:?}");
        } else {
            assert!(s.value() > threshold(), "16-bit depth at {d} m, past {predicted:.1} m: {s:?}");
        }
    }
}

#[test]
fn depth_in_colour_holds_in_32_bits_and_a_half_float_fails_everywhere_once_texels_are_finer_than_it() {
    // R32F needs 32-bit float colour targets, which GL lacks (render tests say so).
    if common::gpu().full_float_moments() {
        let r32 = walls(Settings::default().with(|s| s.shadow.method = ShadowMethod::DepthR32f));
        assert!(r32.iter().all(|s| s.value() <= threshold()), "R32F: {r32:?}");
    }
    // A half float rounds to 2^-11 of the distance at worst, and so does not outgrow the bias
    // (one texel, 5.3·10⁻⁴ of the distance at 2048²) at any distance...
    let r16 = walls(Settings::default().with(|s| s.shadow.method = ShadowMethod::RadialR16f));
    assert!(r16.iter().all(|s| s.value() <= threshold()), "R16F radial at 2048: {r16:?}");
    // ...but at 4096² a texel is 2.7·10⁻⁴ of the distance, and every wall (each just past a
    // power of two, where the rounding is widest) shadows itself.
    let fine = walls(Settings::default().with(|s| {
        s.shadow.method = ShadowMethod::RadialR16f;
        s.maps.shadow_map_size = 4096;
    }));
    assert!(fine.iter().all(|s| s.value() > threshold()), "R16F radial at 4096: {fine:?}");
}

#[test]
fn the_multiplicative_offset_alone_keeps_an_open_plane_free_of_acne() {
    let gpu = common::gpu();
    let acne = case("acne").unwrap();
    let no_bias = Settings::default().with(|s| {
        s.shadow.depth_bias = 0.0;
        s.shadow.slope_bias = 0.0;
        s.shadow.normal_bias = 0.0;
    });
    let measurer = || Measurer::new(&gpu, (256, 256), TruthSettings { soft_rays: 0, ..TruthSettings::default() });
    let without = (acne.run)(&mut measurer(), &no_bias).unwrap();
    let with = (acne.run)(&mut measurer(), &no_bias.with(|s| s.shadow.bias_scale = 0.05)).unwrap();
    eprintln!("acne without bias {:.4}, with a multiplicative offset of 0.05 {:.5}", without.value(), with.value());
    assert!(without.value() > 0.2, "{without:?}");
    assert!(with.value() <= acne.threshold, "{with:?}");
}
