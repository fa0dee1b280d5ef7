//! `umbra bench`'s sweep: every configuration's cost and error, the summary, table and charts.

use super::{BenchArgs, app};
use anyhow::Result;
use std::path::Path;
use std::time::Instant;
use umbra::Settings;
use umbra::render::Gpu;

/// Runs the sweep `args` asks for and writes its results.
pub(super) fn sweep(args: &BenchArgs) -> Result<()> {
    use umbra::eval::{cost, results, sweep, sweep_options};
    let settings = args.scene.settings()?;
    let d = Settings::default();
    if (settings.clone().with(|s| {
        s.scene.file = None;
        s.scene.exposure = d.scene.exposure;
    })) != d
    {
        anyhow::bail!(
            "the sweep sets the shadow settings itself; of the scene options it takes --scene and --exposure, the rest apply to `bench --cache` only"
        );
    }
    let mut options = sweep_options::SweepOptions::new(args.quick);
    options.families = args.family.clone();
    options.skipped = args.skip_family.clone();
    options.cases = (!args.cases.is_empty()).then(|| args.cases.clone());
    if let Some(n) = args.threads {
        options.workers = n as usize;
    }
    // An unknown family or case is refused before a GPU is looked for.
    options.configs().map_err(anyhow::Error::msg)?;
    if settings.scene.file.is_some() {
        options.views = sweep_options::views(&mut app(&args.scene)?);
        options.base = settings;
    }
    let gpu = Gpu::headless()?;
    // What made the run is what was checked out when it began (files edited while it runs are not
    // in its binary).
    let made = umbra::figures::made_by(Path::new("."), &gpu.describe());
    if let Some(n) = args.soft_rays {
        options.truth.soft_rays = n as usize;
    }
    if let Some(degrees) = args.sun_radius {
        options.truth.sizes.sun_angular_radius = Some(degrees.to_radians());
    }
    if let Some(r) = args.spot_radius {
        options.truth.sizes.light_radius = Some(r);
    }
    let scene = match &options.base.scene.file {
        Some(path) => format!("the scene {}", path.display()),
        None => "the sample scene".to_string(),
    };
    let configs = sweep::configs_on(&gpu, &options)?.len();
    let timing = if cost::timed_on_gpu(&gpu) { "GPU timestamps" } else { "the wall clock (no timestamps here)" };
    println!("adapter: {}", gpu.describe());
    println!(
        "{} sweep{}: {configs} configurations; {scene} at {}x{} from {} views, failure cases at {}x{}; timed by {timing}",
        if args.quick { "quick" } else { "full" },
        families(&options),
        options.size.0,
        options.size.1,
        options.views.len(),
        options.case_size.0,
        options.case_size.1,
    );
    let bar = indicatif::ProgressBar::new(1);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {elapsed_precise} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let started = Instant::now();
    let mut timed = None;
    let rows = sweep::run(&gpu, &options, |done, of, what| {
        if what != sweep::TIMING && timed.is_none() {
            timed = Some(started.elapsed().as_secs_f64());
        }
        bar.set_length(of as u64);
        bar.set_position(done as u64);
        bar.set_message(what.to_string());
    })?;
    let total = started.elapsed().as_secs_f64();
    let timed = timed.unwrap_or(total);
    bar.finish_and_clear();
    let heading = format!(
        "# umbra bench{}

{} configurations{} on {}, timed by {timing}; {:.0} s in all ({:.0} s timing, {:.0} s measuring errors). Shadow cost: the median over {} \
         frames of drawing every shadow layer (a frame with every map drawn against the same frame with every \
         map kept) plus what the lookups add (that frame against one with shadows off). Errors: pixels of {} views of {scene} at {}x{} against a ray-traced truth (every light \
         together; the soft truth from {} rays over each light's disc: {}).\n\n{}",
        if args.quick { " --quick" } else { "" },
        rows.len(),
        families(&options),
        gpu.describe(),
        total,
        timed,
        total - timed,
        options.frames as usize * options.views.len(),
        options.views.len(),
        options.size.0,
        options.size.1,
        options.truth.soft_rays,
        light_sizes(options.truth.sizes),
        made,
    );
    let summary = results::write_all(&rows, &args.out, &heading, &gpu.describe())?;
    println!("{summary}");
    println!("wrote {}: results.csv, summary.md and the charts (.png and .svg)", args.out.display());
    Ok(())
}

/// The families a sweep was narrowed to and those it left out, in words ("" for all).
fn families(options: &umbra::eval::sweep_options::SweepOptions) -> String {
    let (names, skipped) = (&options.families, &options.skipped);
    match (names.is_empty(), skipped.is_empty()) {
        (true, true) => String::new(),
        (false, true) => format!(" (the family {} and the default)", names.join(", ")),
        (true, false) => format!(" (without the family {})", skipped.join(", ")),
        (false, false) => format!(" (the family {} and the default, without {})", names.join(", "), skipped.join(", ")),
    }
}

/// The light sizes the soft truth takes, in words.
fn light_sizes(sizes: umbra::eval::truth::SizeOverride) -> String {
    let sun = sizes
        .sun_angular_radius
        .map_or("each sun its own size".to_string(), |r| format!("a {:.2}° sun", r.to_degrees()));
    let local = sizes.light_radius.map_or("each other light its own".to_string(), |r| format!("{r} m lights"));
    format!("{sun}, {local}")
}
