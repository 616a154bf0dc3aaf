"""Strata's engines against SciPy's, and a Python batch call against the
core's per-sample Rust API, side by side (one thread on each side).

    python benchmarks/samplers.py            # n = 2^16, d = 2 and 32, 9 rounds
    python benchmarks/samplers.py --quick    # 3 rounds (CI: checks it runs)

Each comparison runs its two sides in turns (A, B, A, B, ...) and reports
the median values per second of each and their ratio. Speed is reported,
never asserted; the values are: the batch call and the per-sample Rust
loop must draw the same bits (their checksums are compared).
"""

import argparse
import os
import statistics
import time

import numpy as np
from scipy.stats import qmc

import strata
from strata import _strata


def timed(f):
    t = time.perf_counter()
    f()
    return time.perf_counter() - t


def interleaved(rounds, a, b):
    """Median seconds of `a` and of `b`, run in turns."""
    ta, tb = [], []
    for _ in range(rounds):
        ta.append(a())
        tb.append(b())
    return statistics.median(ta), statistics.median(tb)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--rounds", type=int, default=9)
    args = ap.parse_args()
    rounds = 3 if args.quick else args.rounds
    n = 1 << 16
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})  # one CPU: one thread each side
    print(f"strata {strata.__version__} ({strata.simd_level()}), one thread, n = {n}, {rounds} rounds\n")

    print("engine against SciPy (values per second, median; ratio = Strata / SciPy)")
    pairs = [
        ("Sobol'", lambda d, s: strata.Sobol(d, seed=s), lambda d, s: qmc.Sobol(d, scramble=True, rng=s)),
        ("Halton", lambda d, s: strata.Halton(d, seed=s), lambda d, s: qmc.Halton(d, scramble=True, rng=s)),
    ]
    for name, ours, theirs in pairs:
        for d in (2, 32):
            a, b = interleaved(
                rounds,
                lambda: timed(lambda: ours(d, 1).random(n)),
                lambda: timed(lambda: theirs(d, 1).random(n)),
            )
            va, vb = n * d / a, n * d / b
            print(f"  {name:7s} d={d:2d}: Strata {va / 1e6:8.1f} M/s, SciPy {vb / 1e6:8.1f} M/s, ratio {va / vb:6.2f}")

    a, b = interleaved(
        rounds,
        lambda: timed(lambda: strata.Independent(32, seed=1).random(n)),
        lambda: timed(lambda: np.random.default_rng(1).random((n, 32))),
    )
    print(f"  Independent d=32: Strata {n * 32 / a / 1e6:8.1f} M/s, numpy Generator.random {n * 32 / b / 1e6:8.1f} M/s")

    # L2-star discrepancy of Sobol(2) at n = 2^10, mean over 32 seeds.
    ours = np.mean([qmc.discrepancy(strata.Sobol(2, seed=s).random(1024), method="L2-star") for s in range(32)])
    theirs = np.mean([qmc.discrepancy(qmc.Sobol(2, rng=s).random(1024), method="L2-star") for s in range(32)])
    print(f"\nL2-star discrepancy, Sobol(2), n = 1024, 32 seeds: Strata {ours:.3e}, SciPy {theirs:.3e}, ratio {ours / theirs:.3f}")

    print("\nPython batch call against the core's per-sample Rust API into a vector (same values)")
    m = 1 << 17
    for kind in ("sobol", "halton", "independent"):
        for d in (2, 32):
            engine = strata.ENGINES[kind]
            spp = strata.N_MAX
            want = [None]

            def batch():
                e = engine(d, seed=3, n_max=spp)
                t = time.perf_counter()
                x = e.random(m)
                dt = time.perf_counter() - t
                want[0] = int(x.view(np.uint64).sum(dtype=np.uint64))
                return dt

            got = [None]

            def reference():
                seconds, checksum = _strata.per_sample_reference(kind, spp, 3, m, d)
                got[0] = checksum
                return seconds

            a, b = interleaved(rounds, batch, reference)
            if want[0] != got[0]:
                raise SystemExit(f"{kind} d={d}: the batch and the per-sample loop drew different values")
            print(f"  {kind:11s} d={d:2d}, n={m}: batch {a * 1e3:7.2f} ms, per-sample Rust {b * 1e3:7.2f} ms, ratio {a / b:5.2f}")


if __name__ == "__main__":
    main()
