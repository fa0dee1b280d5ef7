//! The `umbra` command: play the sample in a window (the default) or render frames headless.

use anyhow::{Context, Result};
use clap::{Args, Parser, Subcommand};
use scene_args::{SceneArgs, parse_angle, parse_radius, parse_size, parse_time};
use std::path::{Path, PathBuf};
use std::time::Instant;
use umbra::assets::ModelInstance;
use umbra::components::Transform;
use umbra::render::{Gpu, render_headless, render_png};
use umbra::{App, Settings};

mod bench_sweep;
mod scene_args;

/// umbra: a game sample about real-time shadow mapping.
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Play the scene in a window (the default); without a display, render umbra.png instead.
    Play(PlayArgs),
    /// Render one deterministic frame headless to a PNG.
    Render(RenderArgs),
    /// Measure every shadow configuration's cost and accuracy against a ray-traced truth, and
    /// chart one against the other (or, with --cache, what the shadow-map cache saves).
    Bench(BenchArgs),
    /// Find the shadow biases, light by light, that give the fewest wrong pixels on the sample
    /// scene, and write them to a file that play, render and bench --cache read (--biases FILE).
    Tune(TuneArgs),
    /// Render the same view under each kind of shadow (hard, the filters, PCSS, the moment maps,
    /// planar, R16F radial, toon) and write a Markdown grid labelling each picture with its cost
    /// and error from a bench run's results.csv.
    Gallery(GalleryArgs),
    /// Write every figure of the README and the book anew from the run it names (a block
    /// `<!-- figure: docs/bench/summary.md | rows: … -->`; see src/figures.rs): after a bench run,
    /// its tables in the docs follow. Run from the project's root.
    Docs,
}

#[derive(Args)]
struct GalleryArgs {
    /// Where the pictures and gallery.md go.
    #[arg(long, default_value = "docs/gallery")]
    out: PathBuf,
    /// The bench run whose numbers label the pictures (its results.csv; by default the latest
    /// quick sweep's, which measures every method the pictures show).
    #[arg(long, default_value = "docs/bench-quick/results.csv", value_name = "CSV")]
    bench: PathBuf,
    /// Width of each picture in pixels.
    #[arg(long, default_value_t = 480, value_parser = parse_size, allow_negative_numbers = true)]
    width: u32,
    /// Height of each picture in pixels.
    #[arg(long, default_value_t = 270, value_parser = parse_size, allow_negative_numbers = true)]
    height: u32,
}

#[derive(Args, Default)]
struct PlayArgs {
    /// Quit after showing this many frames (for smoke tests).
    #[arg(long, value_name = "N")]
    frames: Option<u32>,
    /// Start the scene's clock at this time, in seconds.
    #[arg(long, value_parser = parse_time, allow_negative_numbers = true)]
    time: Option<f64>,
    #[command(flatten)]
    lab: LabArgs,
    #[command(flatten)]
    scene: SceneArgs,
}

/// How the window starts: what the panel's switches would otherwise set.
#[derive(Args, Default)]
struct LabArgs {
    /// Open the panel (Tab).
    #[arg(long)]
    panel: bool,
    /// Hold the scene's clock (H).
    #[arg(long)]
    hold: bool,
    /// Measure the first frame against the truth and lay the errors over it (M).
    #[arg(long)]
    measure: bool,
    /// Measure again whenever the view has been still half a second (N).
    #[arg(long)]
    auto_measure: bool,
    /// Measure at the window's size divided by this: 1, 2 or 4 (default 2).
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u32).range(1..=4))]
    measure_scale: Option<u32>,
    /// Open the shadow-map viewer (V).
    #[arg(long)]
    map_viewer: bool,
    /// Start with the orbit camera round the scene's middle (O).
    #[arg(long)]
    orbit: bool,
}

