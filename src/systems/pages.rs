//! Virtual shadow maps in the update: each paged light's pages round the camera, one pool that
//! every paged light shares given the pages their last markings asked for (see
//! [`crate::components::SharedPool`]), new contents for the pages a caster moved through, and
//! each light's layers: its coarse map, then one layer a resident page of its own (named by its
//! slot, so it keeps its tile and what was drawn in it for as long as it stays).
//!
//! The pool takes in a frame at most the pages the update budget draws, every light's together:
//! the coarsest level first (a coarse page serves every pixel under it), then the pages that have
//! waited longest, then those of the lights that show most, so where slots run short the pages of
//! the lights that show least go missing first and their pixels read coarser levels. The pool's
//! one pressure then moves every light's levels an octave coarser, or finer while the pool has
//! room, to keep what the view needs at three quarters of the pool ([`Pressure`]), once every paged
//! light has been marked at the pressure as it is: a light marked before the last move asks for
//! the pages of the levels before.

use super::casters::CasterChanges;
use super::layers::{fitted_layers, next_version};
use crate::components::{MarkedPages, PagePlace, PageUpdate, ShadowLayer, ShadowMap, SharedPool, VirtualPages};
use crate::light::PagedFit;
use crate::settings::MapSettings;
use crate::shadow::{
    Aabb, LightPage, PAGE_TILE, PageId, PagePool, PageRange, PageSpace, Pressure, Resident, depth_terms,
};
use bevy_ecs::prelude::Entity;
use std::collections::{HashMap, HashSet};

/// Side of a paged light's coarse map, in texels: what every pixel whose page is not there yet
/// reads (never larger than the settings' map size).
pub const COARSE_SIDE: u32 = 1024;

/// The coarse map's side with `settings`.
#[must_use]
pub fn coarse_side(settings: &MapSettings) -> u32 {
    COARSE_SIDE.min(settings.shadow_map_size)
}

/// Slots of the pool every paged light shares: the settings' page memory in pages at
/// `texel_bytes` a texel, fewer where the memory budget squeezed its tiles below [`PAGE_TILE`]
/// (`resolution`).
#[must_use]
pub fn pool_capacity(settings: &MapSettings, texel_bytes: u32, resolution: u32) -> u32 {
    let page_bytes = u64::from(PAGE_TILE * PAGE_TILE) * u64::from(texel_bytes.max(1));
    let pages = (u64::from(settings.page_memory) << 20) / page_bytes;
    let squeeze = u64::from(resolution.min(PAGE_TILE)).pow(2);
    (pages * squeeze / u64::from(PAGE_TILE * PAGE_TILE)) as u32
}

/// Pages the pool takes in a frame at most, every light's together: as many as the update
/// budget draws (it draws every new page whatever the budget, so the limit is kept here), no
/// limit without one.
#[must_use]
pub fn admit_limit(settings: &MapSettings) -> usize {
    match settings.shadow_updates {
        0 => usize::MAX,
        texels => (texels / (PAGE_TILE * PAGE_TILE)).max(1) as usize,
    }
}

/// What every paged light's update reads besides its fit.
pub(super) struct PagedUpdate<'a> {
    /// What the last marking asked for, every paged light's.
    pub marked: Option<&'a MarkedPages>,
    /// What moved among the casters.
    pub changes: &'a CasterChanges,
    /// Every map must be drawn again (the map settings changed).
    pub forced: bool,
    /// Slots of the pool.
    pub capacity: u32,
    /// New pages the pool takes this update at most.
    pub admit: usize,
    /// The settings' page bias, in octaves.
    pub bias: f32,
}

/// A paged light this update: its map and how its kind fits its pages.
pub(super) struct PagedLight<'a> {
    /// The light.
    pub light: Entity,
    /// Its shadow map.
    pub map: &'a mut ShadowMap,
    /// Its pages and coarse map, as its kind fits them.
    pub fit: PagedFit,
}

