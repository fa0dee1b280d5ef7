//! The `umbra` command as a user runs it: a valid PNG of the asked size, clear errors otherwise.

mod common;

use common::scratch;
use std::path::PathBuf;
use std::process::{Command, Output};

fn umbra(args: &[&str], dir: &PathBuf) -> Output {
    Command::new(env!("CARGO_BIN_EXE_umbra"))
        .args(args)
        .current_dir(dir)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap()
}

fn png_size(path: &PathBuf) -> (u32, u32) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let reader = decoder.read_info().expect("a valid PNG");
    (reader.info().width, reader.info().height)
}

#[test]
fn render_writes_a_png_of_the_requested_size() {
    let dir = scratch("render");
    let out = umbra(&["render", "--out", "frame.png", "--width", "96", "--height", "54", "--time", "1.25"], &dir);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("adapter:"), "the adapter is named: {stdout}");
    assert_eq!(png_size(&dir.join("frame.png")), (96, 54));
}

#[test]
fn without_a_display_play_renders_umbra_png() {
    let dir = scratch("play");
    let out = umbra(&[], &dir);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(stdout.lines().filter(|l| l.starts_with("no display")).count(), 1, "{stdout}");
    assert_eq!(png_size(&dir.join("umbra.png")), (1280, 720));
}

#[test]
fn bad_arguments_are_named_and_fail() {
    let dir = scratch("bad");
    let cases: [(&[&str], &str); 30] = [
        (&["render", "--bias-scale", "0.9"], "bias_scale"),
        (&["render", "--shadow-depth", "d8"], "'d8' for '--shadow-depth <FORMAT>'\n  [possible values: d32, d16]"),
        (&["render", "--moment-bits", "24"], "[possible values: auto, 16, 32]"),
        (&["render", "--moment-blur", "99"], "moment_blur"),
        (&["render", "--light-bleeding", "1"], "light_bleeding"),
        (&["bench", "--shadow-map-size", "512"], "apply to `bench --cache` only"),
        (&["bench", "--sun-radius", "45"], "not an angle"),
        (&["render", "--width", "-5"], "not a size"),
        (&["render", "--cascades", "5"], "cascades"),
        (&["render", "--split-lambda", "2"], "split_lambda"),
        (&["render", "--fit", "loose"], "'loose' for '--fit <MODE>'"),
        (&["bench", "--frames", "0"], "--frames"),
        (&["render", "--height", "0"], "not a size"),
        (&["render", "--time", "nan"], "not a time"),
        (&["render", "--frobnicate"], "--frobnicate"),
        (&["render", "--shadow-strength", "3"], "shadow_strength"),
        (&["render", "--light-method", "lamp=pcss"], "no light is called `lamp`: the scene's lights are `sun`"),
        (&["render", "--light-method", "spot 1=blurry"], "not a shadow method"),
        (&["render", "--light-method", "pcss"], "not LIGHT=METHOD"),
        (&["render", "--light-bias", "sun=1,2"], "not CONSTANT,SLOPE,NORMAL"),
        (&["render", "--light-bias", "moon=1,2,3"], "no light is called `moon`"),
        (&["render", "--light-size", "sun=-1"], "not a size"),
        (&["render", "--no-light-shadow", "lamp"], "no light is called `lamp`"),
        (&["render", "--eye", "1,2,3"], "--target"),
        (&["render", "--eye", "1,2", "--target", "0,0,0"], "not a point"),
        (&["play", "--measure-scale", "9"], "--measure-scale"),
        (&["render", "--sun-maps", "virtual", "--method", "vsm"], "vsm reads a colour map"),
        (&["render", "--sun-maps", "paged"], "[possible values: cascades, virtual]"),
        (&["render", "--page-bias", "9"], "page_bias"),
        (&["render", "--page-memory", "200"], "page_memory"),
    ];
    for (args, says) in cases {
        let out = umbra(args, &dir);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} should fail");
        assert!(stderr.contains(says), "{args:?}: stderr should mention {says:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
    }
    assert!(!dir.join("umbra.png").exists(), "a failed command writes nothing");
}

