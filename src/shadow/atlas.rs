//! The shadow atlas's bookkeeping, with no GPU in it: pages of one texture array, each a
//! quadtree of power-of-two square tiles (a buddy allocator, as Godot's shadow atlas cuts its
//! quadrants), and the placement of every layer of every light in them, kept from frame to frame
//! while a layer keeps its size.

use std::collections::HashMap;
use std::hash::Hash;

/// The page side an atlas takes unless a layer needs larger: 4096² texels, within every WebGPU
/// device's 8192 limit.
pub const MAX_PAGE: u32 = 4096;
/// The smallest tile a layer takes.
pub const MIN_TILE: u32 = 32;

/// How big the atlas is: `pages` square pages of `page` texels a side.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AtlasShape {
    /// Texels along a page's side (a power of two).
    pub page: u32,
    /// Pages in the array.
    pub pages: u32,
}

impl AtlasShape {
    /// The largest atlas whose texels, at `bytes_per_texel` each (every map kept per texel:
    /// depth, its static copy, a colour map), fit in `budget` bytes: as many pages of `page`
    /// texels a side as fit (at most 256), or of the largest power of two under it one of which
    /// fits (never smaller than a [`MIN_TILE`]).
    #[must_use]
    pub fn for_budget(budget: u64, bytes_per_texel: u32, page: u32) -> AtlasShape {
        let texels = budget / u64::from(bytes_per_texel.max(1));
        let mut page = page.clamp(MIN_TILE, 1 << 15).next_power_of_two();
        while page > MIN_TILE && u64::from(page) * u64::from(page) > texels {
            page /= 2;
        }
        let pages = (texels / (u64::from(page) * u64::from(page))).clamp(1, 256) as u32;
        AtlasShape { page, pages }
    }

    /// The smallest atlas within this one that holds `texels` of tiles: one page, the smallest
    /// power of two that is enough (never smaller than the `largest` tile), or where one of its
    /// pages is not enough, the fewest that hold them with a quarter to spare (for tiles kept
    /// where they are as others come and go).
    #[must_use]
    pub fn holding(self, texels: u64, largest: u32) -> AtlasShape {
        let area = |side: u32| u64::from(side) * u64::from(side);
        let mut page = self.page;
        while page / 2 >= largest.max(MIN_TILE) && area(page / 2) >= texels {
            page /= 2;
        }
        let want = if texels <= area(page) { texels } else { texels.saturating_add(texels / 4) };
        let pages = want.div_ceil(area(page)).clamp(1, u64::from(self.pages)) as u32;
        AtlasShape { page, pages }
    }

    /// Texels in all.
    #[must_use]
    pub fn texels(&self) -> u64 {
        u64::from(self.page) * u64::from(self.page) * u64::from(self.pages)
    }

    /// Levels of its quadtrees: the page is level 0, a [`MIN_TILE`] tile the last.
    fn levels(&self) -> u32 {
        (self.page / MIN_TILE).max(1).ilog2() + 1
    }
}

/// A square of texels in the atlas: its page, its corner and its side.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Tile {
    /// Page (layer of the array).
    pub page: u32,
    /// Column of its first texel.
    pub x: u32,
    /// Row of its first texel.
    pub y: u32,
    /// Texels along its side.
    pub size: u32,
}

/// The pages of `tiles`, each once, in order.
#[must_use]
pub fn distinct_pages(tiles: impl Iterator<Item = Tile>) -> Vec<u32> {
    let mut pages: Vec<u32> = tiles.map(|t| t.page).collect();
    pages.sort_unstable();
    pages.dedup();
    pages
}

/// A quadtree node's state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Node {
    Free,
    Split,
    Used,
}

/// One page's quadtree, level after level (level `l` holds `4^l` nodes, row by row).
#[derive(Clone, Debug)]
struct Page {
    nodes: Vec<Node>,
}

fn level_start(level: u32) -> usize {
    ((1usize << (2 * level)) - 1) / 3
}

impl Page {
    fn new(levels: u32) -> Page {
        Page { nodes: vec![Node::Free; level_start(levels)] }
    }

