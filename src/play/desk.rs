//! What the window keeps for the lab between frames (its numbers, the measurement, the camera's
//! name, the viewer's texture), and the egui frame drawn from it over the picture.

use super::{Measuring, Shown};
use crate::render::ShadowStats;
use crate::ui::{History, Lab, Live};
use bevy_ecs::prelude::*;

/// The lab's state between frames.
pub struct Desk {
    /// Frame and pass times.
    pub history: History,
    /// The error overlay's measurements.
    pub measuring: Measuring,
    /// The camera mode, in a few words.
    pub camera: &'static str,
    /// The shadow-map viewer's atlas as egui knows it, and the atlas generation it is bound to.
    atlas: Option<(egui::TextureId, u64)>,
}

impl Default for Desk {
    fn default() -> Self {
        Desk { history: History::default(), measuring: Measuring::default(), camera: "fly camera", atlas: None }
    }
}

impl Desk {
    /// Whether egui has anything to show: the panel, the viewer or a measurement's overlay.
    pub fn shows_anything(&self, lab: &Lab) -> bool {
        lab.panel || lab.map_viewer || (lab.overlay && self.measuring.shown().is_some())
    }

    /// Runs egui for this frame (the overlay under everything, the panel, the viewer) and paints
    /// it over each of `targets`, `size` pixels.
    pub fn paint(
        &mut self,
        shown: &mut Shown,
        world: &mut World,
        lab: &mut Lab,
        (targets, size): (&[&wgpu::TextureView], (u32, u32)),
    ) {
        let stats = world.get_resource::<ShadowStats>().cloned().unwrap_or_default();
        let adapter = shown.gpu.describe();
        let measured = self.measuring.shown();
        let live = Live {
            history: &self.history,
            stats: &stats,
            measured: measured.map(|(r, _)| r),
            status: &self.measuring.status,
            camera: self.camera,
            adapter: &adapter,
        };
        let overlay = measured.filter(|_| lab.overlay).map(|(_, t)| t.id());
        let atlas = lab.map_viewer.then(|| {
            let atlas = shown.renderer.shadow_map_atlas(&shown.gpu);
            let id = match self.atlas {
                Some((id, generation)) if generation == atlas.generation => id,
                known => shown.gui.show_texture(&shown.gpu, atlas.view, known.map(|(id, _)| id)),
            };
            self.atlas = Some((id, atlas.generation));
            (id, atlas.pages, atlas.tiles)
        });
        let painted = shown.gui.run(&shown.window, |ui| {
            if let Some(texture) = overlay {
                let whole = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
                ui.painter().image(texture, ui.ctx().content_rect(), whole, egui::Color32::WHITE);
            }
            if lab.panel {
                crate::ui::panel(ui, world, lab, &live);
            }
            if let Some((texture, pages, tiles)) = &atlas {
                crate::ui::viewer::map_viewer(ui, lab, *texture, *pages, tiles);
            }
        });
        shown.gui.paint(&shown.gpu, targets, size, painted);
    }
}
