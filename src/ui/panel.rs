//! The panel: live numbers, every shadow setting, each light's own method, bias, size and
//! shadow, the error overlay's controls and numbers, and the debug views. It writes the
//! settings' groups ([`ShadowSettings`] and the others) and the lights' components, and only where a value really changed, so
//! an untouched panel dirties nothing.

use super::History;
use crate::components::{ContactShadows, ShadowBias, ShadowMap, ShadowMethod};
use crate::eval::live::LiveReport;
use crate::eval::metrics::Tally;
use crate::light::{Kind, Light, light_list};
use crate::render::ShadowStats;
use crate::settings::{
    CascadeSettings, CasterCulling, LightMaps, MAX_BIAS_SCALE, MapSettings, MomentBits, MomentResolve, MomentSource,
    SettingsGroup, ShadowDepth, ShadowFaces, ShadowSettings, SunMaps, ViewSettings,
};
use crate::shadow::FitMode;
use bevy_ecs::prelude::*;
use egui::{CollapsingHeader, Color32, ComboBox, Slider, Ui};

/// The window's own state beside the settings: what is shown, and what was asked for this frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Lab {
    /// The panel is open.
    pub panel: bool,
    /// The scene's clock is held (the animation stops; the camera still moves).
    pub hold: bool,
    /// The last measurement's error picture is laid over the view.
    pub overlay: bool,
    /// Measure again whenever the view has been still for [`STILL_FOR`] seconds.
    pub auto_measure: bool,
    /// The measured frame is the window's size divided by this (1, 2 or 4).
    pub measure_scale: u32,
    /// The shadow-map viewer is open.
    pub map_viewer: bool,
    /// What the user asked for this frame; the window does it and clears it.
    pub asked: Asked,
    /// The command line that draws the view headless, once asked for.
    pub command: Option<String>,
}

/// Seconds the view must stay still before an automatic measurement.
pub const STILL_FOR: f32 = 0.5;

impl Default for Lab {
    fn default() -> Self {
        Lab {
            panel: false,
            hold: false,
            overlay: true,
            auto_measure: false,
            measure_scale: 2,
            map_viewer: false,
            asked: Asked::default(),
            command: None,
        }
    }
}

/// One-off requests from the panel or the keys.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Asked {
    /// Measure the view on screen now.
    pub measure: bool,
    /// Save a screenshot of the window.
    pub screenshot: bool,
    /// Switch to the next camera.
    pub camera: bool,
}

/// What the panel shows but does not change.
pub struct Live<'a> {
    /// Frame and pass times.
    pub history: &'a History,
    /// The last frame's shadow layers, drawn and kept, per light.
    pub stats: &'a ShadowStats,
    /// The measurement laid over the view, if any.
    pub measured: Option<&'a LiveReport>,
    /// What the measuring is doing, in a few words.
    pub status: &'a str,
    /// The camera mode, in a few words.
    pub camera: &'a str,
    /// The adapter, in a few words.
    pub adapter: &'a str,
}

/// Draws the panel on the left of the window and applies what the user changed to `world`.
pub fn panel(ui: &mut Ui, world: &mut World, lab: &mut Lab, live: &Live<'_>) {
    egui::Panel::left("umbra panel").default_size(330.0).show(ui, |ui| {
        egui::ScrollArea::vertical().show(ui, |ui| {
            live_numbers(ui, live);
            section(ui, "Error against the ray-traced truth", true, |ui| overlay_section(ui, lab, live));
            // Edited in copies, each put back only when it changed and is valid.
            let mut shadow = *world.resource::<ShadowSettings>();
            let mut maps = *world.resource::<MapSettings>();
            let mut cascade = *world.resource::<CascadeSettings>();
            let mut view = world.resource::<ViewSettings>().clone();
            let names: Vec<String> = light_list(world).iter().map(|l| l.label.to_string()).collect();
            section(ui, "Shadow budgets", true, |ui| budget_settings(ui, &mut maps, world, live.stats));
            section(ui, "Shadows", false, |ui| shadow_settings(ui, &mut shadow, &mut maps));
            section(ui, "The sun's maps", false, |ui| {
                sun_maps(ui, &mut maps, &shadow);
                cascade_settings(ui, &mut cascade, &mut view);
            });
            section(ui, "Shading and views", false, |ui| {
                view_settings(ui, &mut view, lab, live.camera);
                texel_density(ui, &mut view, &names);
            });
            // An edit the group refuses is not put in force; the slider shows it until changed.
            let _ = (shadow.put(world), maps.put(world), cascade.put(world), view.put(world));
            section(ui, "Lights", true, |ui| lights(ui, world));
            section(ui, "This view, headless", false, |ui| reproduce(ui, world, lab));
        });
    });
}