    fn index(level: u32, x: u32, y: u32) -> usize {
        level_start(level) + ((y as usize) << level) + x as usize
    }

    /// A free node at level `target` under (`level`, `x`, `y`), preferring nodes already split
    /// (so whole free quadrants stay whole for large tiles), marked used.
    fn take(&mut self, (level, x, y): (u32, u32, u32), target: u32) -> Option<(u32, u32)> {
        let i = Self::index(level, x, y);
        match self.nodes[i] {
            Node::Used => None,
            Node::Free if level == target => {
                self.nodes[i] = Node::Used;
                Some((x, y))
            }
            Node::Split if level == target => None,
            state => {
                let children = [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(dx, dy)| (level + 1, 2 * x + dx, 2 * y + dy));
                if state == Node::Free {
                    self.nodes[i] = Node::Split;
                    return self.take(children[0], target);
                }
                let split = children.iter().filter(|c| self.nodes[Self::index(c.0, c.1, c.2)] == Node::Split);
                let free = children.iter().filter(|c| self.nodes[Self::index(c.0, c.1, c.2)] == Node::Free);
                let order: Vec<(u32, u32, u32)> = split.chain(free).copied().collect();
                order.into_iter().find_map(|c| self.take(c, target))
            }
        }
    }

    /// Frees node (`level`, `x`, `y`) and merges every parent whose four children are free.
    fn give_back(&mut self, (mut level, mut x, mut y): (u32, u32, u32)) {
        self.nodes[Self::index(level, x, y)] = Node::Free;
        while level > 0 {
            let (px, py) = (x / 2, y / 2);
            let siblings =
                [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(dx, dy)| Self::index(level, 2 * px + dx, 2 * py + dy));
            if siblings.iter().any(|&s| self.nodes[s] != Node::Free) {
                break;
            }
            (level, x, y) = (level - 1, px, py);
            self.nodes[Self::index(level, x, y)] = Node::Free;
        }
    }
}

/// The atlas's pages and which layer holds which tile.
#[derive(Clone, Debug)]
pub struct Atlas<K> {
    shape: AtlasShape,
    pages: Vec<Page>,
    placed: HashMap<K, Tile>,
}

/// Where one wanted layer went.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Placed {
    /// Its tile, or none when the atlas could not hold it.
    pub tile: Option<Tile>,
    /// It has a tile it did not have last time (its map must be drawn afresh).
    pub moved: bool,
}

impl<K: Copy + Eq + Hash> Atlas<K> {
    /// An empty atlas of `shape`.
    #[must_use]
    pub fn new(shape: AtlasShape) -> Self {
        let levels = shape.levels();
        Atlas { shape, pages: (0..shape.pages).map(|_| Page::new(levels)).collect(), placed: HashMap::new() }
    }

    /// Its shape.
    #[must_use]
    pub fn shape(&self) -> AtlasShape {
        self.shape
    }

    /// The level of a tile of side `size` (rounded up to a power of two within the page).
    fn level_of(&self, size: u32) -> u32 {
        let size = size.clamp(MIN_TILE, self.shape.page).next_power_of_two().min(self.shape.page);
        (self.shape.page / size).ilog2()
    }

    fn allocate(&mut self, size: u32) -> Option<Tile> {
        let level = self.level_of(size);
        let side = self.shape.page >> level;
        self.pages.iter_mut().enumerate().find_map(|(p, page)| {
            page.take((0, 0, 0), level).map(|(x, y)| Tile { page: p as u32, x: x * side, y: y * side, size: side })
        })
    }

    fn release(&mut self, tile: Tile) {
        let level = self.level_of(tile.size);
        if let Some(page) = self.pages.get_mut(tile.page as usize) {
            page.give_back((level, tile.x / tile.size, tile.y / tile.size));
        }
    }