/// Updates every paged light's virtual map to its fit and gives `pool` what their markings asked
/// for (see the module's notes); a light with a new page space (it moved or turned, or the
/// scene's depth outgrew its range) gives up its pages, a light no longer paged (or gone) too,
/// and a forced redraw or a new pool size every page.
pub(super) fn refresh_paged(shared: &mut SharedPool, lights: &mut [PagedLight], how: &PagedUpdate) {
    if how.forced || shared.pages.capacity() != how.capacity {
        *shared = SharedPool { pages: PagePool::new(how.capacity), ..SharedPool::default() };
    }
    let pool = &mut shared.pages;
    pool.clean();
    let ids: HashSet<u64> = lights.iter().map(|l| l.light.to_bits()).collect();
    pool.release(|k| !ids.contains(&k.light));
    // The lights that show most give their pages first.
    lights.sort_by(|a, b| shows(b).total_cmp(&shows(a)).then(a.light.cmp(&b.light)));
    let taken: Vec<Taken> = lights.iter_mut().map(|l| take_marks(pool, l, how, shared.pressure)).collect();
    let needed: Vec<LightPage> = lights
        .iter()
        .flat_map(|l| {
            let light = l.light.to_bits();
            needed_by(l).iter().map(move |&page| LightPage { light, page })
        })
        .collect();
    let missing = pool.update(&needed, how.admit, next_version).missing;
    if missing > 0 && !shared.short {
        shared.heard.clear();
    }
    shared.short = missing > 0;
    shared.heard.extend(lights.iter().zip(&taken).filter(|(_, t)| t.current).map(|(l, _)| l.light.to_bits()));
    if !ids.is_empty() && ids.iter().all(|id| shared.heard.contains(id)) {
        let next = shared.pressure.next(needed.len(), how.capacity);
        if next != shared.pressure {
            shared.heard.clear();
        }
        shared.pressure = next;
    }
    let moved: HashSet<u64> =
        lights.iter().zip(&taken).filter(|(_, t)| t.moved).map(|(l, _)| l.light.to_bits()).collect();
    let hits = redraw_crossed(pool, lights, how.changes, &moved);
    let mut by_light = account(pool, &hits);
    for (i, l) in lights.iter_mut().enumerate() {
        let (update, own) = by_light.remove(&l.light.to_bits()).unwrap_or_default();
        finish(l, update, &own, taken[i].fresh, shared.pressure, how);
    }
}

/// A light's page resident in a slot of the pool.
type OwnPage = (u32, Resident<LightPage>);

/// What `l` shows on screen, as its visible pixels ask: the pages its last marking needed,
/// counted at the settings' level (each octave coarser needs about 1/2.25 of them). Its reach's
/// share of the screen says less: the camera is inside most lights' reach.
fn shows(l: &PagedLight) -> f32 {
    l.map.pages.as_ref().map_or(0.0, |p| p.needed.len() as f32 * 2.25f32.powf(p.pressure.octaves))
}

/// The pages `l`'s last marking asked for.
fn needed_by<'a>(l: &'a PagedLight) -> &'a [PageId] {
    l.map.pages.as_ref().map_or(&[], |p| &p.needed)
}

/// Gives the resident pages a caster moved through new contents, and every page of the lights
/// that `moved`, and the pages under a caster at rest that changed a new static version, each
/// light's seen from it; returns the pages hit (see [`PagePool::invalidate`]).
fn redraw_crossed(
    pool: &mut PagePool<LightPage>,
    lights: &[PagedLight],
    changes: &CasterChanges,
    moved_lights: &HashSet<u64>,
) -> Vec<(LightPage, bool)> {
    let hit = |ranges: &HashMap<u64, Vec<PageRange>>, k: LightPage| {
        ranges.get(&k.light).is_some_and(|r| r.iter().any(|r| r.contains(k.page)))
    };
    let moved = crossings(lights, &changes.moved);
    let hits = pool.invalidate(|k| moved_lights.contains(&k.light) || hit(&moved, k), next_version);
    let settled = crossings(lights, &changes.settled);
    pool.resettle(|k| moved_lights.contains(&k.light) || hit(&settled, k), next_version);
    hits
}

