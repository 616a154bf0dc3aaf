//! No allocation per sample in the runner's render loop, checked with a
//! counting global allocator (every thread counted): a whole render on 2
//! threads makes no more allocations at 16 samples per pixel than at 1,
//! up to a margin of 64 for rayon's scheduling-dependent internal buffers
//! (an allocation per sample would add over 19 000 here).
//!
//! The core itself cannot allocate: without its `alloc` feature (off by
//! default; the runner does not turn it on) it does not link `alloc` at
//! all (the no_std staticlib check builds it so), so only the runner's
//! loop around it needs this test.
//!
//! The counter counts every thread, so the whole check is one test in its
//! own binary: no other test may run beside it.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use strata_runner::job::{Job, SamplerKind, run};
use strata_runner::scenes::built_in;

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call is forwarded to the system allocator unchanged; the
// counter only observes.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations, on any thread, while `f` runs.
fn allocations_in(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    f();
    ALLOCATIONS.load(Ordering::SeqCst) - before
}

/// Through the runner, on 2 threads: the allocations of a render do not
/// grow with the number of samples.
fn allocations_do_not_grow_with_samples() {
    for name in ["week09", "showcase"] {
        let scene = built_in(name).unwrap();
        let count = |spp: u32| {
            let job = Job {
                max_depth: 8,
                sampler: SamplerKind::Stratified,
                seed: 1,
                ..Job::new(&scene, 48, 27, spp)
            };
            // Once to warm up the thread pool's lazy state, then measured.
            run(&job, &|_| {}).unwrap();
            allocations_in(|| {
                run(&job, &|_| {}).unwrap();
            })
        };
        let (one, many) = (count(1), count(16));
        assert!(
            many <= one + 64,
            "{name}: {one} allocations at 1 spp, {many} at 16"
        );
    }
}

/// The counter works: an allocation inside the measured closure is seen,
/// also on another thread.
fn the_counter_sees_allocations() {
    let here = allocations_in(|| drop(std::hint::black_box(vec![1u64, 2, 3])));
    assert!(here >= 1);
    let there = allocations_in(|| {
        std::thread::scope(|s| {
            s.spawn(|| drop(std::hint::black_box(vec![0u8; 64])));
        });
    });
    assert!(there >= 2, "{there}"); // the thread itself and its vector
}

/// One test, so that nothing else allocates while it counts.
#[test]
fn no_allocation_in_the_per_sample_loop() {
    the_counter_sees_allocations();
    allocations_do_not_grow_with_samples();
}
