//! Virtual shadow maps in the update: a paged light's clipmap round the camera, its pool given
//! the pages the last marking asked for, new contents for the pages a caster moved through, and
//! its layers: the coarse map, then one layer a resident page (named by its slot, so it keeps its
//! tile and what was drawn in it for as long as it stays).

use super::casters::CasterChanges;
use super::layers::{fitted_layers, next_version};
use crate::components::{MarkedPages, PagePlace, PageUpdate, ShadowLayer, ShadowMap, VirtualPages};
use crate::light::PagedFit;
use crate::settings::MapSettings;
use crate::shadow::{Aabb, PAGE_TILE, PageId, PagePool, PageSpace, Pressure, depth_terms};
use bevy_ecs::prelude::Entity;

/// Side of a paged light's coarse map, in texels: what every pixel whose page is not there yet
/// reads (never larger than the settings' map size).
pub const COARSE_SIDE: u32 = 1024;

/// The coarse map's side with `settings`.
#[must_use]
pub fn coarse_side(settings: &MapSettings) -> u32 {
    COARSE_SIDE.min(settings.shadow_map_size)
}

/// Slots of a paged light's pool: the settings' page memory in pages at `texel_bytes` a texel,
/// fewer where the memory budget squeezed its tiles below [`PAGE_TILE`] (`resolution`).
#[must_use]
pub fn pool_capacity(settings: &MapSettings, texel_bytes: u32, resolution: u32) -> u32 {
    let page_bytes = u64::from(PAGE_TILE * PAGE_TILE) * u64::from(texel_bytes.max(1));
    let pages = (u64::from(settings.page_memory) << 20) / page_bytes;
    let squeeze = u64::from(resolution.min(PAGE_TILE)).pow(2);
    (pages * squeeze / u64::from(PAGE_TILE * PAGE_TILE)) as u32
}

/// Pages a light's pool takes in a frame at most: as many as the update budget draws (it draws
/// every new page whatever the budget, so the limit is kept here), no limit without one.
#[must_use]
pub fn admit_limit(settings: &MapSettings) -> usize {
    match settings.shadow_updates {
        0 => usize::MAX,
        texels => (texels / (PAGE_TILE * PAGE_TILE)).max(1) as usize,
    }
}

/// What one paged light's update reads besides its fit.
pub(super) struct PagedUpdate<'a> {
    /// The light.
    pub light: Entity,
    /// What the last marking asked for, every paged light's.
    pub marked: Option<&'a MarkedPages>,
    /// What moved among the casters.
    pub changes: &'a CasterChanges,
    /// Every map must be drawn again (the map settings changed).
    pub forced: bool,
    /// Slots of its pool.
    pub capacity: u32,
    /// New pages it takes this update at most.
    pub admit: usize,
    /// The settings' page bias, in octaves.
    pub bias: f32,
}

/// Updates `map`'s virtual map to `fit` (see the module's notes): a new clipmap (the light
/// turned, or the scene's depth outgrew the range) or a forced redraw gives up every page.
pub(super) fn refresh_paged(map: &mut ShadowMap, fit: &PagedFit, how: &PagedUpdate) {
    let kept = map.pages.take().filter(|p| p.space == fit.space && p.pool.capacity() == how.capacity);
    let mut pages = kept.filter(|_| !how.forced).unwrap_or_else(|| VirtualPages {
        space: fit.space,
        windows: Vec::new(),
        pool: PagePool::new(how.capacity),
        pressure: Pressure::default(),
        bias: how.bias,
        marks_seen: 0,
        update: PageUpdate::default(),
        marked: PageUpdate::default(),
    });
    pages.windows = fit.space.windows(fit.camera);
    pages.bias = how.bias;
    pages.update = PageUpdate::default();
    pages.pool.clean();
    let marks = how.marked.and_then(|m| m.0.iter().find(|m| m.light == how.light.to_bits()));
    if let Some(marks) = marks.filter(|m| m.seq != pages.marks_seen) {
        pages.marks_seen = marks.seq;
        if pages.space.same_pages(&marks.space) {
            let (windows, space) = (&pages.windows, &pages.space);
            let needed: Vec<PageId> = marks
                .pages()
                .filter(|p| windows.get(p.level as usize).is_some_and(|w| w.index(*p).is_some()) && space.holds(*p))
                .collect();
            let residency = pages.pool.update(&needed, how.admit, next_version);
            pages.pressure = pages.pressure.next(needed.len(), residency.missing, how.capacity);
            pages.update.needed = needed.len() as u32;
            pages.update.residency = residency;
            pages.marked = pages.update;
        }
    }
    pages.update.residency.resident = pages.pool.len() as u32;
    let moved = crossing(&pages.space, &how.changes.moved);
    (pages.update.invalidated, pages.update.dropped) =
        pages.pool.invalidate(|p| moved.iter().any(|r| r.contains(p)), next_version);
    let settled = crossing(&pages.space, &how.changes.settled);
    pages.pool.resettle(|p| settled.iter().any(|r| r.contains(p)), next_version);
    let old = &map.layers[..map.layers.len().min(fit.coarse.len())];
    let mut layers = fitted_layers(old, &fit.coarse, fit.coarse_side, how.forced, how.changes);
    layers.extend(page_layers(&pages));
    if map.layers != layers {
        map.layers = layers;
    }
    map.pages = Some(pages);
}