#[test]
fn bench_prints_every_scenario_with_ratios_and_shadow_passes() {
    let dir = scratch("bench");
    let out = umbra(
        &["bench", "--cache", "--frames", "3", "--width", "64", "--height", "36", "--shadow-map-size", "256"],
        &dir,
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let row = |name: &str| {
        let line = stdout
            .lines()
            .find(|l| l.starts_with(&format!("| {name} |")))
            .unwrap_or_else(|| panic!("{name}: {stdout}"));
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        let passes: Vec<f64> = cells[5].split(" / ").map(|v| v.parse().unwrap()).collect();
        (cells[4].to_string(), passes[0], passes[1])
    };
    // Still with shadows off is the baseline; with shadows on and nothing moving, every layer
    // (4 cascades, 2 spots and the lantern's 6 cube faces) is kept and none drawn; one moving
    // cube redraws only some.
    assert_eq!(row("still, shadows off").0, "1.000", "{stdout}");
    assert_eq!(row("still, shadows on"), (row("still, shadows on").0, 0.0, 12.0), "{stdout}");
    let (_, drawn, kept) = row("one cube moving");
    assert!(drawn > 0.0 && kept > 0.0, "{stdout}");
    let (_, drawn, _) = row("everything moving");
    assert!(drawn > 0.0, "{stdout}");
}

#[test]
fn a_users_model_is_placed_in_the_scene_or_named_in_a_clear_error() {
    let dir = scratch("model");
    let model = common::gltf::TestModel::new();
    std::fs::write(dir.join("column.glb"), model.glb()).unwrap();
    let out = umbra(&["render", "--model", "column.glb", "--out", "m.png", "--width", "64", "--height", "36"], &dir);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("model column.glb: 1 parts, 2 joints, playing \"bend\""), "{stdout}");
    assert_eq!(png_size(&dir.join("m.png")), (64, 36));

    // Mended problems are warnings; broken files are errors that name the file and write nothing.
    let mut heavy = model.clone();
    let weights = heavy.add_floats(&[[2.0f32, 2.0, 0.0, 0.0]; 12].concat(), "VEC4");
    heavy.json["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] = serde_json::json!(weights);
    std::fs::write(dir.join("heavy.glb"), heavy.glb()).unwrap();
    let out = umbra(&["render", "--model", "heavy.glb", "--out", "h.png", "--width", "32", "--height", "32"], &dir);
    assert!(out.status.success());
    assert!(
        String::from_utf8_lossy(&out.stderr)
            .contains("warning: heavy.glb: primitive 0: 12 vertices had weights not summing to 1")
    );
    let glb = model.glb();
    std::fs::write(dir.join("cut.glb"), &glb[..glb.len() - 100]).unwrap();
    let refusals = [
        ("cut.glb", "cut.glb: truncated .glb"),
        ("missing.glb", "missing.glb: cannot read it"),
        ("/dev/zero", "/dev/zero: it is a device, not a file"),
        (".", "it is a directory"),
    ];
    for (file, says) in refusals {
        let out = umbra(&["render", "--model", file, "--out", "x.png"], &dir);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && stderr.contains(says) && !stderr.contains("panicked"), "{stderr}");
    }
    assert!(!dir.join("x.png").exists());
}

#[test]
fn a_scene_file_plays_with_its_lights_or_gets_a_sun() {
    use common::scene_file::SceneFile;
    use glam::Vec3;
    let dir = scratch("scene");
    let lamp = serde_json::json!({ "type": "point", "intensity": 10.0 });
    SceneFile::new().light(lamp, Vec3::new(1.0, 2.0, 1.0), Vec3::NEG_Y).write(&dir, "lamp.gltf");
    SceneFile::new().write(&dir, "bare.gltf");
    let small = ["--width", "64", "--height", "36"];
    let out = umbra(&[&["render", "--scene", "lamp.gltf", "--out", "s.png"][..], &small].concat(), &dir);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("scene lamp.gltf: 3 parts"), "{stdout}");
    assert!(stdout.contains("lights: point 1; a camera that frames it (the file has none)"), "{stdout}");
    assert_eq!(png_size(&dir.join("s.png")), (64, 36));
    let out = umbra(&[&["render", "--scene", "bare.gltf", "--out", "b.png"][..], &small].concat(), &dir);
    assert!(String::from_utf8_lossy(&out.stdout).contains("lights: sun (added: the file has no light)"));
    // A scene replaces the sample, so a model cannot go into it; nonsense exposure is named.
    let out = umbra(&["render", "--scene", "bare.gltf", "--model", "bare.gltf"], &dir);
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("--model"));
    let out = umbra(&["render", "--scene", "bare.gltf", "--exposure", "0"], &dir);
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("exposure"));
}