impl LabArgs {
    fn lab(&self) -> umbra::ui::Lab {
        let d = umbra::ui::Lab::default();
        umbra::ui::Lab {
            panel: self.panel,
            hold: self.hold,
            auto_measure: self.auto_measure,
            measure_scale: self.measure_scale.unwrap_or(d.measure_scale),
            map_viewer: self.map_viewer,
            asked: umbra::ui::panel::Asked { measure: self.measure, camera: self.orbit, screenshot: false },
            ..d
        }
    }
}

#[derive(Args)]
struct RenderArgs {
    /// Where to write the PNG.
    #[arg(long, default_value = "umbra.png")]
    out: PathBuf,
    /// Width in pixels.
    #[arg(long, default_value_t = 1280, value_parser = parse_size, allow_negative_numbers = true)]
    width: u32,
    /// Height in pixels.
    #[arg(long, default_value_t = 720, value_parser = parse_size, allow_negative_numbers = true)]
    height: u32,
    /// Scene time in seconds.
    #[arg(long, default_value_t = 2.0, value_parser = parse_time, allow_negative_numbers = true)]
    time: f64,
    /// Render the frame this many extra times and print the median frame time.
    #[arg(long, default_value_t = 0, value_name = "N")]
    repeat: u32,
    #[command(flatten)]
    scene: SceneArgs,
}

#[derive(Args)]
struct BenchArgs {
    /// The short sweep: a few configurations, small frames (a few minutes on a software adapter).
    #[arg(long)]
    quick: bool,
    /// Where the table, summary and charts go.
    #[arg(long, default_value = "bench", value_name = "DIR")]
    out: PathBuf,
    /// Instead of the sweep: frame cost with shadows off and on while nothing, one cube or
    /// everything moves (what the shadow-map cache saves).
    #[arg(long, conflicts_with = "lab")]
    cache: bool,
    /// Instead of the sweep: frame cost of the still scene alone, with the window's panel open,
    /// and with a measurement against the truth running on a worker thread.
    #[arg(long, conflicts_with = "shadow_pass")]
    lab: bool,
    /// Instead of the sweep: umbra's shadow pass against a bare depth pass drawing the same
    /// casters, on scenes of 10 to 20,000 cubes; writes shadow-pass.md and the scale chart.
    #[arg(long, conflicts_with = "cache")]
    shadow_pass: bool,
    /// Instead of the sweep: 4 to 1,024 lights (the sample's and lanterns), without shadows, in
    /// umbra's atlas, every light paged (one 128 MiB pool), Bevy-like and at fixed sizes: cost,
    /// memory, tiles drawn and stale, pages, texels per pixel and each light's error; writes
    /// lights.md and the lights charts (4 to 64 lights with --quick).
    #[arg(long, conflicts_with_all = ["cache", "lab", "shadow_pass"])]
    lights: bool,
    /// Sweep only the configurations of this family (and the default, for the ratios); give it
    /// again for more: "hard", "grid PCF", "moment maps", "Bevy-like" … (an unknown one is
    /// refused with the list); "contact shadows" takes every configuration with them and its
    /// twin without.
    #[arg(long, value_name = "FAMILY", conflicts_with_all = ["cache", "lab", "shadow_pass", "lights"])]
    family: Vec<String>,
    /// Sweep without the configurations of this family (the default stays, for the ratios); give
    /// it again for more: "moment maps" are half the quick sweep's time on a software rasterizer.
    #[arg(long, value_name = "FAMILY", conflicts_with_all = ["cache", "lab", "shadow_pass", "lights"])]
    skip_family: Vec<String>,
    /// Measure only this failure case (give it again for more; every case when not given): the
    /// others are left unmeasured, with no row in the summary's table of cases and no chart. An
    /// unknown one is refused with the list.
    #[arg(long = "case", value_name = "CASE", conflicts_with_all = ["cache", "lab", "shadow_pass", "lights"])]
    cases: Vec<String>,
    /// Configurations whose errors the sweep measures at once, each on a thread of its own
    /// (default: one per four cores, one to four; the timing is never shared).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=64), conflicts_with_all = ["cache", "lab", "shadow_pass", "lights"])]
    threads: Option<u32>,
    /// Rays over each light's disc for the soft truth (default 32, 8 with --quick).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(0..=4096))]
    soft_rays: Option<u32>,
    /// Angular radius of the sun's disc for the soft truth, in degrees (default 0.27, the real sun's).
    #[arg(long, value_name = "DEGREES", value_parser = parse_angle)]
    sun_radius: Option<f32>,
    /// Radius of a spot light's disc for the soft truth, in metres (default 0.1).
    #[arg(long, value_name = "METRES", value_parser = parse_radius)]
    spot_radius: Option<f32>,
    /// Measured frames per scenario (default 60; 10 with --lights, 3 with --lights --quick).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=100_000))]
    frames: Option<u32>,
    /// Width in pixels.
    #[arg(long, default_value_t = 1280, value_parser = parse_size, allow_negative_numbers = true)]
    width: u32,
    /// Height in pixels.
    #[arg(long, default_value_t = 720, value_parser = parse_size, allow_negative_numbers = true)]
    height: u32,
    #[command(flatten)]
    scene: SceneArgs,
}

