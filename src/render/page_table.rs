//! The page tables of paged lights, as the lookups read them (`page_layer` in pages.wgsl): for
//! each level a header of [`PAGE_LEVEL_WORDS`] words (its window's origin, the pages across and
//! down it holds, where its entries start), then for a point light's cube its six faces'
//! matrices, then each level's entries: for each page its level can hold (a clipmap's whole
//! window, a spot's level, a cube's six faces), the layer its resident page is in (its slot + 1;
//! 0 where the page is not resident, or found no tile). Written once the frame's layers have
//! their tiles, so a lookup never reads a page that is not drawn.

use super::frame::FrameData;
use super::gpu_types::PAGE_LEVEL_WORDS;

/// Words of a cube's six face matrices (16 each, column by column).
const FACE_MATRIX_WORDS: usize = 6 * 16;

/// Writes every paged light's table into `data.page_words` and where it starts into the light.
pub fn write_page_tables(data: &mut FrameData) {
    let mut words = Vec::new();
    for light in data.lights.iter_mut().filter(|l| l.layer_count > 0) {
        let Some(view) = &light.light.pages else { continue };
        let start = words.len();
        light.page_word = start as u32;
        let grids: Vec<_> = view.windows.iter().map(|w| view.space.level_grid(w.level)).collect();
        let cube = view.space.faces() > 1;
        let mut next = view.windows.len() * PAGE_LEVEL_WORDS + if cube { FACE_MATRIX_WORDS } else { 0 };
        let mut firsts = Vec::with_capacity(grids.len());
        for (w, grid) in view.windows.iter().zip(&grids) {
            words.extend([w.origin.x as u32, w.origin.y as u32, grid.x as u32 | (grid.y as u32) << 16, next as u32]);
            firsts.push(start + next);
            next += (grid.x * grid.y) as usize;
        }
        if cube {
            words.extend(view.space.face_matrices().iter().flat_map(|m| m.to_cols_array().map(f32::to_bits)));
        }
        words.resize(start + next, 0);
        for (k, layer) in light.light.layers.iter().enumerate() {
            let slot = light.first_layer as usize + k;
            let Some(place) = layer.page else { continue };
            if data.draws.get(slot).is_none_or(|d| d.tile.is_none()) {
                continue;
            }
            let level = place.id.level as usize;
            let (Some(window), Some(&grid)) = (view.windows.get(level), grids.get(level)) else { continue };
            if let Some(i) = window.index_in(place.id, grid) {
                words[firsts[level] + i] = slot as u32 + 1;
            }
        }
    }
    data.page_words = words;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::{ShadowMap, ShadowMethod};
    use crate::settings::{LightMaps, Settings, SunMaps};
    use crate::shadow::{CUBE_FACE_PAGES, MARK_WORDS, PAGE_GRID, PageId, PageMarks, PageSpace, Tile};

    /// The sample scene under `settings` after a marking of its first paged light whose pages
    /// `which` picks that asked for `pages` (window indices) of level `level`, every layer given a
    /// tile but `untiled` (if any, counted from the light's first); and where that light is in the frame.
    fn paged_frame(
        settings: Settings,
        which: impl Fn(&PageSpace) -> bool,
        level: usize,
        pages: &[usize],
        untiled: Option<usize>,
    ) -> (FrameData, usize) {
        let mut app = crate::App::new(settings).unwrap();
        app.set_time(1.0);
        let paged = |l: &&crate::light::Light| l.pages.as_ref().is_some_and(|p| which(&p.space));
        let light = crate::light::light_list(&app.world).iter().find(paged).unwrap().entity;
        let pages_now = app.world.get::<ShadowMap>(light).unwrap().pages.clone().unwrap();
        let mut bits = vec![0u32; pages_now.windows.len() * MARK_WORDS];
        for i in pages {
            bits[level * MARK_WORDS + i / 32] |= 1 << (i % 32);
        }
        let marks = PageMarks {
            light: light.to_bits(),
            seq: 1,
            space: pages_now.space,
            windows: pages_now.windows,
            bias: 0.0,
            bits,
        };
        app.world.insert_resource(crate::components::MarkedPages(vec![marks]));
        app.step_held();
        let mut data = crate::render::extract(&app.world);
        let at = data.lights.iter().position(|l| l.light.entity == light).unwrap();
        let first = data.lights[at].first_layer as usize;
        for (i, d) in data.draws.iter_mut().enumerate() {
            d.tile = (Some(i) != untiled.map(|u| first + u)).then_some(Tile { page: 0, x: 0, y: 0, size: 128 });
        }
        write_page_tables(&mut data);
        (data, at)
    }

    /// Word `k` of level `level`'s header in the table starting at `start`.
    fn header(data: &FrameData, start: usize, level: usize, k: usize) -> u32 {
        data.page_words[start + PAGE_LEVEL_WORDS * level + k]
    }

    #[test]
    fn each_resident_page_with_a_tile_is_found_at_its_window_place() {
        let settings = Settings::default().with(|s| s.maps.sun_maps = SunMaps::Virtual);
        // The second page (layer 2: the coarse map is layer 0) has no tile.
        let (data, sun) = paged_frame(settings, |_| true, 3, &[10, 700], Some(2));
        let light = &data.lights[sun];
        assert_eq!(light.layer_count, 3, "the coarse map and two pages");
        assert_eq!(light.light.method, ShadowMethod::default());
        let view = light.light.pages.as_ref().unwrap();
        let start = light.page_word as usize;
        let levels = view.windows.len();
        assert_eq!(header(&data, start, 0, 0) as i32, view.windows[0].origin.x);
        assert_eq!(header(&data, start, 0, 1) as i32, view.windows[0].origin.y);
        let area = (PAGE_GRID * PAGE_GRID) as usize;
        assert_eq!(header(&data, start, 0, 2), PAGE_GRID | PAGE_GRID << 16, "a clipmap's whole window");
        assert_eq!(header(&data, start, 0, 3) as usize, PAGE_LEVEL_WORDS * levels, "no face matrices");
        let entries = start + header(&data, start, 3, 3) as usize;
        let at = |i: usize| data.page_words[entries + i];
        let placed: Vec<(usize, u32)> = (0..area).filter(|&i| at(i) > 0).map(|i| (i, at(i))).collect();
        assert_eq!(placed.len(), 1, "the page without a tile is left out: {placed:?}");
        let layer = &light.light.layers[(placed[0].1 - 1) as usize - light.first_layer as usize];
        assert_eq!(view.windows[3].index(layer.page.unwrap().id), Some(placed[0].0));
        assert_eq!(data.page_words.len(), PAGE_LEVEL_WORDS * levels + levels * area);
    }

    #[test]
    fn a_cubes_table_holds_its_six_faces_of_each_level_and_no_more() {
        let settings = Settings::default().with(|s| s.maps.light_maps = LightMaps::Virtual);
        // Level 0's page 20 across, 3 down: on face 1 (columns 16 to 31).
        let cube = |s: &PageSpace| s.faces() == 6;
        let (data, point) = paged_frame(settings, cube, 0, &[3 * PAGE_GRID as usize + 20], None);
        let light = &data.lights[point];
        let view = light.light.pages.as_ref().unwrap();
        let (start, levels) = (light.page_word as usize, view.windows.len());
        let across = 3 * CUBE_FACE_PAGES;
        assert_eq!(header(&data, start, 0, 2), across | (2 * CUBE_FACE_PAGES) << 16, "six faces, three across");
        let first = header(&data, start, 0, 3) as usize;
        assert_eq!(first, PAGE_LEVEL_WORDS * levels + FACE_MATRIX_WORDS, "the face matrices come before the entries");
        let slot = data.page_words[start + first + 3 * across as usize + 20];
        assert!(slot > 0, "the marked page is found");
        let layer = &light.light.layers[(slot - 1) as usize - light.first_layer as usize];
        assert_eq!(layer.page.unwrap().id, PageId { level: 0, x: 20, y: 3 });
        // Each level holds its six faces' pages and the next starts after them.
        let mut cells = 0;
        for level in 0..levels {
            let side = (CUBE_FACE_PAGES >> level).max(1);
            assert_eq!(header(&data, start, level, 3) as usize, first + cells, "level {level}");
            cells += 6 * (side * side) as usize;
        }
        assert!(cells * 8 < levels * (PAGE_GRID * PAGE_GRID) as usize, "under an eighth of a whole window per level");
    }
}
