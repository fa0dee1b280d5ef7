//! Virtual shadow maps in the update: each paged light's pages round the camera, one pool that
//! every paged light shares given the pages their last markings asked for (see
//! [`crate::components::SharedPool`]), new contents for the pages a caster moved through, and
//! each light's layers: its coarse map, then one layer a resident page of its own (named by its
//! slot, so it keeps its tile and what was drawn in it for as long as it stays).
//!
//! The pool takes in a frame at most the pages the update budget draws, every light's together:
//! the coarsest level first (a coarse page serves every pixel under it), then the pages that have
//! waited longest, then those of the lights that show most. While pages go missing the lights that
//! show least go an octave coarser first ([`coarser_first`]), each as its next marking comes in;
//! while the pool has room the lights that show most go finer first ([`finer_room`]).

use super::casters::CasterChanges;
use super::layers::{fitted_layers, next_version};
use crate::components::{MarkedPages, PagePlace, PageUpdate, ShadowLayer, ShadowMap, SharedPool, VirtualPages};
use crate::light::PagedFit;
use crate::settings::MapSettings;
use crate::shadow::{
    Aabb, LightPage, MAX_PRESSURE, PAGE_TILE, PageId, PagePool, PageRange, PageSpace, Pressure, Resident, depth_terms,
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

/// Which of the lights go an octave coarser to free `missing` slots, each given as what it
/// shows, the pages its last marking needed and whether it can go coarser still: those that show
/// least first, each counted as freeing 5/9 of its pages (an octave coarser needs about 1/2.25
/// of them, see [`Pressure`]), until what they free covers what is missing.
#[must_use]
pub fn coarser_first(lights: &[(f32, usize, bool)], missing: u32) -> Vec<bool> {
    let shows = |i: usize| if lights[i].0.is_nan() { 0.0 } else { lights[i].0 };
    let mut order: Vec<usize> = (0..lights.len()).filter(|&i| lights[i].2).collect();
    order.sort_by(|&a, &b| shows(a).total_cmp(&shows(b)));
    let mut chosen = vec![false; lights.len()];
    let mut freed = 0usize;
    for i in order {
        if freed >= missing as usize {
            break;
        }
        chosen[i] = true;
        freed = freed.saturating_add(lights[i].1.saturating_mul(5).div_ceil(9));
    }
    chosen
}

/// The slots each of the lights (in the order of what they show, most first, each given as the
/// pages its last marking needed and whether it may go finer) may count on to go an octave finer:
/// what the lights that show more leave, each counted at its finer level's pages where it may go
/// finer (about 2.25 times, see [`Pressure`]). The lights that show less are not counted: where
/// they hold the slots, pages go missing and they go coarser first ([`coarser_first`]).
#[must_use]
pub fn finer_room(capacity: u32, lights: &[(usize, bool)]) -> Vec<u32> {
    let mut taken = 0u64;
    lights
        .iter()
        .map(|&(needed, finer)| {
            let room = u64::from(capacity).saturating_sub(taken) as u32;
            let needed = needed as u64;
            taken = taken.saturating_add(if finer { needed.saturating_mul(9).div_ceil(4) } else { needed });
            room
        })
        .collect()
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
    let pool = &mut shared.pages;
    if how.forced || pool.capacity() != how.capacity {
        *pool = PagePool::new(how.capacity);
    }
    pool.clean();
    let ids: HashSet<u64> = lights.iter().map(|l| l.light.to_bits()).collect();
    pool.release(|k| !ids.contains(&k.light));
    // The lights that show most give their pages first.
    lights.sort_by(|a, b| shows(b).total_cmp(&shows(a)).then(a.light.cmp(&b.light)));
    let fresh: Vec<bool> = lights.iter_mut().map(|l| take_marks(pool, l, how)).collect();
    let needed: Vec<LightPage> = lights
        .iter()
        .flat_map(|l| {
            let light = l.light.to_bits();
            needed_by(l).iter().map(move |&page| LightPage { light, page })
        })
        .collect();
    let missing = pool.update(&needed, how.admit, next_version).missing;
    let can_coarsen = |l: &PagedLight| l.map.pages.as_ref().is_some_and(|p| p.pressure.octaves < MAX_PRESSURE as i32);
    let counts: Vec<(f32, usize, bool)> =
        lights.iter().map(|l| (shows(l), needed_by(l).len(), can_coarsen(l))).collect();
    // Pages go missing for want of slots once every light has been marked since they began to.
    let short = (missing > 0).then(|| {
        let marked = shared.short.get_or_insert_with(HashSet::new);
        marked.extend(lights.iter().zip(&fresh).filter(|(_, f)| **f).map(|(l, _)| l.light.to_bits()));
        ids.iter().all(|id| marked.contains(id))
    });
    if short.is_none() {
        shared.short = None;
    }
    let coarser = if short == Some(true) { coarser_first(&counts, missing) } else { vec![false; lights.len()] };
    let hits = redraw_crossed(pool, lights, how.changes);
    let mut by_light = account(pool, &hits);
    let finer = |l: &PagedLight| l.map.pages.as_ref().is_some_and(|p| p.pressure.may_go_finer());
    let wants: Vec<(usize, bool)> = lights.iter().map(|l| (needed_by(l).len(), finer(l))).collect();
    let rooms = finer_room(how.capacity, &wants);
    for (i, l) in lights.iter_mut().enumerate() {
        let (update, own) = by_light.remove(&l.light.to_bits()).unwrap_or_default();
        finish(l, update, &own, fresh[i].then_some((coarser[i], rooms[i])), how);
    }
}

/// A light's page resident in a slot of the pool.
type OwnPage = (u32, Resident<LightPage>);

/// What `l` shows on screen, as its visible pixels ask: the pages its last marking needed,
/// counted at the settings' level (each octave coarser needs about 1/2.25 of them). Its reach's
/// share of the screen says less: the camera is inside most lights' reach.
fn shows(l: &PagedLight) -> f32 {
    l.map.pages.as_ref().map_or(0.0, |p| p.needed.len() as f32 * 2.25f32.powi(p.pressure.octaves))
}

/// The pages `l`'s last marking asked for.
fn needed_by<'a>(l: &'a PagedLight) -> &'a [PageId] {
    l.map.pages.as_ref().map_or(&[], |p| &p.needed)
}

