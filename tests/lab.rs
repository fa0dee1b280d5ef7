//! The lab without a window: the live measurement against the bench's, the overlay where the
//! acne is, and a bias or size dragged on the panel redrawing only its own light's maps.

mod common;

use common::gpu;
use glam::Vec3;
use umbra::components::{ShadowBias, SpotLight};
use umbra::eval::cases::scenes::{ground, set_sun, sun_direction};
use umbra::eval::live::{OVERLAY_OPACITY, Taken, Worker, snapshot};
use umbra::eval::measure::{Measurer, TruthSettings, place_camera};
use umbra::eval::metrics::{DARK, rendered};
use umbra::eval::sweep::scene_accuracy;
use umbra::eval::sweep_options::{SweepOptions, VIEWS};
use umbra::light::light_list;
use umbra::render::{HEADLESS_FORMAT, Renderer, ShadowStats, render_headless};
use umbra::ui::{History, Lab, Live};
use umbra::{App, Settings};

#[test]
fn the_overlays_numbers_are_the_benchs_for_the_same_view() {
    let gpu = gpu();
    let options = SweepOptions::new(true);
    let view = VIEWS[0];
    let settings = Settings::default().with(|s| s.shadow.method = umbra::components::ShadowMethod::Pcf3);
    let mut bench = Measurer::new(&gpu, options.size, options.truth);
    let (expected, names) = scene_accuracy(&mut bench, &settings, &[view]).unwrap();

    // As played: a window twice the measured size, the view on screen, then measured.
    let (w, h) = (options.size.0 * 2, options.size.1 * 2);
    let mut app = App::new(settings).unwrap();
    app.resize(w, h);
    place_camera(&mut app.world, view.eye, view.target);
    app.set_time(view.time);
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    render_headless(&gpu, &mut renderer, &mut app, w, h).unwrap();
    let shot = snapshot(&gpu, &mut renderer, &mut app, options.size, options.truth).unwrap();
    let mut worker = Worker::default();
    worker.start("overview", shot);
    let Taken::Done(tag, live) = worker.wait() else { panic!("the worker gave nothing back") };
    assert_eq!(tag, "overview");
    let live_names: Vec<String> = live.lights.iter().map(|(n, _)| n.clone()).collect();
    assert_eq!(live_names, names);
    for ((name, got), want) in live.lights.iter().zip(&expected) {
        assert!(want.all.pixels > 1000, "{name}: the view shows its light");
        // The errors (the bench counts texels per pixel besides, which the overlay does not show).
        let errors = |r: &umbra::eval::metrics::LightReport| (r.all, r.bands, r.edge);
        assert_eq!(errors(got), errors(want), "{name}: the overlay's numbers are the bench's");
    }
}

/// A false shadow in the overlay: red at full opacity.
const RED: [u8; 4] = [255, 40, 30, (OVERLAY_OPACITY * 255.0 + 0.5) as u8];

/// The acne case's open plane under a 35° sun, measured live with `bias` texels of every kind.
fn acne_overlay(bias: f32) -> (umbra::eval::live::LiveReport, usize) {
    let gpu = gpu();
    let settings = Settings::default().with(|s| {
        s.shadow.depth_bias = bias;
        s.shadow.slope_bias = bias;
        s.shadow.normal_bias = bias;
    });
    let mut app =
        ground(&settings, 80.0, true, Vec3::NEG_Y, (Vec3::new(0.0, 5.0, 10.0), Vec3::new(0.0, 0.0, -2.0))).unwrap();
    set_sun(&mut app, sun_direction(35.0, 30.0));
    app.resize(384, 384);
    app.set_time(0.0);
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    let truth = TruthSettings { soft_rays: 0, ..Default::default() };
    let report = snapshot(&gpu, &mut renderer, &mut app, (192, 192), truth).unwrap().measure();
    let red = report.overlay.chunks_exact(4).filter(|p| *p == RED).count();
    (report, red)
}

