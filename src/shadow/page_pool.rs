//! The page pool of a virtual shadow map, as pure bookkeeping: which pages hold a slot, kept
//! from frame to frame while they are needed, the least recently needed given up first when a
//! new page wants a slot and none is free, and what each page's contents are (a version that
//! changes whenever what it must hold changes: it is new, or a caster moved through it).
//!
//! A needed page that finds no slot (every slot holds a page needed as much) is counted missing:
//! its pixels read a coarser level. While the view needs more than the pool holds it asks for
//! coarser levels everywhere, as a renderer lowers its resolution when memory runs short; while
//! it has room to spare it asks for finer ones ([`Pressure`]), so the view gets the sharpest
//! shadow its memory holds.
//!
//! A pool names its pages by a [`PoolKey`]: a [`PageId`] where one map has a pool of its own, a
//! [`LightPage`] where every paged light shares one. Among the pages of one level, the longest
//! waiting comes in first, then those given first (a shared pool's owner gives the pages of the
//! lights that show most first): a light that shows little is the first to find no slot.

use super::pages::PageId;
use std::collections::{HashMap, HashSet};
use std::hash::Hash;

/// What names a page in a pool.
pub trait PoolKey: Copy + Eq + Hash + std::fmt::Debug {
    /// Its level: the coarser come into the pool first (a coarse page serves every pixel under
    /// it).
    fn level(&self) -> u32;
}

impl PoolKey for PageId {
    fn level(&self) -> u32 {
        self.level
    }
}

/// A page of light `light`'s virtual map, as a pool that every light shares names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LightPage {
    /// The light, by a number its owner gives it (the entity's bits).
    pub light: u64,
    /// The page of its map.
    pub page: PageId,
}

impl PoolKey for LightPage {
    fn level(&self) -> u32 {
        self.page.level
    }
}

/// Most octaves the pool's pressure makes every level coarser by.
pub const MAX_PRESSURE: u32 = 4;

/// One page holding a slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Resident<K = PageId> {
    /// The page.
    pub page: K,
    /// Its contents: a new number whenever it must be drawn again.
    pub version: u64,
    /// What its casters at rest draw: a new number when one of them changed.
    pub static_version: u64,
    /// The pool's frame it was last needed in.
    pub needed: u64,
    /// It is new or its version changed since the pool was last [`PagePool::clean`]ed.
    pub dirty: bool,
}

/// What one update of the pool did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Residency {
    /// Pages holding a slot after it.
    pub resident: u32,
    /// Pages given a slot by it.
    pub placed: u32,
    /// Needed pages with no slot: every slot holds a page needed as much.
    pub missing: u32,
    /// Needed pages held back by the limit on new pages a frame (they come in later frames).
    pub waiting: u32,
    /// Pages that gave up their slot to a new one.
    pub evicted: u32,
}

impl Residency {
    /// Counts one page's `change` in.
    pub fn count(&mut self, change: Change) {
        let n = match change {
            Change::Placed => &mut self.placed,
            Change::Missing => &mut self.missing,
            Change::Waiting => &mut self.waiting,
            Change::Evicted => &mut self.evicted,
        };
        *n += 1;
    }
}

/// What the last update did to one page.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Change {
    /// It was given a slot.
    Placed,
    /// It is needed and found no slot.
    Missing,
    /// It is needed and waits its turn to come in.
    Waiting,
    /// It gave up its slot to a new page.
    Evicted,
}

/// Slots and the pages in them.
#[derive(Clone, Debug, PartialEq)]
pub struct PagePool<K: PoolKey = PageId> {
    slots: Vec<Option<Resident<K>>>,
    by_page: HashMap<K, u32>,
    frame: u64,
    /// The frame each needed page without a slot first asked for one.
    since: HashMap<K, u64>,
    /// What the last update did, page by page.
    changes: Vec<(K, Change)>,
}

impl<K: PoolKey> Default for PagePool<K> {
    fn default() -> Self {
        PagePool::new(0)
    }
}

impl<K: PoolKey> PagePool<K> {
    /// A pool of `capacity` empty slots.
    #[must_use]
    pub fn new(capacity: u32) -> PagePool<K> {
        PagePool {
            slots: vec![None; capacity as usize],
            by_page: HashMap::new(),
            frame: 0,
            since: HashMap::new(),
            changes: Vec::new(),
        }
    }

    /// Slots in all.
    #[must_use]
    pub fn capacity(&self) -> u32 {
        self.slots.len() as u32
    }

    /// Pages holding a slot.
    #[must_use]
    pub fn len(&self) -> usize {
        self.by_page.len()
    }