/// Gives the resident pages a caster moved through new contents, and the pages under a caster at
/// rest that changed a new static version, each light's seen from it; returns the pages hit (see
/// [`PagePool::invalidate`]).
fn redraw_crossed(
    pool: &mut PagePool<LightPage>,
    lights: &[PagedLight],
    changes: &CasterChanges,
) -> Vec<(LightPage, bool)> {
    let hit = |ranges: &HashMap<u64, Vec<PageRange>>, k: LightPage| {
        ranges.get(&k.light).is_some_and(|r| r.iter().any(|r| r.contains(k.page)))
    };
    let moved = crossings(lights, &changes.moved);
    let hits = pool.invalidate(|k| hit(&moved, k), next_version);
    let settled = crossings(lights, &changes.settled);
    pool.resettle(|k| hit(&settled, k), next_version);
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

/// Gives `l` its account of the update and its layers: its coarse map, then its resident pages
/// (`own`). `marked` (where its marking came in this update) says whether the pool is short of
/// slots for it and how many the other lights leave it: its pressure follows.
fn finish(l: &mut PagedLight, update: PageUpdate, own: &[OwnPage], marked: Option<(bool, u32)>, how: &PagedUpdate) {
    let Some(pages) = l.map.pages.as_mut() else { return };
    pages.update = PageUpdate { needed: pages.update.needed, ..update };
    pages.resident = own.len() as u32;
    if let Some((short, room)) = marked {
        pages.pressure = pages.pressure.next(pages.needed.len(), short, room);
        pages.marked = pages.update;
    }
    let old = &l.map.layers[..l.map.layers.len().min(l.fit.coarse.len())];
    let mut layers = fitted_layers(old, &l.fit.coarse, l.fit.coarse_side, how.forced, how.changes);
    layers.extend(own.iter().map(|(slot, r)| page_layer(&pages.space, *slot, r)));
    if l.map.layers != layers {
        l.map.layers = layers;
    }
}

/// Takes `l`'s fit in, and what its last marking asked for if it is new (returns true then):
/// a new page space gives up the light's pages in `pool`.
fn take_marks(pool: &mut PagePool<LightPage>, l: &mut PagedLight, how: &PagedUpdate) -> bool {
    let (fit, light) = (&l.fit, l.light.to_bits());
    let kept = l.map.pages.take().filter(|p| p.space == fit.space && !how.forced);
    let mut pages = kept.unwrap_or_else(|| {
        pool.release(|k| k.light == light);
        VirtualPages {
            space: fit.space,
            windows: Vec::new(),
            needed: Vec::new(),
            resident: 0,
            pressure: Pressure::default(),
            bias: how.bias,
            marks_seen: 0,
            update: PageUpdate::default(),
            marked: PageUpdate::default(),
        }
    });
    pages.windows = fit.space.windows(fit.camera);
    pages.bias = how.bias;
    pages.update = PageUpdate::default();
    let marks = how.marked.and_then(|m| m.0.iter().find(|m| m.light == light));
    let mut fresh = false;
    if let Some(marks) = marks.filter(|m| m.seq != pages.marks_seen) {
        pages.marks_seen = marks.seq;
        if pages.space.same_pages(&marks.space) {
            let (windows, space) = (&pages.windows, &pages.space);
            pages.needed = marks
                .pages()
                .filter(|p| windows.get(p.level as usize).is_some_and(|w| w.index(*p).is_some()) && space.holds(*p))
                .collect();
            pages.update.needed = pages.needed.len() as u32;
            fresh = true;
        }
    }
    l.map.pages = Some(pages);
    fresh
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
    use crate::shadow::{Change, Clipmap, MARK_WORDS, PageMarks};
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
        PageMarks { light: light.to_bits(), seq, space: fit.space, windows, bits }
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
        let marked = marks(&fit, 1, light, 0, &[0, 2080]);
        refresh(&mut pool, &mut map, light, &fit, &how(Some(&marked), &CasterChanges::default()));
        refresh(&mut pool, &mut map, light, &fit, &how(Some(&marked), &CasterChanges::default()));
        // A small box inside the second page's square, seen along the light.
        let (min, max) = clipmap().footprint(window.page(2080));
        let centre = (min + max) * 0.5;
        let world = clipmap().light_from_world.inverse().transform_point3(centre.extend(0.0));
        let moved = CasterChanges { moved: vec![Aabb::new(world - 0.01, world + 0.01)], settled: Vec::new() };
        refresh(&mut pool, &mut map, light, &fit, &how(None, &moved));
        let dirty: Vec<bool> = map.layers.iter().map(|l| l.dirty).collect();
        assert_eq!(dirty, vec![true, false, true], "the coarse map and the page it crossed");
        assert_eq!(map.pages.as_ref().unwrap().update.invalidated, 1);
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

    /// Lights `near` and `far`, `maps` theirs in that order, updated together in a pool of five
    /// slots (the far light given first).
    fn update_two(
        pool: &mut SharedPool,
        maps: &mut [ShadowMap; 2],
        (near, far): (Entity, Entity),
        marked: &MarkedPages,
    ) {
        let (fit, still) = (fit(), CasterChanges::default());
        let [a, b] = maps;
        let mut lights = [PagedLight { light: far, map: b, fit: fit.clone() }, PagedLight { light: near, map: a, fit }];
        refresh_paged(pool, &mut lights, &PagedUpdate { capacity: 5, ..how(Some(marked), &still) });
    }

    #[test]
    fn lights_share_one_pool_and_the_one_that_shows_least_goes_coarser_first() {
        let (fit, still) = (fit(), CasterChanges::default());
        let (near, far) = (Entity::from_bits(42), Entity::from_bits(7));
        let (mut maps, mut pool) = ([ShadowMap::default(), ShadowMap::default()], SharedPool::default());
        let update = |pool: &mut SharedPool, maps: &mut [ShadowMap; 2], marked: &MarkedPages| {
            update_two(pool, maps, (near, far), marked);
        };
        update(&mut pool, &mut maps, &MarkedPages(vec![marks_of(&fit, 1, near, 0, &[0, 1, 2, 3])]));
        // Seven pages of one level asked for in five slots: the light that shows more keeps its
        // pages, the other's go missing, and it alone goes an octave coarser.
        let marked =
            MarkedPages(vec![marks_of(&fit, 2, near, 0, &[0, 1, 2, 3]), marks_of(&fit, 1, far, 0, &[4, 5, 6])]);
        update(&mut pool, &mut maps, &marked);
        let pages = |m: &ShadowMap| m.pages.clone().unwrap();
        assert_eq!((pages(&maps[0]).resident, pages(&maps[1]).resident), (4, 1));
        assert_eq!(pages(&maps[1]).marked.residency.missing, 2);
        assert_eq!((pages(&maps[0]).pressure.octaves, pages(&maps[1]).pressure.octaves), (0, 1));
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
    fn no_light_goes_coarser_for_pages_another_asked_for_before_it_was_marked_again() {
        let fit = fit();
        let (near, far) = (Entity::from_bits(42), Entity::from_bits(7));
        let (mut maps, mut pool) = ([ShadowMap::default(), ShadowMap::default()], SharedPool::default());
        let update = |pool: &mut SharedPool, maps: &mut [ShadowMap; 2], marked: &MarkedPages| {
            update_two(pool, maps, (near, far), marked);
        };
        let octaves = |maps: &[ShadowMap; 2]| maps.each_ref().map(|m| m.pages.as_ref().unwrap().pressure.octaves);
        let first = MarkedPages(vec![marks_of(&fit, 1, near, 0, &[0, 1, 2, 3]), marks_of(&fit, 1, far, 0, &[9])]);
        update(&mut pool, &mut maps, &first);
        let [near_was, far_was] = octaves(&maps);
        // A cut: the far light asks for two new pages while the near one's last marking still
        // holds four slots; the pool is short, but the near light's need is older than that.
        let cut = MarkedPages(vec![marks_of(&fit, 1, near, 0, &[0, 1, 2, 3]), marks_of(&fit, 2, far, 0, &[20, 21])]);
        update(&mut pool, &mut maps, &cut);
        assert_eq!(pool.pages.changes().iter().filter(|(_, c)| *c == Change::Missing).count(), 1);
        assert_eq!(octaves(&maps), [near_was, far_was], "no light is yet known to want for slots");
        // Once the near light has been marked again and still needs its four, the far light,
        // which shows least, gives way at its next marking.
        let again = MarkedPages(vec![marks_of(&fit, 2, near, 0, &[0, 1, 2, 3]), marks_of(&fit, 2, far, 0, &[20, 21])]);
        update(&mut pool, &mut maps, &again);
        assert_eq!(octaves(&maps)[1], far_was, "not marked since");
        let later = MarkedPages(vec![marks_of(&fit, 2, near, 0, &[0, 1, 2, 3]), marks_of(&fit, 3, far, 0, &[20, 21])]);
        update(&mut pool, &mut maps, &later);
        assert_eq!(octaves(&maps), [near_was, far_was + 1]);
    }

    #[test]
    fn what_shows_least_is_counted_coarser_first_until_the_missing_pages_are_freed() {
        // (shows, pages needed, can go coarser)
        let lights = [(0.9, 100, true), (0.1, 10, true), (0.01, 50, false), (0.2, 40, true), (f32::NAN, 9, true)];
        assert_eq!(coarser_first(&lights, 0), [false; 5]);
        assert_eq!(coarser_first(&lights, 5), [false, false, false, false, true], "NaN shows nothing");
        assert_eq!(coarser_first(&lights, 10), [false, true, false, false, true]);
        assert_eq!(coarser_first(&lights, 20), [false, true, false, true, true]);
        assert_eq!(coarser_first(&lights, u32::MAX), [true, true, false, true, true], "all that can");
        assert!(coarser_first(&[], 7).is_empty());
    }

    #[test]
    fn the_lights_that_show_most_have_first_call_on_the_room_to_go_finer() {
        let lights = [(100, true), (40, false), (10, true)];
        assert_eq!(finer_room(512, &lights), [512, 287, 247], "225 then 40 taken");
        assert_eq!(finer_room(100, &lights), [100, 0, 0]);
        assert_eq!(finer_room(0, &lights), [0, 0, 0]);
        assert_eq!(finer_room(u32::MAX, &[(usize::MAX, true), (1, true)]), [u32::MAX, 0], "no overflow");
        assert!(finer_room(9, &[]).is_empty());
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