fn section(ui: &mut Ui, title: &str, open: bool, body: impl FnOnce(&mut Ui)) {
    CollapsingHeader::new(title).default_open(open).show(ui, body);
}

fn live_numbers(ui: &mut Ui, live: &Live<'_>) {
    let h = live.history;
    let gpu = |i: usize| History::median(h.passes.iter().map(|p| if i == 0 { p.0 } else { p.1 }), 30);
    ui.label(format!("{:.0} fps · {}", h.fps(), live.adapter));
    match (gpu(0), gpu(1)) {
        (Some(shadow), Some(main)) => {
            ui.label(format!("GPU: shadow pass {shadow:.2} ms · main pass {main:.2} ms (median of 30)"));
        }
        _ => {
            ui.label("GPU pass times: no timestamps on this adapter");
        }
    }
    graph(ui, h);
    ui.label(format!("shadow layers drawn / kept this frame: {}", live.stats));
    ui.horizontal_wrapped(|ui| {
        // The lights whose maps were drawn or wait: a scene of a thousand lamps lists a few.
        for l in live.stats.lights.iter().filter(|l| l.drawn > 0 || l.stale > 0).take(LISTED_LIGHTS) {
            let colour = if l.stale > 0 { Color32::from_rgb(240, 80, 80) } else { Color32::from_rgb(255, 170, 60) };
            let waits = if l.stale > 0 { format!(", {} stale", l.stale) } else { String::new() };
            ui.colored_label(colour, format!("{} {}/{}{waits}", l.light, l.drawn, l.kept));
        }
    });
    ui.separator();
}

/// Lights the live numbers name one by one.
const LISTED_LIGHTS: usize = 12;

/// The shadow memory and the update budget, with what the atlas holds and what waits.
fn budget_settings(ui: &mut Ui, s: &mut MapSettings, world: &World, stats: &ShadowStats) {
    let memory = crate::settings::MIN_SHADOW_MEMORY..=4096;
    ui.add(slide(&mut s.shadow_memory, memory).logarithmic(true).text("shadow memory (MiB)"));
    if let Some(atlas) = world.get_resource::<crate::systems::ShadowAtlas>() {
        let (page, pages, mib) = (atlas.shape.page, atlas.shape.pages, atlas.bytes() >> 20);
        ui.label(format!("atlas: {pages} pages of {page}² ({mib} MiB, {} bytes a texel)", atlas.texel_bytes));
    }
    let updates = slide(&mut s.shadow_updates, 0..=MAX_PANEL_UPDATES)
        .logarithmic(true)
        .smallest_positive(f64::from(crate::settings::MIN_SHADOW_UPDATES))
        .custom_formatter(|v, _| if v < 1.0 { "no limit".into() } else { texels(v as u64) })
        .text("texels redrawn a frame");
    ui.add(updates);
    ui.label(format!("drawn this frame: {} texels", texels(stats.texels)));
    if let Some(pages) = page_line(world, stats) {
        ui.label(pages);
    }
    if stats.stale() > 0 {
        let (layers, lights, oldest) = (stats.stale(), stats.stale_lights(), stats.waited());
        let line = format!("waiting: {layers} layers of {lights} lights, the oldest {oldest} frames");
        ui.colored_label(Color32::from_rgb(240, 80, 80), line);
    }
}