#[test]
fn the_overlay_is_red_where_the_acne_is_and_nearly_empty_with_the_default_bias() {
    let (acne, red) = acne_overlay(0.0);
    let ground = acne.frame.position.iter().filter(|p| p.w > 0.5).count();
    assert!(red * 10 > ground, "zero bias: acne over a tenth of the plane at least ({red} of {ground})");
    // Red exactly where the renderer says dark and the truth says lit.
    for i in 0..ground.min(acne.frame.position.len()) {
        let acne_here =
            acne.truth[0][i].is_some_and(|t| t.lit) && rendered(&acne.frame, 0, i).is_some_and(|v| v < DARK);
        assert_eq!(acne.overlay[4 * i..4 * i + 4] == RED, acne_here, "pixel {i}");
    }
    assert_eq!(red as u64, acne.lights[0].1.all.false_shadow, "the picture and the numbers agree");
    let (clean, red) = acne_overlay(ShadowBias::default().constant);
    let wrong = clean.overlay.chunks_exact(4).filter(|p| p[3] > 0).count();
    assert!(wrong * 1000 < ground, "default bias: nearly empty ({wrong} marked, {red} red, of {ground})");
}

/// Every text egui laid out, with its rectangle.
fn all_texts(shapes: &[egui::epaint::ClippedShape]) -> Vec<(String, egui::Rect)> {
    fn walk(shape: &egui::Shape, out: &mut Vec<(String, egui::Rect)>) {
        match shape {
            egui::Shape::Text(t) => out.push((t.galley.text().to_string(), t.visual_bounding_rect())),
            egui::Shape::Vec(v) => v.iter().for_each(|s| walk(s, out)),
            _ => {}
        }
    }
    let mut out = Vec::new();
    shapes.iter().for_each(|s| walk(&s.shape, &mut out));
    out
}

/// Rectangles of the texts `text` egui laid out, top first.
fn texts(shapes: &[egui::epaint::ClippedShape], text: &str) -> Vec<egui::Rect> {
    let mut out: Vec<egui::Rect> = all_texts(shapes).into_iter().filter(|(t, _)| t == text).map(|(_, r)| r).collect();
    out.sort_by(|a, b| a.top().total_cmp(&b.top()));
    out
}

/// A point on the rail of the slider labelled at `label`: a slider is its rail, its value's box
/// (the text just left of the label on that row), then its label.
fn on_slider(shapes: &[egui::epaint::ClippedShape], label: egui::Rect) -> egui::Pos2 {
    let value = all_texts(shapes)
        .into_iter()
        .map(|(_, r)| r)
        .filter(|r| (r.center().y - label.center().y).abs() < 2.0 && r.right() < label.left())
        .max_by(|a, b| a.right().total_cmp(&b.right()))
        .expect("a slider's value box");
    // The box's frame and the gap before it, then a point well inside the 100-pixel rail.
    egui::pos2(value.left() - 12.0 - 30.0, label.center().y)
}

/// Runs the panel over `app` once with `events`, and gives back what it drew.
fn panel_pass(
    ctx: &egui::Context,
    app: &mut App,
    lab: &mut Lab,
    events: Vec<egui::Event>,
) -> Vec<egui::epaint::ClippedShape> {
    let (history, stats) = (History::default(), ShadowStats::default());
    let live = Live { history: &history, stats: &stats, measured: None, status: "", camera: "fly", adapter: "test" };
    let input = egui::RawInput {
        screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1280.0, 4000.0))),
        events,
        ..Default::default()
    };
    let mut out = ctx.run_ui(input, |ui| umbra::ui::panel(ui, &mut app.world, lab, &live));
    let shapes = std::mem::take(&mut out.shapes);
    out.drop_without_applying_deltas();
    shapes
}

fn button(at: egui::Pos2, pressed: bool) -> egui::Event {
    egui::Event::PointerButton { pos: at, button: egui::PointerButton::Primary, pressed, modifiers: Default::default() }
}

fn click(at: egui::Pos2) -> Vec<egui::Event> {
    vec![egui::Event::PointerMoved(at), button(at, true), button(at, false)]
}

/// Presses at `at`, drags to `to` and lets go, a pass each, as a slider wants.
fn drag(ctx: &egui::Context, app: &mut App, lab: &mut Lab, at: egui::Pos2, to: egui::Pos2) {
    panel_pass(ctx, app, lab, vec![egui::Event::PointerMoved(at), button(at, true)]);
    panel_pass(ctx, app, lab, vec![egui::Event::PointerMoved(to)]);
    panel_pass(ctx, app, lab, vec![button(to, false)]);
}