    /// True when no page holds a slot.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.by_page.is_empty()
    }

    /// Gives up every page (what every page holds changed).
    pub fn clear(&mut self) {
        self.release(|_| true);
    }

    /// Gives up every page for which `hit` is true (its light moved, or is gone); returns how many.
    pub fn release(&mut self, hit: impl Fn(K) -> bool) -> u32 {
        let mut released = 0;
        for slot in &mut self.slots {
            if let Some(r) = slot.take_if(|r| hit(r.page)) {
                self.by_page.remove(&r.page);
                released += 1;
            }
        }
        self.since.retain(|k, _| !hit(*k));
        released
    }

    /// What the last [`PagePool::update`] did, page by page: the pages it placed, gave up, left
    /// missing or waiting.
    #[must_use]
    pub fn changes(&self) -> &[(K, Change)] {
        &self.changes
    }

    /// The pages holding slots, with their slots, in slot order.
    pub fn resident(&self) -> impl Iterator<Item = (u32, &Resident<K>)> {
        self.slots.iter().enumerate().filter_map(|(i, s)| s.as_ref().map(|r| (i as u32, r)))
    }

    /// The slot `page` holds, if any.
    #[must_use]
    pub fn slot_of(&self, page: K) -> Option<u32> {
        self.by_page.get(&page).copied()
    }

    /// Marks every page clean: what the last update made dirty has been seen.
    pub fn clean(&mut self) {
        self.slots.iter_mut().flatten().for_each(|r| r.dirty = false);
    }

    /// One frame's needs: every page of `needed` (each once) is kept or given a slot, at most
    /// `admit` of them new, the coarsest levels first (a coarse page serves every pixel under
    /// it), then those that have waited longest, then in the order given; a new page takes a
    /// free slot, else that of the page needed least recently of those not needed now. Pages
    /// not needed keep their slots until one is wanted. `next_version` numbers new contents.
    pub fn update(&mut self, needed: &[K], admit: usize, mut next_version: impl FnMut() -> u64) -> Residency {
        self.frame += 1;
        let frame = self.frame;
        self.changes.clear();
        let mut wanted: Vec<K> = Vec::new();
        let mut seen = HashSet::new();
        for page in needed {
            match self.by_page.get(page) {
                Some(&slot) => {
                    if let Some(r) = self.slots[slot as usize].as_mut() {
                        r.needed = frame;
                    }
                }
                None if seen.insert(*page) => wanted.push(*page),
                None => {}
            }
        }
        // Only the pages still wanted keep their place in the queue.
        self.since.retain(|k, _| seen.contains(k));
        let since = |k: &K| self.since.get(k).copied().unwrap_or(frame);
        wanted.sort_by_key(|k| (std::cmp::Reverse(k.level()), since(k)));
        let mut out = Residency::default();
        // Free slots first, then the least recently needed of those not needed now, oldest first.
        let mut free: Vec<u32> = (0..self.capacity()).filter(|&i| self.slots[i as usize].is_none()).rev().collect();
        let mut old: Vec<(u64, u32)> =
            self.resident().filter(|(_, r)| r.needed < frame).map(|(i, r)| (r.needed, i)).collect();
        old.sort_unstable_by(|a, b| b.cmp(a));
        for (n, page) in wanted.iter().enumerate() {
            let slot = if n >= admit { None } else { free.pop().or_else(|| old.pop().map(|(_, slot)| slot)) };
            let Some(slot) = slot else {
                let change = if n >= admit { Change::Waiting } else { Change::Missing };
                self.changes.push((*page, change));
                self.since.entry(*page).or_insert(frame);
                continue;
            };
            if let Some(gone) = self.slots[slot as usize].take() {
                self.by_page.remove(&gone.page);
                self.changes.push((gone.page, Change::Evicted));
            }
            let version = next_version();
            let static_version = next_version();
            self.slots[slot as usize] =
                Some(Resident { page: *page, version, static_version, needed: frame, dirty: true });
            self.by_page.insert(*page, slot);
            self.since.remove(page);
            self.changes.push((*page, Change::Placed));
        }
        self.changes.iter().for_each(|(_, c)| out.count(*c));
        out.resident = self.by_page.len() as u32;
        out
    }

    /// Gives every resident page for which `hit` is true new contents (something it holds
    /// moved), if the last update needed it; one it did not need gives up its slot instead, so
    /// that no page out of view is drawn again (it is drawn anew if it is needed again). Returns
    /// the pages hit, each with whether it was given new contents (else it gave up its slot).
    pub fn invalidate(&mut self, hit: impl Fn(K) -> bool, mut next_version: impl FnMut() -> u64) -> Vec<(K, bool)> {
        let mut hits = Vec::new();
        for slot in &mut self.slots {
            let Some(r) = slot.as_mut().filter(|r| hit(r.page)) else { continue };
            let kept = r.needed == self.frame;
            hits.push((r.page, kept));
            if kept {
                (r.version, r.dirty) = (next_version(), true);
            } else {
                self.by_page.remove(&r.page);
                *slot = None;
            }
        }
        hits
    }

    /// Gives every resident page for which `hit` is true a new static version (a caster at rest
    /// in it changed).
    pub fn resettle(&mut self, hit: impl Fn(K) -> bool, mut next_version: impl FnMut() -> u64) {
        for r in self.slots.iter_mut().flatten().filter(|r| hit(r.page)) {
            r.static_version = next_version();
        }
    }
}

