//! `umbra tune`: the biases it finds never make a light's shadows worse on the views it tunes
//! for, and the file it writes gives the lights those biases when read back.

mod common;

use umbra::App;
use umbra::biases::LightBiases;
use umbra::eval::tune::tune;
use umbra::settings::Settings;

#[test]
fn tuned_biases_are_no_worse_and_come_back_from_their_file() {
    let gpu = common::gpu();
    // Start from a deliberately poor bias so there is something to find.
    let poor = Settings::default().with(|s| {
        s.shadow.depth_bias = 0.0;
        s.shadow.slope_bias = 0.0;
        s.shadow.normal_bias = 0.0;
    });
    let (lights, biases) = tune(&gpu, &poor, (192, 108), |_, _| {}).unwrap();
    assert_eq!(
        lights.iter().map(|l| l.light.as_str()).collect::<Vec<_>>(),
        ["sun", "spot 1", "spot 2", "point 1"],
        "every light of any kind"
    );
    for l in &lights {
        let (before, after) = l.wrong();
        assert!(after <= before, "{}: {before} wrong pixels became {after}", l.light);
    }
    let sun = &lights[0];
    assert!(sun.wrong().0 > 10 * sun.wrong().1.max(1), "zero bias leaves acne that tuning removes: {:?}", sun.wrong());
    // The acne is everywhere, so the biases found remove it from the views the search never saw too.
    let (held_before, held_after) = sun.held_out.expect("the sample's four views: two held out");
    let wrong = |t: &umbra::eval::metrics::Tally| t.false_shadow + t.false_lit;
    assert!(
        wrong(&held_before) > 10 * wrong(&held_after).max(1),
        "held out: {} wrong pixels became {}",
        wrong(&held_before),
        wrong(&held_after)
    );

    let file = std::env::temp_dir().join(format!("umbra-tune-{}.json", std::process::id()));
    biases.save(&file).unwrap();
    let mut app =
        App::new(Settings::default().with(|s| s.scene.biases = Some(LightBiases::load(&file).unwrap()))).unwrap();
    assert_eq!(LightBiases::of(&mut app.world), biases);
}