/// The most the panel's update slider offers: sixteen 2048² maps a frame.
const MAX_PANEL_UPDATES: u32 = 64 << 20;

/// `n` texels as "4M", "256K" or "900".
fn texels(n: u64) -> String {
    match n {
        n if n >= 1 << 20 => format!("{:.1}M", n as f64 / f64::from(1 << 20)),
        n if n >= 1 << 10 => format!("{:.0}K", n as f64 / 1024.0),
        n => n.to_string(),
    }
}

/// The frame time (grey), and the shadow (orange) and main (cyan) pass times, oldest on the left.
fn graph(ui: &mut Ui, h: &History) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(ui.available_width(), 56.0), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, Color32::from_black_alpha(90));
    let top = h.frames.iter().copied().chain(h.passes.iter().map(|p| p.0 + p.1)).fold(1.0f32, f32::max);
    let line = |values: Vec<f32>, colour: Color32| {
        let n = super::history::KEPT as f32;
        let points = values
            .iter()
            .enumerate()
            .map(|(i, v)| {
                let x = rect.right() - (values.len() - i) as f32 / n * rect.width();
                egui::pos2(x, rect.bottom() - v / top * rect.height())
            })
            .collect();
        painter.line(points, egui::Stroke::new(1.5, colour));
    };
    line(h.frames.iter().copied().collect(), Color32::GRAY);
    line(h.passes.iter().map(|p| p.0).collect(), Color32::from_rgb(255, 150, 40));
    line(h.passes.iter().map(|p| p.1).collect(), Color32::from_rgb(60, 200, 230));
    painter.text(
        rect.left_top(),
        egui::Align2::LEFT_TOP,
        format!("{top:.0} ms"),
        egui::FontId::monospace(10.0),
        Color32::WHITE,
    );
}

/// A slider that keeps a value set outside its range (from the command line, say) until it is
/// dragged: showing the panel must change nothing.
fn slide<'a, N: egui::emath::Numeric>(value: &'a mut N, range: std::ops::RangeInclusive<N>) -> Slider<'a> {
    Slider::new(value, range).clamping(egui::SliderClamping::Edits)
}

fn choice<T: Copy + PartialEq>(ui: &mut Ui, label: &str, value: &mut T, all: &[T], name: fn(T) -> &'static str) {
    ComboBox::from_label(label).selected_text(name(*value)).show_ui(ui, |ui| {
        for c in all {
            ui.selectable_value(value, *c, name(*c));
        }
    });
}

/// Shadow-map sizes the panel offers.
pub const MAP_SIZES: [u32; 6] = [256, 512, 1024, 2048, 4096, 8192];

