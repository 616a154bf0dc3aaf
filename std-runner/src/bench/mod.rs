//! `strata bench`: a fixed, documented throughput suite.
//!
//! - **sampling**: samples/s of every mapping (on precomputed `u`), of the
//!   disk and sphere by analytic maps vs the course's rejection loops (each
//!   drawing from a PCG32 inside the timed loop), pixel samples/s of
//!   each sampler along a depth-2 path's dimensions (reported), and what a
//!   `week09` render costs with each sampler against the independent one
//!   (judged), beside a must-fail control (`Slowed`);
//! - **intersection**: rays/s and ray–sphere tests/s, scalar vs 1×8 vs
//!   packet, on the course (4 spheres) and cover (485) layouts, coherent
//!   camera rays and incoherent random rays, closest hit and shadow rays;
//! - **rendering**: camera paths/s and rays/s of `week09` (320 × 180, 32
//!   spp, depth 5) and `cover` (320 × 180, 8 spp, depth 50) on 1 and 2
//!   threads, timed by the render itself (tracing only, not building the
//!   scene's structures or the thread pool), with the CPU seconds per wall
//!   second of the 2-thread runs, so a busy neighbour shows.
//!
//! `--group` runs one of the groups; `examples/sampler_cost.rs` runs the
//! sampler workload alone, for instruction counters.
//!
//! Method: each comparison's contenders run interleaved, one after the
//! other (forwards, then backwards in the next repetition), in every
//! repetition: one warm-up repetition, then `repetitions` timed ones. Each timing repeats its work until it lasts at least
//! `min_time`. A figure is the median over repetitions with its min–max
//! spread; a ratio (packet/scalar, 2 threads/1 thread) is the median of
//! the per-repetition ratios, so both sides of a ratio share a repetition's
//! machine state.

pub(crate) mod harness;
mod suite;

pub use harness::{
    Figure, Goal, Group, MIN_JUDGED_CORES, Options, PACKET_TARGET, RENDER_COST,
    RENDER_COST_CONTROL, RENDER_COST_TARGETS, Ratio, Report, Stat, Target, Verdict, cpu_model,
    process_cpu_seconds, table, target,
};
pub use suite::{COMPARISONS, run_suite};