#[test]
fn a_broken_bias_file_is_named_and_nothing_is_written() {
    let dir = scratch("biases");
    std::fs::write(dir.join("bad.json"), "{ not json").unwrap();
    std::fs::write(dir.join("negative.json"), r#"{"lights": {"sun": {"constant": -2, "slope": 0, "normal": 0}}}"#)
        .unwrap();
    std::fs::write(dir.join("lamp.json"), r#"{"methods": {"lamp": "pcss"}}"#).unwrap();
    std::fs::write(dir.join("blurry.json"), r#"{"methods": {"sun": "blurry"}}"#).unwrap();
    let cases = [
        ("bad.json", "bad.json: not JSON"),
        ("negative.json", "sun: `constant` = -2"),
        ("gone.json", "cannot read it"),
        ("lamp.json", "no light is called `lamp`"),
        ("blurry.json", "blurry.json: methods: sun: `blurry` is not a shadow method"),
    ];
    for (file, says) in cases {
        let out = umbra(&["render", "--biases", file, "--out", "b.png"], &dir);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && stderr.contains(says) && !stderr.contains("panicked"), "{stderr}");
    }
    assert!(!dir.join("b.png").exists());
    // A good file's methods are taken: the sun's shadow sampled by PCSS renders.
    std::fs::write(dir.join("good.json"), r#"{"methods": {"sun": "pcss"}}"#).unwrap();
    let out = umbra(&["render", "--biases", "good.json", "--width", "64", "--height", "36", "--out", "b.png"], &dir);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn no_adapter_is_a_clear_error_not_a_panic() {
    if cfg!(target_vendor = "apple") {
        return; // Metal is a real backend there.
    }
    let dir = scratch("noadapter");
    // Metal exists only on Apple machines: asking for it alone leaves no adapter here.
    let out = Command::new(env!("CARGO_BIN_EXE_umbra"))
        .args(["render", "--width", "8", "--height", "8"])
        .current_dir(&dir)
        .env("WGPU_BACKEND", "metal")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("no GPU adapter found"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!dir.join("umbra.png").exists());
}

#[test]
fn help_lists_every_shadow_method_the_parser_takes_and_a_wrong_one_is_refused_with_them() {
    let dir = std::env::temp_dir();
    let help = String::from_utf8(umbra(&["render", "--help"], &dir).stdout).unwrap();
    // The option's entry: its line and what follows up to the next option.
    let entry: String = help
        .lines()
        .skip_while(|l| !l.trim_start().starts_with("--method"))
        .enumerate()
        .take_while(|(i, l)| *i == 0 || !l.trim_start().starts_with('-'))
        .map(|(_, l)| format!("{l}\n"))
        .collect();
    let listed = entry.split("[possible values:").nth(1).expect("--method lists its values");
    let words: Vec<&str> = listed.split(|c: char| !(c.is_ascii_alphanumeric() || c == '-')).collect();
    for method in umbra::components::ShadowMethod::ALL {
        assert_eq!(method.name().parse::<umbra::components::ShadowMethod>(), Ok(*method));
        assert!(words.contains(&method.name()), "--help does not list {}: {entry}", method.name());
    }
    let wrong = umbra(&["render", "--method", "blurry", "--out", "never.png"], &dir);
    let err = String::from_utf8(wrong.stderr).unwrap();
    assert!(!wrong.status.success() && err.contains("--method") && err.contains("msm-hausdorff"), "{err}");
    assert!(!dir.join("never.png").exists());
}