fn shadow_settings(ui: &mut Ui, s: &mut ShadowSettings, maps: &mut MapSettings) {
    ui.checkbox(&mut s.enabled, "shadows");
    ui.checkbox(&mut maps.reuse_shadow_maps, "keep clean lights' maps (the cache)");
    ui.checkbox(&mut maps.static_cache, "casters at rest kept in static maps");
    ui.checkbox(&mut maps.instancing, "instanced casters (one call per mesh and layer)");
    choice(ui, "method (lights without their own)", &mut s.method, ShadowMethod::ALL, ShadowMethod::name);
    ComboBox::from_label("map size").selected_text(format!("{}²", maps.shadow_map_size)).show_ui(ui, |ui| {
        for size in MAP_SIZES {
            ui.selectable_value(&mut maps.shadow_map_size, size, format!("{size}²"));
        }
    });
    choice(ui, "depth format", &mut maps.shadow_depth, ShadowDepth::ALL, ShadowDepth::name);
    ui.add(slide(&mut s.shadow_strength, 0.0..=1.0).text("shadow strength"));
    ui.label("bias of lights without their own (texels):");
    bias_sliders(ui, &mut s.depth_bias, &mut s.slope_bias, &mut s.normal_bias, &mut s.bias_scale);
    ui.checkbox(&mut s.receiver_plane, "receiver-plane bias (filters)");
    ui.checkbox(&mut s.planar_ground, "planar shadows on the ground");
    choice(ui, "casters culled to", &mut maps.caster_culling, CasterCulling::ALL, CasterCulling::name);
    choice(ui, "caster faces", &mut maps.shadow_faces, ShadowFaces::ALL, ShadowFaces::name);
    ui.add(slide(&mut maps.moment_blur, 0..=crate::settings::MAX_MOMENT_BLUR).text("moment blur (texels)"));
    ui.add(slide(&mut s.light_bleeding, 0.0..=0.9).text("light-bleeding cut"));
    choice(ui, "moment bits", &mut maps.moment_bits, MomentBits::ALL, MomentBits::name);
    choice(ui, "moments from", &mut maps.moments_from, MomentSource::ALL, MomentSource::name);
    choice(ui, "moments resolved by", &mut maps.moment_resolve, MomentResolve::ALL, MomentResolve::name);
    let samples = &mut maps.moment_samples;
    ComboBox::from_label("moment samples (MSAA)").selected_text(samples.to_string()).show_ui(ui, |ui| {
        for n in crate::settings::MOMENT_SAMPLES {
            ui.selectable_value(samples, n, n.to_string());
        }
    });
    ui.checkbox(&mut s.contact_shadows, "contact shadows, lights without their own (J)");
    ui.add(slide(&mut s.contact_steps, 1..=crate::settings::MAX_CONTACT_STEPS).text("contact steps"));
    ui.add(slide(&mut s.contact_length, 0.0..=2.0).text("contact length (m)"));
    ui.add(slide(&mut s.contact_thickness, 0.01..=1.0).text("contact thickness (m)"));
}

fn bias_sliders(ui: &mut Ui, constant: &mut f32, slope: &mut f32, normal: &mut f32, scale: &mut f32) {
    ui.add(slide(constant, 0.0..=8.0).text("constant"));
    ui.add(slide(slope, 0.0..=8.0).text("slope"));
    ui.add(slide(normal, 0.0..=8.0).text("normal"));
    ui.add(slide(scale, 0.0..=MAX_BIAS_SCALE).text("scale (share of distance)"));
}

/// Cascades or a virtual map for the sun, atlas tiles or virtual maps for the other lights, and the
/// virtual maps' bias and pool.
fn sun_maps(ui: &mut Ui, s: &mut MapSettings, shadow: &ShadowSettings) {
    choice(ui, "sun's maps", &mut s.sun_maps, SunMaps::ALL, SunMaps::name);
    choice(ui, "spot and point lights' maps", &mut s.light_maps, LightMaps::ALL, LightMaps::name);
    if s.paged() {
        if !shadow.method.pages() {
            let line =
                format!("{} reads no depth pages: every light keeps its cascades or tiles", shadow.method.name());
            ui.colored_label(Color32::from_rgb(240, 80, 80), line);
        }
        let bias = crate::settings::MAX_PAGE_BIAS;
        ui.add(slide(&mut s.page_bias, -bias..=bias).text("page bias (octaves coarser)"));
        let most = (s.shadow_memory / 2).max(1);
        ui.add(slide(&mut s.page_memory, 1..=most).logarithmic(true).text("page pool (MiB)"));
    }
}

fn cascade_settings(ui: &mut Ui, s: &mut CascadeSettings, view: &mut ViewSettings) {
    ui.add(slide(&mut s.cascades, 1..=crate::shadow::MAX_CASCADES as u32).text("cascades"));
    ui.add(slide(&mut s.split_lambda, 0.0..=1.0).text("split λ (0 uniform, 1 log)"));
    choice(ui, "fit", &mut s.fit_mode, FitMode::ALL, FitMode::name);
    ui.add(slide(&mut s.cascade_blend, 0.0..=0.5).text("blend band"));
    ui.add(slide(&mut s.shadow_distance, 5.0..=200.0).logarithmic(true).text("shadow distance (m)"));
    ui.checkbox(&mut view.cascade_debug, "tint each cascade");
}

