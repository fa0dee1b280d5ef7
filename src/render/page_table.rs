//! The page tables of paged lights, as the lookups read them (`page_layer` in pages.wgsl): for
//! each level, its window's origin, then for each page of the window the layer its resident page
//! is in (its slot + 1; 0 where the page is not resident, or found no tile), then for a point
//! light's cube its six faces' matrices. Written once the frame's layers have their tiles, so a
//! lookup never reads a page that is not drawn.

use super::frame::FrameData;
use crate::shadow::PAGE_GRID;

/// Writes every paged light's table into `data.page_words` and where it starts into the light.
pub fn write_page_tables(data: &mut FrameData) {
    let mut words = Vec::new();
    let area = (PAGE_GRID * PAGE_GRID) as usize;
    for light in data.lights.iter_mut().filter(|l| l.layer_count > 0) {
        let Some(view) = &light.light.pages else { continue };
        light.page_word = words.len() as u32;
        words.extend(view.windows.iter().flat_map(|w| [w.origin.x as u32, w.origin.y as u32]));
        let entries = words.len();
        words.resize(entries + view.windows.len() * area, 0);
        for (k, layer) in light.light.layers.iter().enumerate() {
            let slot = light.first_layer as usize + k;
            let Some(place) = layer.page else { continue };
            if data.draws.get(slot).is_none_or(|d| d.tile.is_none()) {
                continue;
            }
            let level = place.id.level as usize;
            if let Some(i) = view.windows.get(level).and_then(|w| w.index(place.id)) {
                words[entries + level * area + i] = slot as u32 + 1;
            }
        }
        if view.space.faces() > 1 {
            words.extend(view.space.face_matrices().iter().flat_map(|m| m.to_cols_array().map(f32::to_bits)));
        }
    }
    data.page_words = words;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::{ShadowMap, ShadowMethod};
    use crate::settings::{Settings, SunMaps};
    use crate::shadow::{MARK_WORDS, PageMarks, Tile};

    /// The sample scene with virtual sun maps, after a marking that asked for `pages` (window
    /// indices) of level `level`.
    fn paged_frame(level: usize, pages: &[usize]) -> FrameData {
        let settings = Settings::default().with(|s| s.maps.sun_maps = SunMaps::Virtual);
        let mut app = crate::App::new(settings).unwrap();
        app.set_time(1.0);
        let sun = crate::light::light_list(&app.world)[0].entity;
        let pages_now = app.world.get::<ShadowMap>(sun).unwrap().pages.clone().unwrap();
        let mut bits = vec![0u32; pages_now.windows.len() * MARK_WORDS];
        for i in pages {
            bits[level * MARK_WORDS + i / 32] |= 1 << (i % 32);
        }
        let marks = PageMarks {
            light: sun.to_bits(),
            seq: 1,
            space: pages_now.space,
            windows: pages_now.windows,
            bias: 0.0,
            bits,
        };
        app.world.insert_resource(crate::components::MarkedPages(vec![marks]));
        app.step_held();
        crate::render::extract(&app.world)
    }

    #[test]
    fn each_resident_page_with_a_tile_is_found_at_its_window_place() {
        let mut data = paged_frame(3, &[10, 700]);
        let sun = data.lights.iter().position(|l| l.light.pages.is_some()).unwrap();
        assert_eq!(data.lights[sun].layer_count, 3, "the coarse map and two pages");
        assert_eq!(data.lights[sun].light.method, ShadowMethod::default());
        // Give every layer a tile but the second page's.
        let first = data.lights[sun].first_layer as usize;
        for (i, d) in data.draws.iter_mut().enumerate() {
            d.tile = (i != first + 2).then_some(Tile { page: 0, x: 0, y: 0, size: 128 });
        }
        write_page_tables(&mut data);
        let light = &data.lights[sun];
        let view = light.light.pages.as_ref().unwrap();
        let start = light.page_word as usize;
        let levels = view.windows.len();
        assert_eq!(data.page_words[start] as i32, view.windows[0].origin.x);
        assert_eq!(data.page_words[start + 1] as i32, view.windows[0].origin.y);
        let entries = start + 2 * levels;
        let area = (PAGE_GRID * PAGE_GRID) as usize;
        let at = |i: usize| data.page_words[entries + 3 * area + i];
        let placed: Vec<(usize, u32)> = (0..area).filter(|&i| at(i) > 0).map(|i| (i, at(i))).collect();
        assert_eq!(placed.len(), 1, "the page without a tile is left out: {placed:?}");
        let layer = &light.light.layers[(placed[0].1 - 1) as usize - first];
        assert_eq!(view.windows[3].index(layer.page.unwrap().id), Some(placed[0].0));
        assert_eq!(data.page_words.len(), 2 * levels + levels * area);
    }
}
