//! What loading a model costs in memory, measured (not timed) with a counting allocator: a file
//! of 100,000 nodes instancing one mesh stays far inside the budget, and one of 300,000 nodes
//! is refused before it is built.

mod common;

use common::gltf::TestModel;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use umbra::assets::{MAX_DECODED_BYTES, MAX_OBJECTS, parse_model};

/// The system allocator, keeping count of the bytes held and the most ever held.
struct Counting;

static HELD: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grew(by: usize) {
    let now = HELD.fetch_add(by, Ordering::Relaxed) + by;
    PEAK.fetch_max(now, Ordering::Relaxed);
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }
    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        unsafe { System.dealloc(p, layout) };
        HELD.fetch_sub(layout.size(), Ordering::Relaxed);
    }
    unsafe fn realloc(&self, p: *mut u8, layout: Layout, size: usize) -> *mut u8 {
        let q = unsafe { System.realloc(p, layout, size) };
        if !q.is_null() {
            HELD.fetch_sub(layout.size(), Ordering::Relaxed);
            grew(size);
        }
        q
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// Runs `f` and returns its result with the most bytes held above the start while it ran.
fn peak_of<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let base = HELD.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let out = f();
    (out, PEAK.load(Ordering::Relaxed) - base)
}

/// The test column drawn rigid by `n` more nodes, each placed apart, as .gltf text.
fn instances(n: usize) -> Vec<u8> {
    TestModel::instanced(n).gltf_embedded()
}

// One test, so that no other test's allocations land in the counts.
#[test]
fn node_trees_cost_little_and_too_many_nodes_are_refused_at_once() {
    let file = instances(100_000);
    let (model, peak) = peak_of(|| parse_model(&file, None, "many.gltf").unwrap());
    assert_eq!(model.parts.len(), 100_001);
    let held = HELD.load(Ordering::Relaxed);
    drop(model);
    let kept = held - HELD.load(Ordering::Relaxed);
    eprintln!(
        "100,000 instancing nodes ({} MB of .gltf): peak {:.1} MB while loading, {:.1} MB kept ({} bytes a node)",
        file.len() / 1_000_000,
        peak as f64 / 1e6,
        kept as f64 / 1e6,
        kept / 100_001
    );
    assert!(peak < (MAX_DECODED_BYTES / 4) as usize, "peak {peak} bytes: well under the budget");
    assert!(kept / 100_001 < 1000, "{} bytes a node", kept / 100_001);

    let file = instances(300_000);
    let (result, peak) = peak_of(|| parse_model(&file, None, "too-many.gltf"));
    let err = result.unwrap_err().to_string();
    assert!(err.contains("of them nodes") && err.contains(&format!("at most {MAX_OBJECTS}")), "{err}");
    eprintln!("300,000 nodes ({} MB): refused with a peak of {:.1} MB", file.len() / 1_000_000, peak as f64 / 1e6);
    assert!(peak < 1 << 20, "refused before anything is built: peak {peak} bytes");
}