fn view_settings(ui: &mut Ui, s: &mut ViewSettings, lab: &mut Lab, camera: &str) {
    let mut toon = s.toon_bands > 0;
    ui.horizontal(|ui| {
        ui.radio_value(&mut toon, false, "Phong");
        ui.radio_value(&mut toon, true, "toon");
    });
    s.toon_bands = match (toon, s.toon_bands) {
        (false, _) => 0,
        (true, 0) => crate::settings::DEFAULT_TOON_BANDS,
        (true, n) => n,
    };
    if toon {
        ui.add(slide(&mut s.toon_bands, 2..=crate::settings::MAX_TOON_BANDS).text("bands"));
    }
    ui.checkbox(&mut s.ground_grid, "checker on the ground");
    ui.checkbox(&mut s.light_volumes, "light volumes (L)");
    ui.checkbox(&mut lab.hold, "hold the scene's clock (H)");
    ui.horizontal(|ui| {
        ui.label(format!("camera: {camera}"));
        lab.asked.camera |= ui.button("next (O)").clicked();
    });
    ui.checkbox(&mut lab.map_viewer, "shadow-map viewer (V)");
    lab.asked.screenshot |= ui.button("save a screenshot (F12)").clicked();
}

/// The texel-density view: which light's, or the shading.
fn texel_density(ui: &mut Ui, s: &mut ViewSettings, lights: &[String]) {
    let shown = s.texel_density.clone().unwrap_or_else(|| "off (the shading)".into());
    ComboBox::from_label("texel density of (B)").selected_text(shown).show_ui(ui, |ui| {
        ui.selectable_value(&mut s.texel_density, None, "off (the shading)");
        for name in lights {
            ui.selectable_value(&mut s.texel_density, Some(name.clone()), name);
        }
    });
    if s.texel_density.is_some() {
        ui.horizontal(|ui| {
            ui.colored_label(Color32::from_rgb(230, 40, 25), "■ a texel over pixels");
            ui.colored_label(Color32::from_rgb(50, 200, 50), "■ one a pixel");
            ui.colored_label(Color32::from_rgb(40, 90, 240), "■ many a pixel");
        });
    }
}

/// Each light: its shadow on or off, its own method, bias and size (or the settings').
fn lights(ui: &mut Ui, world: &mut World) {
    let settings = *world.resource::<ShadowSettings>();
    for light in light_list(world) {
        ui.push_id(light.entity, |ui| {
            CollapsingHeader::new(light.label.to_string()).show(ui, |ui| one_light(ui, world, &light, &settings));
        });
    }
}

fn one_light(ui: &mut Ui, world: &mut World, light: &Light, settings: &ShadowSettings) {
    let e = light.entity;
    let mut shadowed = light.shadowed;
    ui.checkbox(&mut shadowed, "casts a shadow");
    if shadowed != light.shadowed {
        if shadowed {
            world.entity_mut(e).insert(ShadowMap::default());
        } else {
            world.entity_mut(e).remove::<ShadowMap>();
        }
    }
    let own = world.get::<ShadowMethod>(e).copied();
    let mut method = own;
    let default = format!("the settings' ({})", settings.method.name());
    ComboBox::from_label("method").selected_text(method.map_or(default.clone(), |m| m.name().to_string())).show_ui(
        ui,
        |ui| {
            ui.selectable_value(&mut method, None, default);
            for m in ShadowMethod::ALL {
                ui.selectable_value(&mut method, Some(*m), m.name());
            }
        },
    );
    if method != own {
        match method {
            Some(m) => world.entity_mut(e).insert(m),
            None => world.entity_mut(e).remove::<ShadowMethod>(),
        };
    }
    let own = world.get::<ShadowBias>(e).copied();
    let mut bias = own.unwrap_or_else(|| settings.shadow_bias());
    ui.label(if own.is_some() { "its own bias (texels):" } else { "the settings' bias (texels):" });
    bias_sliders(ui, &mut bias.constant, &mut bias.slope, &mut bias.normal, &mut bias.scale);
    ui.checkbox(&mut bias.receiver_plane, "receiver-plane bias");
    if Some(bias) != own && bias != settings.shadow_bias() {
        world.entity_mut(e).insert(bias);
    }
    if own.is_some() && ui.button("use the settings' bias").clicked() {
        world.entity_mut(e).remove::<ShadowBias>();
    }
    let mut contact = light.contact;
    ui.checkbox(&mut contact, "contact shadows");
    if contact != light.contact {
        world.entity_mut(e).insert(ContactShadows(contact));
    }
    light_size(ui, world, light);
}