#[derive(Args)]
struct TuneArgs {
    /// Where to write the biases found.
    #[arg(long, default_value = "umbra-biases.json", value_name = "FILE")]
    out: PathBuf,
    /// Width of the measured frames in pixels.
    #[arg(long, default_value_t = 480, value_parser = parse_size, allow_negative_numbers = true)]
    width: u32,
    /// Height of the measured frames in pixels.
    #[arg(long, default_value_t = 270, value_parser = parse_size, allow_negative_numbers = true)]
    height: u32,
    #[command(flatten)]
    scene: SceneArgs,
}

fn main() {
    quiet_mesa();
    if let Err(e) = run(Cli::parse()) {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

/// Mesa's EGL looks for a Wayland session through `XDG_RUNTIME_DIR` and, where there is none (CI,
/// ssh, a container), prints "error: XDG_RUNTIME_DIR is invalid or not set", which reads like
/// umbra failing. Where it is unset or not a directory, point it at a private one of umbra's own
/// in the temporary directory; called first, before any thread exists or any driver loads.
#[cfg(unix)]
fn quiet_mesa() {
    use std::os::unix::fs::PermissionsExt;
    if std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| std::path::Path::new(&d).is_dir()) {
        return;
    }
    let dir = std::env::temp_dir().join("umbra-runtime");
    let private = std::fs::Permissions::from_mode(0o700);
    if std::fs::create_dir_all(&dir).is_ok() && std::fs::set_permissions(&dir, private).is_ok() {
        // SAFETY: nothing else runs yet to read the environment at the same time.
        unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
    }
}

#[cfg(not(unix))]
fn quiet_mesa() {}

fn run(cli: Cli) -> Result<()> {
    match cli.command.unwrap_or(Command::Play(PlayArgs::default())) {
        Command::Play(args) => play(args),
        Command::Render(args) => render(&args),
        Command::Bench(args) => bench(&args),
        Command::Tune(args) => tune(&args),
        Command::Gallery(args) => gallery(&args),
        Command::Docs => docs(),
    }
}

fn docs() -> Result<()> {
    let root = Path::new(".");
    let read = |path: &str| std::fs::read_to_string(root.join(path)).map_err(|e| e.to_string());
    for document in umbra::figures::documents(root) {
        let text = std::fs::read_to_string(&document).with_context(|| format!("reading {}", document.display()))?;
        let written = umbra::figures::rewrite(&text, read).with_context(|| format!("in {}", document.display()))?;
        if written != text {
            std::fs::write(&document, written).with_context(|| format!("writing {}", document.display()))?;
            println!("wrote the figures of {}", document.display());
        }
    }
    Ok(())
}

fn gallery(args: &GalleryArgs) -> Result<()> {
    use umbra::eval::gallery::{entries, markdown, read_results};
    let csv = std::fs::read_to_string(&args.bench).with_context(|| format!("reading {}", args.bench.display()))?;
    let results = read_results(&csv).map_err(|e| anyhow::anyhow!("{}: {e}", args.bench.display()))?;
    std::fs::create_dir_all(&args.out).with_context(|| format!("creating {}", args.out.display()))?;
    let gpu = Gpu::headless()?;
    println!("adapter: {}", gpu.describe());
    let all = entries();
    for e in &all {
        // Each picture is its own app (and renderer, which holds its meshes): the same scene,
        // time and camera, drawn its way.
        let mut renderer = umbra::render::Renderer::new(&gpu, umbra::render::HEADLESS_FORMAT)?;
        let mut app = App::new(e.settings(&Settings::default()))?;
        app.hear(renderer.news());
        app.resize(args.width, args.height);
        let (eye, target, time) = umbra::eval::gallery::VIEW;
        umbra::eval::measure::place_camera(&mut app.world, eye, target);
        app.set_time(time);
        let path = args.out.join(format!("{}.png", e.slug));
        render_headless(&gpu, &mut renderer, &mut app, args.width, args.height)
            .and_then(|image| image.save_png(&path))
            .with_context(|| format!("rendering {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    // The pictures sit beside gallery.md; the README shows the same grid from the repository's root.
    let summary = std::fs::read_to_string(args.bench.with_file_name("summary.md")).unwrap_or_default();
    let run = umbra::figures::what_made(&summary);
    let md = format!("Numbers from {}: {run}.\n\n{}", args.bench.display(), markdown(&all, &results, "", 4));
    let path = args.out.join("gallery.md");
    std::fs::write(&path, md).with_context(|| format!("writing {}", path.display()))?;
    println!("wrote {}", path.display());
    Ok(())
}

/// `bench --shadow-pass`: the table on stdout and in `shadow-pass.md`, the chart beside it.
fn shadow_pass(args: &BenchArgs) -> Result<()> {
    use umbra::eval::passes;
    let frames = args.frames.unwrap_or(60);
    let settings = args.scene.settings()?;
    settings.validate()?;
    let gpu = Gpu::headless()?;
    let adapter = gpu.describe();
    println!("adapter: {adapter}");
    println!(
        "{} frames per scene, {}² shadow maps, every layer drawn every frame",
        frames, settings.maps.shadow_map_size
    );
    let rows = passes::run(&gpu, &settings, &passes::SCENE_SIZES, frames, |r| {
        eprintln!("{} cubes: umbra {:.2} ms, bare {:.2} ms", r.cubes, r.umbra_ms, r.bare_ms);
    })?;
    let table = passes::table(&rows);
    print!("{table}");
    std::fs::create_dir_all(&args.out)?;
    std::fs::write(args.out.join("shadow-pass.md"), format!("adapter: {adapter}\n\n{table}"))?;
    let title = format!("shadow pass against casters inside its layers ({adapter})");
    passes::chart(&args.out.join("scale"), &title, &rows)?;
    println!("wrote {}", args.out.join("shadow-pass.md").display());
    Ok(())
}

fn bench(args: &BenchArgs) -> Result<()> {
    if args.shadow_pass {
        return shadow_pass(args);
    }
    if args.lights {
        return lights(args);
    }
    if !args.cache && !args.lab {
        return bench_sweep::sweep(args);
    }
    use umbra::play::bench::{LAB_SCENARIOS, SCENARIOS};
    let scenarios = if args.lab { &LAB_SCENARIOS[..] } else { &SCENARIOS[..] };
    let settings = args.scene.settings()?;
    settings.validate()?;
    let gpu = Gpu::headless()?;
    println!("adapter: {}", gpu.describe());
    println!(
        "{} frames per scenario at {}x{}, {}² shadow maps, {} cascades, {} fit",
        args.frames.unwrap_or(60),
        args.width,
        args.height,
        settings.maps.shadow_map_size,
        settings.cascade.cascades,
        settings.cascade.fit_mode.name()
    );
    let frames = args.frames.unwrap_or(60);
    let rows = umbra::play::bench::run(&gpu, &settings, scenarios, frames, args.width, args.height, |done, all| {
        if done == all || done % 10 == 0 {
            eprint!("\r{done}/{all} rounds");
        }
    })?;
    eprintln!();
    print!("{}", umbra::play::bench::table(&rows));
    Ok(())
}

fn lights(args: &BenchArgs) -> Result<()> {
    use umbra::eval::many;
    let settings = args.scene.settings()?;
    settings.validate()?;
    let gpu = Gpu::headless()?;
    let adapter = gpu.describe();
    // What made the run is what was checked out when it began (files edited while it runs are not
    // in its binary).
    let made = umbra::figures::made_by(Path::new("."), &adapter);
    let counts = if args.quick { &many::QUICK_COUNTS[..] } else { &many::LIGHT_COUNTS[..] };
    let options = many::LightsOptions {
        frames: args.frames.unwrap_or(if args.quick { 3 } else { 10 }),
        size: (args.width, args.height),
        measure: ((args.width / 2).max(16), (args.height / 2).max(16)),
        soft_rays: args.soft_rays.unwrap_or(if args.quick { 8 } else { 32 }) as usize,
    };
    println!("adapter: {adapter}");
    println!(
        "{} frames per run at {}x{} after a warm-up, measured at {}x{} against the truth ({} soft rays)",
        options.frames, options.size.0, options.size.1, options.measure.0, options.measure.1, options.soft_rays
    );
    let rows = many::run(&gpu, &settings, counts, options, |r| {
        eprintln!("{} lights, {}: {:.1} ms a frame, {} MiB", r.lights, r.policy.name(), r.frame_ms, r.memory_mib);
    })?;
    let table = many::table(&rows);
    print!("{table}");
    let shrink = shrink_sweep(&gpu, &settings)?;
    print!("{shrink}");
    std::fs::create_dir_all(&args.out)?;
    let head = format!(
        "adapter: {adapter}; {} frames at {}x{}, measured at {}x{}\n\n{}\n\n{}\n\n",
        options.frames,
        options.size.0,
        options.size.1,
        options.measure.0,
        options.measure.1,
        made,
        many::columns_note()
    );
    let tail =
        format!("\nThe tile-shrink case's spot with its tile held at each side (256x256, from 24 m up):\n\n{shrink}");
    std::fs::write(args.out.join("lights.md"), head + &table + &tail)?;
    many::charts(&args.out.join("lights"), &adapter, &rows)?;
    println!("wrote {}", args.out.join("lights.md").display());
    Ok(())
}

/// The tile-shrink case's error against its tile's side, predicted and measured (a table).
fn shrink_sweep(gpu: &Gpu, settings: &Settings) -> Result<String> {
    use umbra::eval::cases::{budget, case};
    use umbra::eval::measure::{Measurer, TruthSettings};
    let threshold = case("tile-shrink").map_or(0.005, |c| c.threshold);
    let mut m = Measurer::new(gpu, (256, 256), TruthSettings { soft_rays: 0, ..TruthSettings::default() });
    let points = budget::tile_shrink_sweep(&mut m, settings, &[32, 64, 128, 256, 512, 1024, 2048])?;
    Ok(umbra::eval::many::shrink_table(&points, threshold))
}

/// The sample scene or the user's, with what was mended in the user's file (if any) said on
/// stderr.
fn app(scene: &SceneArgs) -> Result<App> {
    let mut app = App::new(scene.settings()?)?;
    let mut models = app.world.query::<(&ModelInstance, &Transform)>();
    let file = scene.model.as_ref().or(scene.scene.as_ref()).map(|p| p.display().to_string());
    for (model, placement) in models.iter(&app.world).filter(|(m, _)| file.as_ref() == Some(&m.0.name)) {
        for warning in &model.0.warnings {
            eprintln!("warning: {warning}");
        }
        let joints = model.0.skins.iter().map(|s| s.joints.len()).sum::<usize>();
        let clip = model.0.clips.first().map_or("no animation".to_string(), |c| format!("playing \"{}\"", c.name));
        println!(
            "{} {}: {} parts, {joints} joints, {clip}, at scale {}",
            if scene.scene.is_some() { "scene" } else { "model" },
            model.0.name,
            model.0.parts.len(),
            placement.scale.x
        );
    }
    if let Some((model, _)) = models.iter(&app.world).find(|_| scene.scene.is_some()) {
        let (lights, camera) = (model.0.lights.len(), model.0.camera.is_some());
        let labels: Vec<_> = umbra::light::light_list(&app.world).iter().map(|l| l.label).collect();
        println!(
            "lights: {}{}; {}",
            umbra::light::names::lights_line(&labels),
            if lights == 0 { " (added: the file has no light)" } else { "" },
            if camera { "its own camera" } else { "a camera that frames it (the file has none)" }
        );
    }
    Ok(app)
}

fn tune(args: &TuneArgs) -> Result<()> {
    let settings = args.scene.settings()?;
    settings.validate()?;
    let gpu = Gpu::headless()?;
    println!("adapter: {}", gpu.describe());
    let bar = indicatif::ProgressBar::new(1);
    let (lights, biases) = umbra::eval::tune::tune(&gpu, &settings, (args.width, args.height), |done, of| {
        bar.set_length(of as u64);
        bar.set_position(done as u64);
    })?;
    bar.finish_and_clear();
    println!(
        "wrong pixels (false shadow + false lit) over the views of {} at {}x{}:",
        args.scene.scene.as_ref().map_or("the sample scene".to_string(), |p| p.display().to_string()),
        args.width,
        args.height
    );
    let shown = |t: &umbra::eval::metrics::Tally| {
        format!("{} ({:.4}%)", t.false_shadow + t.false_lit, 100.0 * t.misclassified())
    };
    println!("tuned on the first half of the views; held out: the other half, which the search never saw");
    println!(
        "| light | tuned on: before | after | held out: before | after | bias found: constant, slope, normal (texels); scale; receiver plane |"
    );
    println!("| --- | --- | --- | --- | --- | --- |");
    for l in &lights {
        let (held_before, held_after) =
            l.held_out.as_ref().map_or(("-".into(), "-".into()), |(b, a)| (shown(b), shown(a)));
        println!(
            "| {} | {} | {} | {held_before} | {held_after} | {}, {}, {}; {}; {} |",
            l.light,
            shown(&l.before),
            shown(&l.after),
            l.bias.constant,
            l.bias.slope,
            l.bias.normal,
            l.bias.scale,
            if l.bias.receiver_plane { "on" } else { "off" }
        );
    }
    biases.save(&args.out)?;
    println!("wrote {}; use it with `umbra play --biases {}`", args.out.display(), args.out.display());
    Ok(())
}

fn play(args: PlayArgs) -> Result<()> {
    let mut app = app(&args.scene)?;
    if let Some(t) = args.time {
        app.set_time(t);
    }
    Ok(umbra::play::play_or_render(app, args.frames, args.lab.lab(), Path::new("umbra.png"))?)
}

fn render(args: &RenderArgs) -> Result<()> {
    let mut app = app(&args.scene)?;
    let (gpu, mut renderer, _) = render_png(&mut app, args.width, args.height, args.time, &args.out)
        .with_context(|| format!("rendering {}", args.out.display()))?;
    println!("adapter: {}", gpu.describe());
    println!("wrote {} ({}x{})", args.out.display(), args.width, args.height);
    for notice in app.take_notices() {
        eprintln!("warning: {notice}");
    }
    if args.repeat == 0 {
        return Ok(());
    }
    let mut times = Vec::new();
    for _ in 0..args.repeat {
        let start = Instant::now();
        render_headless(&gpu, &mut renderer, &mut app, args.width, args.height)?;
        times.push(start.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    println!(
        "frame time (shadow pass + main pass + readback) over {} frames: median {:.1} ms, min {:.1}, max {:.1}",
        times.len(),
        times[times.len() / 2],
        times[0],
        times[times.len() - 1]
    );
    Ok(())
}