/// Each light's account of the pool's last update (its pages' changes, and those of `hits`
/// redrawn or given up) and its resident pages with their slots, in slot order.
fn account(pool: &PagePool<LightPage>, hits: &[(LightPage, bool)]) -> HashMap<u64, (PageUpdate, Vec<OwnPage>)> {
    let mut by_light: HashMap<u64, (PageUpdate, Vec<_>)> = HashMap::new();
    for (k, change) in pool.changes() {
        by_light.entry(k.light).or_default().0.residency.count(*change);
    }
    for (k, kept) in hits {
        let update = &mut by_light.entry(k.light).or_default().0;
        *(if *kept { &mut update.invalidated } else { &mut update.dropped }) += 1;
    }
    for (slot, r) in pool.resident() {
        let (update, own) = by_light.entry(r.page.light).or_default();
        update.residency.resident += 1;
        own.push((slot, *r));
    }
    by_light
}

/// Gives `l` its account of the update (kept as its marking's too where one came in, `marked`),
/// the pool's `pressure` and its layers: its coarse map, then its resident pages (`own`).
fn finish(
    l: &mut PagedLight,
    update: PageUpdate,
    own: &[OwnPage],
    marked: bool,
    pressure: Pressure,
    how: &PagedUpdate,
) {
    let Some(pages) = l.map.pages.as_mut() else { return };
    pages.update = PageUpdate { needed: pages.update.needed, ..update };
    pages.resident = own.len() as u32;
    pages.pressure = pressure;
    if marked {
        pages.marked = pages.update;
    }
    let old = &l.map.layers[..l.map.layers.len().min(l.fit.coarse.len())];
    let mut layers = fitted_layers(old, &l.fit.coarse, l.fit.coarse_side, how.forced, how.changes);
    layers.extend(own.iter().map(|(slot, r)| page_layer(&pages.space, *slot, r)));
    if l.map.layers != layers {
        l.map.layers = layers;
    }
}

/// What taking a light's fit and marking in found.
#[derive(Clone, Copy, Debug, Default)]
struct Taken {
    /// A marking of it came back and was taken in: its pages are the ones it names (made against
    /// its pages as they are, or as they were before it moved).
    fresh: bool,
    /// And it was made at the pool's pressure as it is.
    current: bool,
    /// It moved or turned, its pages cut as before: each is drawn again where it is.
    moved: bool,
}

/// Takes `l`'s fit in, and what its last marking asked for if it is new: a light that moved or
/// turned with its pages cut as before keeps them (and what it asked), to be drawn again; one cut
/// anew gives up its pages in `pool`. `pressure` is the pool's.
fn take_marks(pool: &mut PagePool<LightPage>, l: &mut PagedLight, how: &PagedUpdate, pressure: Pressure) -> Taken {
    let (fit, light) = (&l.fit, l.light.to_bits());
    let mut taken = Taken::default();
    let kept = l.map.pages.take().filter(|p| p.space.same_layout(&fit.space) && !how.forced);
    let mut pages = match kept {
        Some(p) => {
            taken.moved = p.space != fit.space;
            VirtualPages { space: fit.space, ..p }
        }
        None => {
            pool.release(|k| k.light == light);
            VirtualPages {
                space: fit.space,
                windows: Vec::new(),
                needed: Vec::new(),
                resident: 0,
                pressure,
                bias: how.bias,
                marks_seen: 0,
                update: PageUpdate::default(),
                marked: PageUpdate::default(),
            }
        }
    };
    pages.windows = fit.space.windows(fit.camera);
    pages.bias = how.bias;
    pages.update = PageUpdate::default();
    let marks = how.marked.and_then(|m| m.0.iter().find(|m| m.light == light));
    if let Some(marks) = marks.filter(|m| m.seq != pages.marks_seen) {
        pages.marks_seen = marks.seq;
        if pages.space.same_layout(&marks.space) {
            let (windows, space) = (&pages.windows, &pages.space);
            pages.needed = marks
                .pages()
                .filter(|p| windows.get(p.level as usize).is_some_and(|w| w.index(*p).is_some()) && space.holds(*p))
                .collect();
            pages.update.needed = pages.needed.len() as u32;
            taken.fresh = true;
            taken.current = marks.bias == how.bias + pressure.octaves;
        }
    }
    l.map.pages = Some(pages);
    taken
}