/// The light's size, which PCSS and the soft truth take, in its kind's own units.
fn light_size(ui: &mut Ui, world: &mut World, light: &Light) {
    let size = light.kind.size_control();
    let mut value = size.value;
    ui.add(slide(&mut value, 0.0..=size.max).text(size.label));
    if value != size.value {
        light.kind.set_size(world, light.entity, value);
    }
}

/// What the virtual maps hold and did this frame, every paged light's together: pages resident in
/// the pool they share (and the share of the pool), drawn and left stale this frame, and those the last
/// marking asked for that have no slot (missing) or wait their turn to come in; none where no
/// light is paged.
pub fn page_line(world: &World, stats: &ShadowStats) -> Option<String> {
    let mut maps = world.try_query::<&crate::components::ShadowMap>()?;
    let pools: Vec<&crate::components::VirtualPages> = maps.iter(world).filter_map(|m| m.pages.as_ref()).collect();
    if pools.is_empty() {
        return None;
    }
    let sum = |f: &dyn Fn(&crate::components::VirtualPages) -> u32| pools.iter().map(|p| f(p)).sum::<u32>();
    let shared = world.get_resource::<crate::components::SharedPool>()?;
    let (resident, capacity) = (shared.pages.len(), shared.pages.capacity().max(1));
    let missing = sum(&|p| p.marked.residency.missing);
    let waiting = sum(&|p| p.marked.residency.waiting);
    let o = shared.pressure.octaves;
    let pressure = match o {
        0.0 => String::new(),
        o if o > 0.0 => format!(", every light's levels {o} octaves coarser (the pool is short)"),
        o => format!(", every light's levels {} octaves finer (the pool has room)", -o),
    };
    Some(format!(
        "pages: {resident} resident ({:.0} % of the pool), {} drawn, {missing} missing, {waiting} waiting, {} stale{pressure}",
        100.0 * resident as f64 / f64::from(capacity),
        stats.pages.drawn,
        stats.pages.stale
    ))
}

/// The command line that renders what the window shows, for a bug report or a picture.
fn reproduce(ui: &mut Ui, world: &mut World, lab: &mut Lab) {
    if ui.button("write the command line").clicked() {
        let line = format!("umbra render {}", crate::reproduce::shell_line(&crate::reproduce::command_line(world)));
        println!("{line}");
        lab.command = Some(line);
    }
    if let Some(line) = &lab.command {
        ui.add(egui::Label::new(egui::RichText::new(line).monospace()).selectable(true));
    }
}