    /// Places every wanted layer (its key and its side in texels, a power of two), in order:
    /// a layer that had a tile of that size keeps it; the others take new tiles, largest first.
    /// When the free space is too broken up for them, every tile is placed afresh (all move).
    /// Layers the atlas cannot hold at all get none. Keys not wanted give their tiles back.
    pub fn place(&mut self, wanted: &[(K, u32)]) -> Vec<Placed> {
        let sizes: HashMap<K, u32> = wanted.iter().map(|&(k, s)| (k, self.shape.page >> self.level_of(s))).collect();
        let gone: Vec<(K, Tile)> =
            self.placed.iter().filter(|(k, t)| sizes.get(k) != Some(&t.size)).map(|(k, t)| (*k, *t)).collect();
        for (k, tile) in gone {
            self.placed.remove(&k);
            self.release(tile);
        }
        let mut new: Vec<K> = wanted.iter().map(|(k, _)| *k).filter(|k| !self.placed.contains_key(k)).collect();
        new.sort_by_key(|k| std::cmp::Reverse(sizes[k]));
        new.dedup();
        let mut fresh = Vec::new();
        for k in &new {
            match self.allocate(sizes[k]) {
                Some(tile) => {
                    self.placed.insert(*k, tile);
                    fresh.push(*k);
                }
                None => {
                    self.repack(wanted, &sizes);
                    return wanted
                        .iter()
                        .map(|(k, _)| Placed { tile: self.placed.get(k).copied(), moved: true })
                        .collect();
                }
            }
        }
        wanted.iter().map(|(k, _)| Placed { tile: self.placed.get(k).copied(), moved: fresh.contains(k) }).collect()
    }