#[test]
fn a_bias_or_size_dragged_on_the_panel_changes_only_its_light_and_redraws_nothing() {
    let gpu = gpu();
    let mut app = App::new(Settings::default()).unwrap();
    app.resize(256, 256);
    app.set_time(2.0);
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    render_headless(&gpu, &mut renderer, &mut app, 256, 256).unwrap();
    let lights = light_list(&app.world);
    let spot = lights.iter().find(|l| l.label.to_string() == "spot 1").unwrap().entity;

    let ctx = egui::Context::default();
    // Sections open at once, not over a few frames.
    ctx.all_styles_mut(|s| s.animation_time = 0.0);
    let mut lab = Lab { panel: true, ..Lab::default() };
    let shapes = panel_pass(&ctx, &mut app, &mut lab, vec![]);
    let header = texts(&shapes, "spot 1")[0];
    panel_pass(&ctx, &mut app, &mut lab, click(header.center()));
    let shapes = panel_pass(&ctx, &mut app, &mut lab, vec![]);
    let constants = texts(&shapes, "constant");
    assert_eq!(constants.len(), 1, "spot 1's bias (the settings' is in the closed Shadows section)");
    let at = on_slider(&shapes, constants[0]);
    drag(&ctx, &mut app, &mut lab, at, egui::pos2(1000.0, at.y));
    let bias = *app.world.get::<ShadowBias>(spot).expect("spot 1 has a bias of its own now");
    assert_eq!(bias.constant, 8.0, "dragged to the far end of a 0..8 slider");
    assert_eq!(app.settings(), Settings::default(), "the settings' bias is untouched");
    for other in lights.iter().filter(|l| l.entity != spot) {
        assert!(app.world.get::<ShadowBias>(other.entity).is_none(), "{} keeps the settings' bias", other.label);
    }
    app.set_time(2.0);
    render_headless(&gpu, &mut renderer, &mut app, 256, 256).unwrap();
    let stats = app.world.resource::<ShadowStats>().clone();
    assert_eq!(stats.drawn(), 0, "a bias is applied when maps are read, so nothing is redrawn: {stats}");

    // The radius is the light's size, which PCSS reads when it samples the maps: it reaches the
    // shaders, and like the bias it redraws nothing. Laid out afresh: the light's own bias
    // brought a button above the radius.
    let shapes = panel_pass(&ctx, &mut app, &mut lab, vec![]);
    let at = on_slider(&shapes, texts(&shapes, "radius (m)")[0]);
    drag(&ctx, &mut app, &mut lab, at, egui::pos2(1000.0, at.y));
    assert_eq!(app.world.get::<SpotLight>(spot).unwrap().radius, 1.0, "dragged to the far end of 0..1 m");
    app.set_time(2.0);
    render_headless(&gpu, &mut renderer, &mut app, 256, 256).unwrap();
    let stats = app.world.resource::<ShadowStats>().clone();
    assert_eq!(stats.drawn(), 0, "a size is applied when maps are read, so nothing is redrawn: {stats}");
    let data = umbra::render::extract(&app.world);
    let sizes: Vec<(String, f32)> = data.lights.iter().map(|l| (l.light.label.to_string(), l.gpu().size)).collect();
    assert!(sizes.iter().any(|(name, size)| name == "spot 1" && *size == 1.0), "{sizes:?}");
}

#[test]
fn a_window_state_renders_the_same_headless_from_its_command_line() {
    use umbra::components::ShadowMethod;
    use umbra::reproduce::{LightSetting, apply, command_line};
    let gpu = gpu();
    let mut app = App::new(Settings::default()).unwrap();
    // What a learner did in the window: settings, a light's method, bias, size and shadow, the camera.
    let learned = app.settings().with(|s| {
        (s.cascade.cascades, s.shadow.method, s.cascade.shadow_distance, s.view.toon_bands) =
            (2, ShadowMethod::Gauss5, 40.0, 3)
    });
    app.set_settings(&learned).unwrap();
    let own = [
        ("spot 1".to_string(), LightSetting::Method(ShadowMethod::Pcss)),
        (
            "sun".to_string(),
            LightSetting::Bias(ShadowBias {
                constant: 1.25,
                slope: 0.0,
                normal: 2.0,
                scale: 0.01,
                receiver_plane: false,
            }),
        ),
        ("point 1".to_string(), LightSetting::Size(0.3)),
        ("spot 2".to_string(), LightSetting::NoShadow),
    ];
    apply(&mut app.world, &own).unwrap();
    place_camera(&mut app.world, Vec3::new(4.0, 3.0, 9.0), Vec3::new(-1.0, 0.5, 0.0));
    app.resize(256, 256);
    app.set_time(3.5);
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    let window = render_headless(&gpu, &mut renderer, &mut app, 256, 256).unwrap();
    drop((renderer, gpu));

    let args = command_line(&mut app.world);
    let out = common::scratch("reproduce").join("view.png");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_umbra"))
        .args(["render", "--width", "256", "--height", "256", "--out"])
        .arg(&out)
        .args(&args)
        .output()
        .unwrap();
    assert!(run.status.success(), "{args:?}: {}", String::from_utf8_lossy(&run.stderr));
    let headless = common::read_png(&out).expect("an RGBA PNG");
    let differing = headless.pixels.chunks_exact(4).zip(window.pixels.chunks_exact(4)).filter(|(a, b)| a != b).count();
    assert_eq!(differing, 0, "the headless frame is the window's: {}", umbra::reproduce::shell_line(&args));
}