fn overlay_section(ui: &mut Ui, lab: &mut Lab, live: &Live<'_>) {
    ui.horizontal(|ui| {
        lab.asked.measure |= ui.button("measure now (M)").clicked();
        ui.checkbox(&mut lab.auto_measure, "when still (N)");
        ui.checkbox(&mut lab.overlay, "show (X)");
    });
    ComboBox::from_label("measured size").selected_text(format!("1/{} of the window", lab.measure_scale)).show_ui(
        ui,
        |ui| {
            for k in [1, 2, 4] {
                ui.selectable_value(&mut lab.measure_scale, k, format!("1/{k} of the window"));
            }
        },
    );
    ui.label(live.status);
    ui.horizontal(|ui| {
        ui.colored_label(Color32::from_rgb(255, 60, 40), "■ false shadow");
        ui.colored_label(Color32::from_rgb(60, 110, 255), "■ false lit");
        ui.label("faint: off the soft truth");
    });
    let Some(report) = live.measured else { return };
    egui::Grid::new("errors").striped(true).show(ui, |ui| {
        for h in ["light", "wrong", "at edges", "mean error"] {
            ui.strong(h);
        }
        ui.end_row();
        let row = |ui: &mut Ui, name: &str, all: &Tally, edge: &Tally| {
            ui.label(name);
            ui.label(format!("{:.3} %", 100.0 * all.misclassified()));
            ui.label(format!("{:.2} %", 100.0 * edge.misclassified()));
            ui.label(format!("{:.4}", all.mae_soft()));
            ui.end_row();
        };
        for (name, r) in &report.lights {
            row(ui, name, &r.all, &r.edge);
        }
        let all = report.all();
        row(ui, "every light", &all.all, &all.edge);
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::SpotLight;
    use crate::settings::Settings;

    fn run(world: &mut World, lab: &mut Lab) {
        let ctx = egui::Context::default();
        let (history, stats) = (History::default(), ShadowStats::default());
        let live =
            Live { history: &history, stats: &stats, measured: None, status: "", camera: "fly", adapter: "test" };
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1280.0, 720.0))),
            ..Default::default()
        };
        // Two passes: egui lays out on the first and settles on the second.
        for _ in 0..2 {
            ctx.run_ui(input.clone(), |ui| panel(ui, world, lab, &live)).drop_without_applying_deltas();
        }
    }

    fn dirty_layers(world: &mut World) -> usize {
        world.query::<&ShadowMap>().iter(world).map(|m| m.layers.iter().filter(|l| l.dirty).count()).sum()
    }

    #[test]
    fn an_untouched_panel_dirties_nothing() {
        let mut app = crate::App::new(Settings::default()).unwrap();
        // Values beyond the sliders' ranges, as the command line may set them.
        app.world.resource_mut::<crate::settings::CascadeSettings>().shadow_distance = 400.0;
        let spot = light_list(&app.world)[1].entity;
        app.world.entity_mut(spot).insert(ShadowBias { constant: 20.0, ..Default::default() });
        app.world.get_mut::<SpotLight>(spot).unwrap().radius = 3.0;
        app.set_time(1.0);
        app.set_time(1.0);
        assert_eq!(dirty_layers(&mut app.world), 0, "a still scene is clean");
        let before = app.settings();
        let mut lab = Lab { panel: true, ..Default::default() };
        run(&mut app.world, &mut lab);
        assert_eq!(app.settings(), before);
        assert_eq!(lab, Lab { panel: true, ..Default::default() });
        // The sections the panel opens only on a click, drawn open.
        let ctx = egui::Context::default();
        let settings = app.settings();
        for light in light_list(&app.world) {
            ctx.run_ui(egui::RawInput::default(), |ui| one_light(ui, &mut app.world, &light, &settings.shadow))
                .drop_without_applying_deltas();
        }
        let mut edited = settings.clone();
        ctx.run_ui(egui::RawInput::default(), |ui| {
            budget_settings(ui, &mut edited.maps, &app.world, &ShadowStats::default());
            shadow_settings(ui, &mut edited.shadow, &mut edited.maps);
            cascade_settings(ui, &mut edited.cascade, &mut edited.view);
            view_settings(ui, &mut edited.view, &mut lab, "fly");
        })
        .drop_without_applying_deltas();
        assert_eq!(edited, settings);
        app.set_time(1.0);
        assert_eq!(dirty_layers(&mut app.world), 0, "the panel wrote nothing that a light's maps depend on");
    }
}