/// Each light's pages, every level's, that one of `boxes` lies across, seen from the light;
/// lights none crosses are left out.
fn crossings(lights: &[PagedLight], boxes: &[Aabb]) -> HashMap<u64, Vec<PageRange>> {
    if boxes.is_empty() {
        return HashMap::new();
    }
    let crossing = |space: &PageSpace| -> Vec<PageRange> { boxes.iter().flat_map(|b| space.crossing(b)).collect() };
    lights
        .iter()
        .filter_map(|l| l.map.pages.as_ref().map(|p| (l.light.to_bits(), crossing(&p.space))))
        .filter(|(_, r)| !r.is_empty())
        .collect()
}

/// The layer of page `r`, resident in `slot`, of a light whose pages are `space`.
fn page_layer(space: &PageSpace, slot: u32, r: &Resident<LightPage>) -> ShadowLayer {
    let projection = space.projection(r.page.page);
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
        page: Some(PagePlace { id: r.page.page, slot }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::LayerFit;
    use crate::shadow::{Change, Clipmap, MARK_WORDS, PAGE_GRID, PageMarks};
    use glam::{Vec2, Vec3};

    fn clipmap() -> Clipmap {
        Clipmap::new(Vec3::new(0.2, -1.0, 0.3), 60.0, (20.0, -20.0))
    }

    fn fit() -> PagedFit {
        let coarse = clipmap().projection(PageId { level: 9, x: 0, y: 0 });
        let coarse = vec![LayerFit::everywhere(coarse)];
        PagedFit { space: PageSpace::Clipmap(clipmap()), camera: Vec3::ZERO, coarse, coarse_side: 1024 }
    }

    /// Marks of `light` asking for the window pages `indices` of level `level`.
    fn marks_of(fit: &PagedFit, seq: u64, light: Entity, level: usize, indices: &[usize]) -> PageMarks {
        let windows = fit.space.windows(fit.camera);
        let mut bits = vec![0u32; windows.len() * MARK_WORDS];
        for i in indices {
            bits[level * MARK_WORDS + i / 32] |= 1 << (i % 32);
        }
        PageMarks { light: light.to_bits(), seq, space: fit.space, windows, bias: 0.0, bits }
    }

    fn marks(fit: &PagedFit, seq: u64, light: Entity, level: usize, indices: &[usize]) -> MarkedPages {
        MarkedPages(vec![marks_of(fit, seq, light, level, indices)])
    }

    fn how<'a>(marked: Option<&'a MarkedPages>, changes: &'a CasterChanges) -> PagedUpdate<'a> {
        PagedUpdate { marked, changes, forced: false, capacity: 8, admit: usize::MAX, bias: 0.0 }
    }

    /// One light's update, alone in `pool`.
    fn refresh(pool: &mut SharedPool, map: &mut ShadowMap, light: Entity, fit: &PagedFit, how: &PagedUpdate) {
        refresh_paged(pool, &mut [PagedLight { light, map, fit: fit.clone() }], how);
    }

    #[test]
    fn marked_pages_become_layers_after_the_coarse_map_and_keep_their_versions() {
        let (fit, light, still) = (fit(), Entity::from_bits(42), CasterChanges::default());
        let (mut map, mut pool) = (ShadowMap::default(), SharedPool::default());
        refresh(&mut pool, &mut map, light, &fit, &how(None, &still));
        assert_eq!(map.layers.len(), 1, "the coarse map alone before any marking");
        assert!(map.layers[0].page.is_none() && map.layers[0].resolution == 1024);
        let marked = marks(&fit, 1, light, 2, &[5, 6, 7]);
        refresh(&mut pool, &mut map, light, &fit, &how(Some(&marked), &still));
        assert_eq!(map.layers.len(), 4);
        let pages = map.pages.as_ref().unwrap();
        assert_eq!((pages.update.needed, pages.update.residency.placed, pages.resident), (3, 3, 3));
        let first: Vec<ShadowLayer> = map.layers.clone();
        assert!(first[1..].iter().all(|l| l.dirty && l.resolution == PAGE_TILE && l.page.unwrap().id.level == 2));
        // The same marking again is not counted twice; nothing moved, nothing is dirty.
        refresh(&mut pool, &mut map, light, &fit, &how(Some(&marked), &still));
        assert_eq!(map.pages.as_ref().unwrap().update.residency.placed, 0);
        assert!(map.layers.iter().all(|l| !l.dirty));
        assert!(map.layers.iter().zip(&first).all(|(a, b)| a.version == b.version));
        // Another light's marks are not this light's; its last marking's pages stay.
        let other = marks(&fit, 2, Entity::from_bits(7), 3, &[1]);
        refresh(&mut pool, &mut map, light, &fit, &how(Some(&other), &still));
        assert_eq!(map.layers.len(), 4);
    }

    #[test]
    fn a_caster_moving_through_a_page_dirties_it_and_no_other() {
        let (fit, light) = (fit(), Entity::from_bits(42));
        let (mut map, mut pool) = (ShadowMap::default(), SharedPool::default());
        let window = clipmap().window(0, Vec2::ZERO);
        let camera_page = (PAGE_GRID / 2 * (PAGE_GRID + 1)) as usize;
        let marked = marks(&fit, 1, light, 0, &[0, camera_page]);
        refresh(&mut pool, &mut map, light, &fit, &how(Some(&marked), &CasterChanges::default()));
        refresh(&mut pool, &mut map, light, &fit, &how(Some(&marked), &CasterChanges::default()));
        // A small box inside the second page's square, seen along the light.
        let (min, max) = clipmap().footprint(window.page(camera_page));
        let centre = (min + max) * 0.5;
        let world = clipmap().light_from_world.inverse().transform_point3(centre.extend(0.0));
        let moved = CasterChanges { moved: vec![Aabb::new(world - 0.01, world + 0.01)], settled: Vec::new() };
        refresh(&mut pool, &mut map, light, &fit, &how(None, &moved));
        let dirty: Vec<bool> = map.layers.iter().map(|l| l.dirty).collect();
        assert_eq!(dirty, vec![true, false, true], "the coarse map and the page it crossed");
        assert_eq!(map.pages.as_ref().unwrap().update.invalidated, 1);
    }

    #[test]
    fn a_light_that_moved_with_its_pages_cut_as_before_keeps_its_slots_and_draws_them_again() {
        let (fit, light, still) = (fit(), Entity::from_bits(42), CasterChanges::default());
        let (mut map, mut pool) = (ShadowMap::default(), SharedPool::default());
        refresh(&mut pool, &mut map, light, &fit, &how(Some(&marks(&fit, 1, light, 1, &[9])), &still));
        refresh(&mut pool, &mut map, light, &fit, &how(None, &still));
        let before = map.layers[1];
        assert!(!before.dirty);
        // A new depth range: the same pages, each holding other depths now.
        let PageSpace::Clipmap(c) = fit.space else { unreachable!() };
        let moved = PagedFit { space: PageSpace::Clipmap(Clipmap { depth: (40.0, -40.0), ..c }), ..fit.clone() };
        refresh(&mut pool, &mut map, light, &moved, &how(None, &still));
        let after = map.layers[1];
        assert_eq!((map.layers.len(), after.page.unwrap().slot), (2, before.page.unwrap().slot), "kept in its slot");
        assert!(after.dirty && after.version != before.version, "drawn again");
        assert_eq!(map.pages.as_ref().unwrap().update.invalidated, 1);
        // A marking made before the move is still taken in.
        refresh(&mut pool, &mut map, light, &moved, &how(Some(&marks(&fit, 2, light, 1, &[9, 10])), &still));
        assert_eq!(map.pages.as_ref().unwrap().needed.len(), 2);
    }

    #[test]
    fn a_new_clipmap_or_a_forced_redraw_gives_up_every_page() {
        let (fit, light, still) = (fit(), Entity::from_bits(42), CasterChanges::default());
        let (mut map, mut pool) = (ShadowMap::default(), SharedPool::default());
        let marked = marks(&fit, 1, light, 1, &[9]);
        refresh(&mut pool, &mut map, light, &fit, &how(Some(&marked), &still));
        assert_eq!(map.layers.len(), 2);
        let turned = Clipmap::new(Vec3::new(-0.5, -1.0, 0.0), 60.0, (20.0, -20.0));
        let turned = PagedFit { space: PageSpace::Clipmap(turned), ..fit.clone() };
        refresh(&mut pool, &mut map, light, &turned, &how(Some(&marked), &still));
        assert_eq!(map.layers.len(), 1, "the sun turned: no page is good, and old marks name other pages");
        assert!(pool.pages.is_empty());
        let mut map = ShadowMap::default();
        refresh(&mut pool, &mut map, light, &fit, &how(Some(&marked), &still));
        refresh(&mut pool, &mut map, light, &fit, &PagedUpdate { forced: true, ..how(None, &still) });
        assert_eq!(map.layers.len(), 1);
    }

    /// Lights `near` and `far`, `maps` theirs in that order, updated together in a pool of
    /// `capacity` slots (the far light given first).
    fn update_two(
        (pool, capacity): (&mut SharedPool, u32),
        maps: &mut [ShadowMap; 2],
        (near, far): (Entity, Entity),
        marked: &MarkedPages,
    ) {
        let (fit, still) = (fit(), CasterChanges::default());
        let [a, b] = maps;
        let mut lights = [PagedLight { light: far, map: b, fit: fit.clone() }, PagedLight { light: near, map: a, fit }];
        refresh_paged(pool, &mut lights, &PagedUpdate { capacity, ..how(Some(marked), &still) });
    }

    #[test]
    fn lights_share_one_pool_the_one_that_shows_least_finds_no_slot_first_and_all_go_coarser() {
        let (fit, still) = (fit(), CasterChanges::default());
        let (near, far) = (Entity::from_bits(42), Entity::from_bits(7));
        let (mut maps, mut pool) = ([ShadowMap::default(), ShadowMap::default()], SharedPool::default());
        let update = |pool: &mut SharedPool, maps: &mut [ShadowMap; 2], marked: &MarkedPages| {
            update_two((pool, 5), maps, (near, far), marked);
        };
        update(&mut pool, &mut maps, &MarkedPages(vec![marks_of(&fit, 1, near, 0, &[0, 1, 2, 3])]));
        assert_eq!(pool.pressure.octaves, 0.0, "the far light is not marked yet");
        // Seven pages of one level asked for in five slots: the light that shows more keeps its
        // pages, the other's go missing, and the pool's levels go an octave coarser, every light's.
        let marked =
            MarkedPages(vec![marks_of(&fit, 2, near, 0, &[0, 1, 2, 3]), marks_of(&fit, 1, far, 0, &[4, 5, 6])]);
        update(&mut pool, &mut maps, &marked);
        let pages = |m: &ShadowMap| m.pages.clone().unwrap();
        assert_eq!((pages(&maps[0]).resident, pages(&maps[1]).resident), (4, 1));
        assert_eq!(pages(&maps[1]).marked.residency.missing, 2);
        // Seven pages for three quarters of five slots: 2.25^0.77 times too many.
        assert_eq!(
            (pool.pressure.octaves, pages(&maps[0]).pressure, pages(&maps[1]).pressure),
            (0.75, pool.pressure, pool.pressure)
        );
        assert_eq!(pool.pages.len(), 5);
        assert!(
            maps[1].layers[1..].iter().all(|l| l.page.is_some_and(|p| p.slot == 4)),
            "the slot the near light left"
        );
        // A light no longer paged gives its pages up.
        let [a, _] = &mut maps;
        refresh(&mut pool, a, near, &fit, &PagedUpdate { capacity: 5, ..how(None, &still) });
        assert!(pool.pages.len() == 4 && pool.pages.resident().all(|(_, r)| r.page.light == near.to_bits()));
        assert!(pool.pages.resident().all(|(_, r)| !r.dirty), "kept as they were");
    }

    #[test]
    fn the_pressure_moves_once_every_light_is_marked_at_it_since_pages_went_missing() {
        let fit = fit();
        let (near, far) = (Entity::from_bits(42), Entity::from_bits(7));
        let (mut maps, mut pool) = ([ShadowMap::default(), ShadowMap::default()], SharedPool::default());
        // Six slots: five pages are within the slack of three quarters of them.
        let update = |pool: &mut SharedPool, maps: &mut [ShadowMap; 2], marked: Vec<PageMarks>| {
            update_two((pool, 6), maps, (near, far), &MarkedPages(marked));
        };
        let at = |bias: f32, marks: PageMarks| PageMarks { bias, ..marks };
        update(&mut pool, &mut maps, vec![marks_of(&fit, 1, near, 0, &[0, 1, 2, 3]), marks_of(&fit, 1, far, 0, &[9])]);
        assert_eq!((pool.pressure.octaves, pool.short), (0.0, false), "five pages in six slots");
        // A cut: the far light asks for three new pages while the near one's last marking still
        // holds four slots; the pool is short, but the near light's need is older than that.
        let cut = [20, 21, 22];
        update(&mut pool, &mut maps, vec![marks_of(&fit, 1, near, 0, &[0, 1, 2, 3]), marks_of(&fit, 2, far, 0, &cut)]);
        assert_eq!(pool.pages.changes().iter().filter(|(_, c)| *c == Change::Missing).count(), 1);
        assert_eq!(pool.pressure.octaves, 0.0, "no light is yet known to want for slots");
        // Once the near light has been marked again and still needs its four, the levels go
        // coarser: seven pages, 2.25^0.55 times three quarters of six.
        update(&mut pool, &mut maps, vec![marks_of(&fit, 2, near, 0, &[0, 1, 2, 3]), marks_of(&fit, 2, far, 0, &cut)]);
        assert_eq!(pool.pressure.octaves, 0.5);
        assert!(maps.iter().all(|m| m.pages.as_ref().unwrap().lookup_bias() == 0.5), "every light's lookups");
        // Markings made before that move still ask for the finer levels' pages: they move nothing.
        update(&mut pool, &mut maps, vec![marks_of(&fit, 3, near, 0, &[0, 1, 2, 3]), marks_of(&fit, 3, far, 0, &cut)]);
        assert_eq!((pool.pressure.octaves, pool.short), (0.5, true));
        let current =
            vec![at(0.5, marks_of(&fit, 4, near, 0, &[0, 1, 2, 3])), at(0.5, marks_of(&fit, 4, far, 0, &cut))];
        update(&mut pool, &mut maps, current);
        assert_eq!(pool.pressure.octaves, 1.0, "marked at the coarser levels and still short");
    }

    #[test]
    fn the_pool_holds_the_page_memory_and_the_budget_limits_new_pages() {
        let settings = MapSettings { page_memory: 32, ..MapSettings::default() };
        assert_eq!(pool_capacity(&settings, 4, PAGE_TILE), 2048, "32 MiB of 64² depth pages");
        assert_eq!(pool_capacity(&settings, 8, PAGE_TILE), 1024);
        assert_eq!(pool_capacity(&settings, 4, PAGE_TILE / 2), 512, "squeezed tiles, fewer pages");
        assert_eq!(pool_capacity(&settings, 0, 0), 0);
        assert_eq!(admit_limit(&settings), usize::MAX);
        assert_eq!(admit_limit(&MapSettings { shadow_updates: 1 << 20, ..settings }), 256);
        assert_eq!(admit_limit(&MapSettings { shadow_updates: 1024, ..settings }), 1);
        assert_eq!(coarse_side(&MapSettings { shadow_map_size: 256, ..settings }), 256);
    }
}
