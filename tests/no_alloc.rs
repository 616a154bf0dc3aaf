//! No allocation inside the per-sample loop: `render_tile` on the built-in
//! scenes (every material, lights, image textures, the 485-sphere cover)
//! performs zero heap allocations, counted by a global allocator that
//! tallies the calling thread's allocations while a render runs. (How
//! the claim of `strata bench` is checked.)

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use strata::render::{Camera, PixelSum, RenderSettings, Tile, render_tile};
use strata::{Independent, Sampler, Stratified};
use strata_runner::scenes::{BUILT_IN, built_in};

struct Counting;

// Both per thread: tests run in parallel, and another test's allocations
// must not count here.
thread_local! {
    static MEASURING: Cell<bool> = const { Cell::new(false) };
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn note() {
    if MEASURING.with(Cell::get) {
        ALLOCATIONS.with(|a| a.set(a.get() + 1));
    }
}

// SAFETY: every call is forwarded to the system allocator unchanged; the
// counter only observes.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note();
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note();
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations `f` makes on this thread.
fn allocations_in(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.with(Cell::get);
    MEASURING.with(|m| m.set(true));
    f();
    MEASURING.with(|m| m.set(false));
    ALLOCATIONS.with(Cell::get) - before
}

fn check<S: Sampler + Clone>(name: &str, sampler: S) {
    let data = built_in(name).unwrap();
    let camera = Camera::new(&data.camera, 64, 36).unwrap();
    let settings = RenderSettings {
        max_depth: data.defaults.max_depth,
        direct_lighting: true,
    };
    let tile = Tile {
        x0: 8,
        y0: 4,
        width: 24,
        height: 16,
    };
    let mut film = vec![PixelSum::ZERO; tile.area()];
    let (count, stats) = data
        .with_scene(|scene| {
            let mut stats = None;
            let count = allocations_in(|| {
                stats = Some(render_tile(
                    scene,
                    &camera,
                    &sampler,
                    &settings,
                    tile,
                    0..8,
                    &mut film,
                ));
            });
            (count, stats.unwrap().unwrap())
        })
        .unwrap();
    assert!(stats.rays > 0);
    assert_eq!(
        count, 0,
        "{name}: {count} allocations while rendering {stats:?}"
    );
}

#[test]
fn render_tile_never_allocates() {
    for name in BUILT_IN {
        check(name, Independent::new(8, 1).unwrap());
        check(name, Stratified::new(8, 1).unwrap());
    }
}

/// The counter works: an allocation inside the measured closure is seen.
#[test]
fn the_counter_sees_allocations() {
    let n = allocations_in(|| {
        let v: Vec<u64> = std::hint::black_box(vec![1, 2, 3]);
        drop(v);
    });
    assert_eq!(n, 1);
}
