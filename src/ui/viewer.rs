//! The shadow-map viewer (key V): the atlas as the last frame used it, each tile outlined and
//! named by its light, a virtual map's pages by their level.

use super::Lab;
use crate::render::AtlasTile;
use egui::{Color32, Ui};

/// The shadow-map viewer: the atlas as the last frame used it, page by page, each tile outlined
/// and named by its light where there is room (and under the pointer wherever it is).
pub fn map_viewer(ui: &mut Ui, lab: &mut Lab, atlas: egui::TextureId, pages: u32, tiles: &[AtlasTile]) {
    use crate::render::map_view::atlas_size;
    let mut open = lab.map_viewer;
    let right = ui.ctx().content_rect().right();
    let window = egui::Window::new("shadow atlas (V)").open(&mut open).default_width(520.0);
    window.default_pos(egui::pos2(right - 540.0, 10.0)).show(ui.ctx(), |ui| {
        ui.label(
            "each tile a layer where the atlas keeps it (a virtual map's pages by level, L0 the finest); depth as \
             distance from the light, black near, white far",
        );
        let (w, h) = atlas_size(pages);
        let width = ui.available_width().min(w as f32);
        let size = egui::vec2(width, width * h as f32 / w as f32);
        let response = ui.image(egui::load::SizedTexture::new(atlas, size));
        let scale = width / w as f32;
        let orange = Color32::from_rgb(255, 120, 40);
        let mut count = std::collections::HashMap::new();
        let mut hovered = None;
        for &AtlasTile { light, rect: [x, y, side], texels, level } in tiles {
            let n = *count.entry(light).and_modify(|n| *n += 1).or_insert(1);
            // A page of a virtual map is named by its level; its light's other layers by number.
            let (n, colour) = match level {
                Some(level) => (format!("L{level}"), level_colour(level)),
                None => (n.to_string(), orange),
            };
            let rect = egui::Rect::from_min_size(
                response.rect.min + egui::vec2(x, y) * scale,
                egui::Vec2::splat(side * scale),
            );
            ui.painter().rect_stroke(
                rect,
                0.0,
                egui::Stroke::new(1.0, colour.gamma_multiply(0.6)),
                egui::StrokeKind::Inside,
            );
            let text = format!("{light} · {n} ({texels}²)");
            // The whole name where it fits in the tile, the light and layer where they do, else
            // nothing (the pointer names it).
            let fits = [text.clone(), format!("{light}·{n}")].into_iter().find_map(|t| {
                let galley = ui.painter().layout_no_wrap(t, egui::FontId::proportional(11.0), colour);
                (galley.size().x + 6.0 <= rect.width() && galley.size().y + 4.0 <= rect.height()).then_some(galley)
            });
            if let Some(galley) = fits {
                ui.painter().galley(rect.min + egui::vec2(3.0, 2.0), galley, colour);
            }
            if response.hover_pos().is_some_and(|p| rect.contains(p)) {
                hovered = Some(text);
            }
        }
        ui.label(hovered.unwrap_or_else(|| format!("{} tiles; point at one to name it", tiles.len())));
    });
    lab.map_viewer = open;
}

/// The outline of a virtual map's page of `level` in the viewer: a hue a level, round again after
/// eight, so neighbouring levels differ.
fn level_colour(level: u32) -> Color32 {
    const HUES: [(u8, u8, u8); 8] = [
        (255, 90, 90),
        (255, 200, 60),
        (120, 230, 80),
        (60, 210, 230),
        (90, 130, 255),
        (200, 100, 255),
        (255, 110, 200),
        (220, 220, 220),
    ];
    let (r, g, b) = HUES[level as usize % HUES.len()];
    Color32::from_rgb(r, g, b)
}
