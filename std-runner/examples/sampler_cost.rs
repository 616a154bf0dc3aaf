//! The sampler workload of `strata bench` (sampling / sampler) as a
//! program, for instruction counters such as callgrind, which a timed
//! suite cannot run under:
//!
//! ```sh
//! cargo run --release -p strata-runner --example sampler_cost -- sobol 100
//! ```
//!
//! runs `sampler_pattern` (16 × 16 pixels at 16 spp, 14 dimensions per
//! pixel sample) the given number of times with the named sampler. Two
//! counts give the marginal cost: the difference of the instruction totals
//! over the difference of pixel samples (`256 · 16` per run).

use strata::{Halton, Independent, Sampler, Sobol, Stratified, UniformGrid, ZSobol};
use strata_runner::workload::sampler_pattern;

const SPP: u32 = 16;

fn runs<S: Sampler>(mut s: S, n: u32) -> f32 {
    (0..n).map(|_| sampler_pattern(&mut s, SPP)).sum()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(kind), Some(n)) = (
        args.first(),
        args.get(1).and_then(|n| n.parse::<u32>().ok()),
    ) else {
        eprintln!("usage: sampler_cost independent|grid|stratified|sobol|halton|zsobol RUNS");
        std::process::exit(2);
    };
    let sum = match kind.as_str() {
        "independent" => Independent::new(SPP, 1).map(|s| runs(s, n)),
        "grid" => UniformGrid::new(SPP, 1).map(|s| runs(s, n)),
        "stratified" => Stratified::new(SPP, 1).map(|s| runs(s, n)),
        "sobol" => Sobol::new(SPP, 1).map(|s| runs(s, n)),
        "halton" => Halton::new(SPP, 1).map(|s| runs(s, n)),
        // The bench's 16 × 16 pixels as the image.
        "zsobol" => ZSobol::new(SPP, 1, glam::UVec2::splat(16))
            .ok()
            .map(|s| runs(s, n)),
        _ => None,
    };
    match sum {
        Some(sum) => println!("{kind} x {n}: checksum {sum}"),
        None => {
            eprintln!("unknown sampler `{kind}`");
            std::process::exit(2);
        }
    }
}