/// The pages of every level that each of `boxes` lies across, seen from the light.
fn crossing(space: &PageSpace, boxes: &[Aabb]) -> Vec<crate::shadow::PageRange> {
    boxes.iter().flat_map(|b| space.crossing(b)).collect()
}

/// One layer a resident page, in slot order.
fn page_layers(pages: &VirtualPages) -> impl Iterator<Item = ShadowLayer> + '_ {
    pages.pool.resident().map(|(slot, r)| {
        let projection = pages.space.projection(r.page);
        ShadowLayer {
            clip_from_world: projection.view_proj,
            texel: projection.texel,
            resolution: PAGE_TILE,
            far: f32::INFINITY,
            blend: 0.0,
            depth: depth_terms(&projection.proj),
            dirty: r.dirty,
            version: r.version,
            static_version: r.static_version,
            page: Some(PagePlace { id: r.page, slot }),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::LayerFit;
    use crate::shadow::{Clipmap, MARK_WORDS, PageMarks};
    use glam::{Vec2, Vec3};

    fn clipmap() -> Clipmap {
        Clipmap::new(Vec3::new(0.2, -1.0, 0.3), 60.0, (20.0, -20.0))
    }

    fn fit() -> PagedFit {
        let coarse = clipmap().projection(PageId { level: 9, x: 0, y: 0 });
        let coarse = vec![LayerFit::everywhere(coarse)];
        PagedFit { space: PageSpace::Clipmap(clipmap()), camera: Vec3::ZERO, coarse, coarse_side: 1024 }
    }

    /// Marks asking for the window pages `indices` of level `level`.
    fn marks(fit: &PagedFit, seq: u64, light: Entity, level: usize, indices: &[usize]) -> MarkedPages {
        let windows = fit.space.windows(fit.camera);
        let mut bits = vec![0u32; windows.len() * MARK_WORDS];
        for i in indices {
            bits[level * MARK_WORDS + i / 32] |= 1 << (i % 32);
        }
        MarkedPages(vec![PageMarks { light: light.to_bits(), seq, space: fit.space, windows, bits }])
    }

    fn how<'a>(light: Entity, marked: Option<&'a MarkedPages>, changes: &'a CasterChanges) -> PagedUpdate<'a> {
        PagedUpdate { light, marked, changes, forced: false, capacity: 8, admit: usize::MAX, bias: 0.0 }
    }

    #[test]
    fn marked_pages_become_layers_after_the_coarse_map_and_keep_their_versions() {
        let (fit, light, still) = (fit(), Entity::from_bits(42), CasterChanges::default());
        let mut map = ShadowMap::default();
        refresh_paged(&mut map, &fit, &how(light, None, &still));
        assert_eq!(map.layers.len(), 1, "the coarse map alone before any marking");
        assert!(map.layers[0].page.is_none() && map.layers[0].resolution == 1024);
        let marked = marks(&fit, 1, light, 2, &[5, 6, 7]);
        refresh_paged(&mut map, &fit, &how(light, Some(&marked), &still));
        assert_eq!(map.layers.len(), 4);
        let pages = map.pages.as_ref().unwrap();
        assert_eq!((pages.update.needed, pages.update.residency.placed), (3, 3));
        let first: Vec<ShadowLayer> = map.layers.clone();
        assert!(first[1..].iter().all(|l| l.dirty && l.resolution == PAGE_TILE && l.page.unwrap().id.level == 2));
        // The same marking again is not counted twice; nothing moved, nothing is dirty.
        refresh_paged(&mut map, &fit, &how(light, Some(&marked), &still));
        assert_eq!(map.pages.as_ref().unwrap().update.residency.placed, 0);
        assert!(map.layers.iter().all(|l| !l.dirty));
        assert!(map.layers.iter().zip(&first).all(|(a, b)| a.version == b.version));
        // Another light's marks are not this light's.
        let other = marks(&fit, 2, Entity::from_bits(7), 3, &[1]);
        refresh_paged(&mut map, &fit, &how(light, Some(&other), &still));
        assert_eq!(map.layers.len(), 4);
    }

    #[test]
    fn a_caster_moving_through_a_page_dirties_it_and_no_other() {
        let (fit, light) = (fit(), Entity::from_bits(42));
        let mut map = ShadowMap::default();
        let window = clipmap().window(0, Vec2::ZERO);
        let marked = marks(&fit, 1, light, 0, &[0, 2080]);
        refresh_paged(&mut map, &fit, &how(light, Some(&marked), &CasterChanges::default()));
        refresh_paged(&mut map, &fit, &how(light, Some(&marked), &CasterChanges::default()));
        // A small box inside the second page's square, seen along the light.
        let (min, max) = clipmap().footprint(window.page(2080));
        let centre = (min + max) * 0.5;
        let world = clipmap().light_from_world.inverse().transform_point3(centre.extend(0.0));
        let moved = CasterChanges { moved: vec![Aabb::new(world - 0.01, world + 0.01)], settled: Vec::new() };
        refresh_paged(&mut map, &fit, &how(light, None, &moved));
        let dirty: Vec<bool> = map.layers.iter().map(|l| l.dirty).collect();
        assert_eq!(dirty, vec![true, false, true], "the coarse map and the page it crossed");
        assert_eq!(map.pages.as_ref().unwrap().update.invalidated, 1);
    }

    #[test]
    fn a_new_clipmap_or_a_forced_redraw_gives_up_every_page() {
        let (fit, light, still) = (fit(), Entity::from_bits(42), CasterChanges::default());
        let mut map = ShadowMap::default();
        let marked = marks(&fit, 1, light, 1, &[9]);
        refresh_paged(&mut map, &fit, &how(light, Some(&marked), &still));
        assert_eq!(map.layers.len(), 2);
        let turned = Clipmap::new(Vec3::new(-0.5, -1.0, 0.0), 60.0, (20.0, -20.0));
        let turned = PagedFit { space: PageSpace::Clipmap(turned), ..fit.clone() };
        refresh_paged(&mut map, &turned, &how(light, Some(&marked), &still));
        assert_eq!(map.layers.len(), 1, "the sun turned: no page is good, and old marks name other pages");
        let mut map = ShadowMap::default();
        refresh_paged(&mut map, &fit, &how(light, Some(&marked), &still));
        refresh_paged(&mut map, &fit, &PagedUpdate { forced: true, ..how(light, None, &still) });
        assert_eq!(map.layers.len(), 1);
    }

    #[test]
    fn the_pool_holds_the_page_memory_and_the_budget_limits_new_pages() {
        let settings = MapSettings { page_memory: 32, ..MapSettings::default() };
        assert_eq!(pool_capacity(&settings, 4, PAGE_TILE), 512, "32 MiB of 128² depth pages");
        assert_eq!(pool_capacity(&settings, 8, PAGE_TILE), 256);
        assert_eq!(pool_capacity(&settings, 4, PAGE_TILE / 2), 128, "squeezed tiles, fewer pages");
        assert_eq!(pool_capacity(&settings, 0, 0), 0);
        assert_eq!(admit_limit(&settings), usize::MAX);
        assert_eq!(admit_limit(&MapSettings { shadow_updates: 1 << 20, ..settings }), 64);
        assert_eq!(admit_limit(&MapSettings { shadow_updates: 1024, ..settings }), 1);
        assert_eq!(coarse_side(&MapSettings { shadow_map_size: 256, ..settings }), 256);
    }
}