#[test]
fn the_ground_checker_shows_in_the_picture_and_never_in_the_measuring_view() {
    use umbra::render::render_debug_frame;
    let gpu = gpu();
    let frames = |grid: bool| {
        let mut app = App::new(Settings::default().with(|s| s.view.ground_grid = grid)).unwrap();
        app.resize(192, 108);
        app.set_time(6.0);
        let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
        let picture = render_headless(&gpu, &mut renderer, &mut app, 192, 108).unwrap();
        (picture, render_debug_frame(&gpu, &mut renderer, &mut app, 192, 108).unwrap())
    };
    let ((checkered, measured_on), (plain, measured_off)) = (frames(true), frames(false));
    assert_eq!(measured_on, measured_off, "the measuring view is the same bit for bit");
    let darker = checkered
        .pixels
        .chunks_exact(4)
        .zip(plain.pixels.chunks_exact(4))
        .filter(|(a, b)| a[0] as i32 + 3 < b[0] as i32)
        .count();
    assert!(darker > 1000, "the checker's dark squares darken the ground: {darker} pixels");
}

#[test]
fn texel_density_is_red_for_a_coarse_map_and_blue_for_a_fine_one() {
    let gpu = gpu();
    let mean = |size: u32| {
        let settings = Settings::default().with(|s| {
            s.maps.shadow_map_size = size;
            s.view.texel_density = Some("sun".into());
        });
        let mut app = App::new(settings).unwrap();
        app.resize(480, 270);
        app.set_time(6.0);
        let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
        let image = render_headless(&gpu, &mut renderer, &mut app, 480, 270).unwrap();
        // The ground, in the lower half of the view.
        let pixels: Vec<&[u8]> = image.pixels.chunks_exact(4).skip(480 * 270 / 2).collect();
        let channel = |c: usize| pixels.iter().map(|p| p[c] as f64).sum::<f64>() / pixels.len() as f64;
        (channel(0), channel(2))
    };
    let ((coarse_red, coarse_blue), (fine_red, fine_blue)) = (mean(64), mean(2048));
    assert!(coarse_red > coarse_blue + 20.0, "64² texels each cover pixels: red {coarse_red}, blue {coarse_blue}");
    assert!(
        fine_blue > fine_red + 20.0,
        "2048² at 480x270 puts texels to spare in a pixel: red {fine_red}, blue {fine_blue}"
    );
}

#[test]
fn the_sweeps_errors_are_the_same_whether_one_thread_measures_them_or_several() {
    let gpu = gpu();
    let mut options = SweepOptions::new(true);
    // The default and planar shadows, one small view, one timed frame, and three small cases: one
    // view, frames waiting on a starved budget, and a camera cut (every case took 66 s a
    // configuration here).
    options.families = vec!["planar".into()];
    options.views = vec![VIEWS[0]];
    options.size = (160, 90);
    options.case_size = (128, 128);
    options.frames = 1;
    options.cases = Some(["peter-panning", "starved-budget", "camera-cut"].map(String::from).to_vec());
    let run = |workers| {
        let options = SweepOptions { workers, ..options.clone() };
        umbra::eval::sweep::run(&gpu, &options, |_, _, _| {}).unwrap()
    };
    let (one, two) = (run(1), run(2));
    assert_eq!(one.len(), 2);
    assert_eq!(one[0].cases.iter().filter(|c| c.is_some()).count(), 3, "only the cases asked for");
    assert!(one.iter().zip(&two).all(|(a, b)| a.config == b.config), "rows in the order of the configurations");
    for (a, b) in one.iter().zip(&two) {
        // The second configuration: measured after the first by one thread, first by its own.
        assert_eq!((&a.scene, &a.lights, &a.cases), (&b.scene, &b.lights, &b.cases), "{}", a.config.label());
    }
}