/// Most octaves finer than the settings ask a pool with room to spare chooses every level.
pub const MAX_FINER: f32 = 4.0;

/// The share of the pool's slots the pressure aims the view's pages at: the rest is room for what
/// a turn of the camera brings in before the next marking.
pub const POOL_FILL: f32 = 0.75;

/// How far (in octaves of pressure) what the view needs may stray from [`POOL_FILL`] before the
/// pressure moves: a smaller move would redraw pages for little (and two markings of one view
/// differ by a few pages).
pub const PRESSURE_SLACK: f32 = 0.15;

/// How much finer or coarser than the settings ask a pool chooses every level: as fine as its
/// slots hold the view's pages, with room to spare.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pressure {
    /// Octaves coarser every level is chosen (negative: finer), -[`MAX_FINER`] to
    /// [`MAX_PRESSURE`], in eighths of an octave.
    pub octaves: f32,
}

impl Pressure {
    /// The pressure after markings at this one needed `needed` pages of a pool with `capacity`
    /// slots: moved by as many octaves as bring `needed` to [`POOL_FILL`] of the slots, at most
    /// one octave a move, none while it is within [`PRESSURE_SLACK`] of it. A move coarser counts
    /// each octave as 2.25 times the pages (2.0 to 2.15 measured on the sample views), so it
    /// frees at least the room it aims at; a move finer counts it as 4 times (the most a level
    /// can grow, twice the pages each way) in whole eighths towards none, so that it never
    /// overshoots into a move back (a view of thin pillars took 1.74 times the pages three
    /// eighths finer, and swung between the two for good). A view that needs nothing (the sky)
    /// says nothing of what finer levels would take.
    #[must_use]
    pub fn next(self, needed: usize, capacity: u32) -> Pressure {
        if needed == 0 {
            return self;
        }
        let over = (needed as f32).ln() - (POOL_FILL * capacity as f32).ln();
        let step = over / if over > 0.0 { 2.25f32 } else { 4.0 }.ln();
        if step.abs() < PRESSURE_SLACK {
            return self;
        }
        let eighths = step.clamp(-1.0, 1.0) * 8.0;
        let eighths = if eighths > 0.0 { eighths.round() } else { eighths.ceil() };
        Pressure { octaves: (self.octaves + eighths / 8.0).clamp(-MAX_FINER, MAX_PRESSURE as f32) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn page(level: u32, x: i32) -> PageId {
        PageId { level, x, y: 0 }
    }

    fn counter() -> impl FnMut() -> u64 {
        let mut n = 0;
        move || {
            n += 1;
            n
        }
    }

    #[test]
    fn needed_pages_are_kept_with_their_versions_and_new_ones_take_free_slots() {
        let mut pool = PagePool::new(4);
        let mut v = counter();
        let r = pool.update(&[page(0, 1), page(0, 2)], usize::MAX, &mut v);
        assert_eq!((r.placed, r.resident, r.missing, r.evicted), (2, 2, 0, 0));
        let before: Vec<Resident> = pool.resident().map(|(_, r)| *r).collect();
        assert!(before.iter().all(|r| r.dirty));
        pool.clean();
        let r = pool.update(&[page(0, 1), page(0, 2)], usize::MAX, &mut v);
        assert_eq!(r.placed, 0);
        let after: Vec<Resident> = pool.resident().map(|(_, r)| *r).collect();
        assert!(after.iter().zip(&before).all(|(a, b)| a.version == b.version && !a.dirty), "kept, clean");
        assert_eq!(pool.slot_of(page(0, 1)), Some(0));
        // Not needed for a while, a page keeps its slot while nothing wants it.
        pool.update(&[], usize::MAX, &mut v);
        assert_eq!(pool.len(), 2);
    }

    #[test]
    fn a_full_pool_gives_up_the_least_recently_needed_and_counts_what_it_cannot_place() {
        let mut pool = PagePool::new(2);
        let mut v = counter();
        pool.update(&[page(0, 1)], usize::MAX, &mut v);
        pool.update(&[page(0, 2)], usize::MAX, &mut v);
        // page 1 was needed longest ago: page 3 takes its slot.
        let r = pool.update(&[page(0, 2), page(0, 3)], usize::MAX, &mut v);
        assert_eq!((r.placed, r.evicted, r.missing), (1, 1, 0));
        assert_eq!(pool.slot_of(page(0, 1)), None);
        assert_eq!(pool.slot_of(page(0, 3)), Some(0));
        // Three needed in two slots: the coarser level is placed, one page is missing.
        let r = pool.update(&[page(0, 2), page(0, 3), page(1, 9)], usize::MAX, &mut v);
        assert_eq!((r.placed, r.missing, r.resident), (0, 1, 2));
        let r = pool.update(&[page(0, 5), page(1, 9)], usize::MAX, &mut v);
        assert_eq!((r.placed, r.missing), (2, 0));
        assert!(pool.slot_of(page(1, 9)).is_some(), "the coarser page first");
    }

    #[test]
    fn at_most_admit_pages_come_in_a_frame_and_the_rest_wait() {
        let mut pool = PagePool::new(16);
        let mut v = counter();
        let needed: Vec<PageId> = (0..10).map(|x| page(0, x)).chain([page(3, 0)]).collect();
        let r = pool.update(&needed, 4, &mut v);
        assert_eq!((r.placed, r.waiting, r.missing), (4, 7, 0));
        assert!(pool.slot_of(page(3, 0)).is_some(), "coarsest first");
        let r = pool.update(&needed, 4, &mut v);
        assert_eq!((r.placed, r.waiting), (4, 3));
        let r = pool.update(&needed, 4, &mut v);
        assert_eq!((r.placed, r.waiting, r.resident), (3, 0, 11));
        // Duplicates count once; no slots at all means every page is missing.
        let r = pool.update(&[page(5, 5), page(5, 5)], usize::MAX, &mut v);
        assert_eq!(r.placed, 1);
        let r = PagePool::new(0).update(&needed, usize::MAX, &mut v);
        assert_eq!((r.placed, r.missing), (0, 11));
    }

    #[test]
    fn invalidating_gives_new_contents_only_to_the_pages_hit() {
        let mut pool = PagePool::new(4);
        let mut v = counter();
        pool.update(&[page(0, 1), page(0, 2)], usize::MAX, &mut v);
        pool.clean();
        let before: Vec<u64> = pool.resident().map(|(_, r)| r.version).collect();
        assert_eq!(pool.invalidate(|p| p.x == 2, &mut v), [(page(0, 2), true)]);
        let after: Vec<(u64, bool)> = pool.resident().map(|(_, r)| (r.version, r.dirty)).collect();
        assert_eq!(after[0], (before[0], false));
        assert!(after[1].0 != before[1] && after[1].1);
        let statics: Vec<u64> = pool.resident().map(|(_, r)| r.static_version).collect();
        pool.resettle(|p| p.x == 1, &mut v);
        assert_ne!(pool.resident().next().unwrap().1.static_version, statics[0]);
        // A page the last marking did not need gives up its slot rather than be drawn again.
        pool.update(&[page(0, 1)], usize::MAX, &mut v);
        assert_eq!(pool.invalidate(|_| true, &mut v), [(page(0, 1), true), (page(0, 2), false)]);
        assert_eq!((pool.len(), pool.slot_of(page(0, 2))), (1, None));
        pool.clear();
        assert!(pool.is_empty() && pool.resident().next().is_none());
    }

    #[test]
    fn lights_sharing_a_pool_keep_the_same_page_of_each_apart() {
        let mut pool: PagePool<LightPage> = PagePool::new(3);
        let mut v = counter();
        let (sun, spot) = (LightPage { light: 0, page: page(0, 1) }, LightPage { light: 7, page: page(0, 1) });
        let lantern = LightPage { light: 3, page: page(2, 0) };
        let r = pool.update(&[spot, sun, lantern], 2, &mut v);
        assert_eq!((r.placed, r.waiting), (2, 1));
        assert!(pool.slot_of(lantern).is_some(), "the coarsest first, whichever light it is");
        assert!(pool.slot_of(spot).is_some() && pool.slot_of(sun).is_none(), "then in the order given");
        assert_eq!(pool.changes().iter().filter(|(_, c)| *c == Change::Waiting).count(), 1);
        assert!(pool.changes().contains(&(sun, Change::Waiting)));
        pool.update(&[spot, sun, lantern], usize::MAX, &mut v);
        pool.clean();
        assert_eq!(pool.invalidate(|k| k.light == 7, &mut v), [(spot, true)], "the spot's page, not the sun's");
        let dirty: Vec<u64> = pool.resident().filter(|(_, r)| r.dirty).map(|(_, r)| r.page.light).collect();
        assert_eq!(dirty, [7]);
        // A light that moved gives up its pages, and only its.
        assert_eq!(pool.release(|k| k.light == 3), 1);
        assert_eq!((pool.len(), pool.slot_of(lantern)), (2, None));
    }

    #[test]
    fn the_longest_waiting_page_of_a_level_comes_in_first_and_each_change_is_told() {
        let mut pool = PagePool::new(8);
        let mut v = counter();
        let r = pool.update(&[page(0, 1), page(0, 2)], 1, &mut v);
        assert_eq!(pool.changes(), [(page(0, 1), Change::Placed), (page(0, 2), Change::Waiting)]);
        assert_eq!((r.placed, r.waiting), (1, 1));
        // Given first now, page 3 still comes after page 2, which has waited a frame.
        pool.update(&[page(0, 3), page(0, 2)], 1, &mut v);
        assert!(pool.slot_of(page(0, 2)).is_some() && pool.slot_of(page(0, 3)).is_none());
        // A page no longer needed leaves the queue: asked for again, it starts at the back.
        pool.update(&[page(0, 4)], 1, &mut v);
        pool.update(&[page(0, 5), page(0, 3)], 1, &mut v);
        assert!(pool.slot_of(page(0, 5)).is_some(), "page 3 left the queue when page 4 came in");
        // Full, a new page takes the slot of the one needed longest ago, and says so.
        let mut full = PagePool::new(1);
        full.update(&[page(0, 1)], usize::MAX, &mut v);
        let r = full.update(&[page(0, 2)], usize::MAX, &mut v);
        assert_eq!(r.evicted, 1);
        assert_eq!(full.changes(), [(page(0, 1), Change::Evicted), (page(0, 2), Change::Placed)]);
    }

    #[test]
    fn pressure_moves_the_pages_towards_three_quarters_of_the_pool_an_octave_at_most() {
        let p = Pressure::default();
        // 384 slots are three quarters of 512: 600 pages want half an octave coarser (600 / 384
        // is 2.25^0.55), 100 pages seven eighths finer (384 / 100 is 4^0.97), 20 pages an octave
        // at most (2.1 octaves would bring them there).
        assert_eq!(p.next(600, 512).octaves, 0.5);
        assert_eq!(p.next(100, 512).octaves, -0.875);
        assert_eq!(p.next(20, 512).octaves, -1.0);
        assert_eq!(p.next(400, 512), p, "within the slack");
        assert_eq!(p.next(5000, 512).octaves, 1.0, "an octave a move");
        let most = Pressure { octaves: MAX_PRESSURE as f32 };
        assert_eq!(most.next(600, 512), most);
        let finest = Pressure { octaves: -MAX_FINER };
        assert_eq!(finest.next(1, 512), finest);
        assert_eq!(p.next(0, 512), p, "the sky asks for nothing finer");
        assert_eq!(p.next(0, 0), p);
        assert_eq!(p.next(3, 0).octaves, 1.0, "no slots: coarser");
        assert_eq!(p.next(usize::MAX, u32::MAX).octaves, 1.0, "huge counts are no trouble");
        // Moved by a marking at the pressure it set, it settles: 600 pages become about 384.
        let settled = p.next(600, 512);
        assert_eq!(settled.next((600.0 / 2.25f32.powf(0.5)) as usize, 512), settled);
    }

    #[test]
    fn pressure_comes_to_rest_however_steeply_a_view_grows_finer() {
        // A view needing `start` pages at no pressure and `growth` times as many an octave finer.
        for growth in [1.5f32, 2.25, 4.4, 6.0] {
            for start in [50.0f32, 1166.0, 2029.0, 8000.0] {
                let needed = |p: Pressure| (start * growth.powf(-p.octaves)) as usize;
                let mut p = Pressure::default();
                let mut seen = Vec::new();
                for _ in 0..24 {
                    p = p.next(needed(p), 2048);
                    seen.push(p);
                }
                assert!(seen[12..].iter().all(|q| *q == p), "{growth}, {start}: {seen:?}");
                assert!(needed(p) <= 2048, "{growth}, {start}: at rest it fits ({p:?})");
            }
        }
    }
}