    /// Every tile given back, and every wanted layer placed again, largest first.
    fn repack(&mut self, wanted: &[(K, u32)], sizes: &HashMap<K, u32>) {
        *self = Atlas::new(self.shape);
        let mut order: Vec<K> = wanted.iter().map(|(k, _)| *k).collect();
        order.sort_by_key(|k| std::cmp::Reverse(sizes[k]));
        order.dedup();
        for k in order {
            if let Some(tile) = self.allocate(sizes[&k]) {
                self.placed.insert(k, tile);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_atlas_takes_the_pages_its_tiles_need_and_no_more_than_its_budget() {
        let budget = AtlasShape { page: 4096, pages: 8 };
        let big = 4096 * 4096;
        assert_eq!(budget.holding(2 * big, 2048), AtlasShape { page: 4096, pages: 3 }, "a quarter to spare");
        assert_eq!(budget.holding(100 * big, 2048), budget, "never past the budget");
        assert_eq!(budget.holding(2048 * 2048, 2048), AtlasShape { page: 2048, pages: 1 }, "one tile, one page");
        assert_eq!(budget.holding(2 * 2048 * 2048, 2048), AtlasShape { page: 4096, pages: 1 });
        assert_eq!(budget.holding(3 * 1024 * 1024, 1024), AtlasShape { page: 2048, pages: 1 }, "a smaller page");
        assert_eq!(budget.holding(0, 0), AtlasShape { page: MIN_TILE, pages: 1 });
        assert_eq!(budget.holding(u64::MAX, u32::MAX), budget);
    }

    fn overlap(a: &Tile, b: &Tile) -> bool {
        a.page == b.page && a.x < b.x + b.size && b.x < a.x + a.size && a.y < b.y + b.size && b.y < a.y + a.size
    }

    fn check(shape: AtlasShape, placed: &[Placed]) {
        let tiles: Vec<Tile> = placed.iter().filter_map(|p| p.tile).collect();
        for (i, a) in tiles.iter().enumerate() {
            assert!(a.x + a.size <= shape.page && a.y + a.size <= shape.page && a.page < shape.pages, "{a:?}");
            assert_eq!((a.x % a.size, a.y % a.size), (0, 0), "{a:?} is aligned to its size");
            for b in &tiles[i + 1..] {
                assert!(!overlap(a, b), "{a:?} and {b:?} overlap");
            }
        }
    }

    #[test]
    fn budgets_give_pages_of_the_largest_side_that_fits() {
        let mib = 1u64 << 20;
        assert_eq!(AtlasShape::for_budget(256 * mib, 8, MAX_PAGE), AtlasShape { page: 4096, pages: 2 });
        assert_eq!(AtlasShape::for_budget(256 * mib, 4, MAX_PAGE), AtlasShape { page: 4096, pages: 4 });
        assert_eq!(AtlasShape::for_budget(32 * mib, 8, MAX_PAGE), AtlasShape { page: 2048, pages: 1 });
        assert_eq!(AtlasShape::for_budget(16 * mib, 8, MAX_PAGE), AtlasShape { page: 1024, pages: 2 });
        assert_eq!(AtlasShape::for_budget(1024 * mib, 8, 8192), AtlasShape { page: 8192, pages: 2 });
        assert_eq!(AtlasShape::for_budget(0, 8, MAX_PAGE), AtlasShape { page: MIN_TILE, pages: 1 });
        assert_eq!(AtlasShape::for_budget(u64::MAX, 0, u32::MAX).pages, 256);
        for budget in [mib, 7 * mib, 100 * mib, 1000 * mib] {
            let shape = AtlasShape::for_budget(budget, 12, MAX_PAGE);
            assert!(shape.texels() * 12 <= budget, "{budget}: {shape:?}");
        }
    }

    #[test]
    fn tiles_never_overlap_and_fill_a_page_exactly() {
        let shape = AtlasShape { page: 1024, pages: 1 };
        let mut atlas = Atlas::new(shape);
        // 3 of 512, 8 of 128 and 32 of 64 fill 1024² exactly.
        let wanted: Vec<(u32, u32)> = (0..43)
            .map(|k| {
                (
                    k,
                    if k < 3 {
                        512
                    } else if k < 11 {
                        128
                    } else {
                        64
                    },
                )
            })
            .collect();
        let placed = atlas.place(&wanted);
        assert!(placed.iter().all(|p| p.tile.is_some() && p.moved));
        check(shape, &placed);
        let more = atlas.place(&[wanted.clone(), vec![(99, 32)]].concat());
        assert_eq!(more.last().unwrap().tile, None, "nothing is left for a 44th tile");
    }

    #[test]
    fn a_layer_keeps_its_tile_while_it_keeps_its_size() {
        let shape = AtlasShape { page: 2048, pages: 2 };
        let mut atlas = Atlas::new(shape);
        let first = atlas.place(&[(1, 1024), (2, 256), (3, 256), (4, 2048)]);
        check(shape, &first);
        // 3 goes, 2 grows, 5 comes: 1 and 4 stay where they were.
        let second = atlas.place(&[(1, 1024), (2, 512), (4, 2048), (5, 128)]);
        check(shape, &second);
        assert_eq!((second[0].tile, second[0].moved), (first[0].tile, false));
        assert_eq!((second[2].tile, second[2].moved), (first[3].tile, false));
        assert!(second[1].moved && second[1].tile.unwrap().size == 512);
        assert!(second[3].moved);
        // Sizes are rounded up to powers of two within MIN_TILE and the page.
        let odd = atlas.place(&[(7, 3), (8, 100_000), (9, 300)]);
        let sizes: Vec<u32> = odd.iter().map(|p| p.tile.unwrap().size).collect();
        assert_eq!(sizes, vec![MIN_TILE, 2048, 512]);
    }

    #[test]
    fn a_broken_up_atlas_is_packed_afresh_rather_than_refusing_what_fits() {
        let shape = AtlasShape { page: 256, pages: 1 };
        let mut atlas = Atlas::new(shape);
        // Four quadrants of 128, then two given back and one asked for: it takes a free one and
        // the kept ones stay.
        atlas.place(&[(0, 128), (1, 128), (2, 128), (3, 128)]);
        let kept = atlas.place(&[(0, 128), (2, 128), (5, 128)]);
        assert!(!kept[0].moved && !kept[1].moved && kept[2].moved);
        // Eight 64s where only 128-size holes are: they fit once the holes are split.
        let many: Vec<(u32, u32)> = (10..18).map(|k| (k, 64)).chain([(0, 128), (2, 128)]).collect();
        let placed = atlas.place(&many);
        assert!(placed.iter().all(|p| p.tile.is_some()));
        check(shape, &placed);
    }
}
