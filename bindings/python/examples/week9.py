"""The lecture's week-9 experiment: random against stratified pixel
samples (and Sobol'), error against samples per pixel on ``week09``.

The course renders with random pixel positions (``render()``) or
jittered strata (``render_jittered()``) and compares the images by eye.
Here each sampler renders the scene at 1, 2, 4, ... spp; the RMS error
against a high-spp reference (another sampler and seed, so no sampler is
compared with itself) falls as a straight line on log-log axes: about
``spp^-1/2`` for random samples, faster for stratified and Sobol' ones
while the pixel's integrand is smooth enough to reward them.

    python examples/week9.py                # 160 x 90, up to 256 spp
    python examples/week9.py --quick        # a smaller run (CI)
    python examples/week9.py -o errors.png  # where the plot goes
"""

import argparse
import time

import matplotlib

matplotlib.use("Agg")  # files only: no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import strata  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", default="week9-convergence.png")
    ap.add_argument("--quick", action="store_true", help="64 x 36, up to 64 spp")
    args = ap.parse_args()
    width, height, top, ref_spp = (64, 36, 64, 1024) if args.quick else (160, 90, 256, 4096)
    size = dict(width=width, height=height, max_depth=8)

    t0 = time.perf_counter()
    reference = strata.render("week09", spp=ref_spp, sampler="halton", seed=1234, **size)
    print(f"reference: {width}x{height}, {ref_spp} spp Halton, {time.perf_counter() - t0:.1f} s")

    spps = [2**k for k in range(int(np.log2(top)) + 1)]
    samplers = {"independent": "random (render)", "stratified": "stratified (render_jittered)", "sobol": "Sobol'"}
    errors = {}
    for sampler in samplers:
        errors[sampler] = []
        for spp in spps:
            img = strata.render("week09", spp=spp, sampler=sampler, seed=7, **size)
            errors[sampler].append(float(np.sqrt(np.mean((img - reference) ** 2))))
        slope = np.polyfit(np.log(spps), np.log(errors[sampler]), 1)[0]
        print(f"{sampler:12s} RMSE {errors[sampler][0]:.4f} at 1 spp -> {errors[sampler][-1]:.4f} at {top}; slope {slope:.2f}")

    fig, ax = plt.subplots(figsize=(6, 4.5), dpi=120)
    for sampler, label in samplers.items():
        ax.loglog(spps, errors[sampler], "o-", label=label)
    guide = errors["independent"][0] / np.sqrt(spps)
    ax.loglog(spps, guide, "k:", label=r"$\propto spp^{-1/2}$")
    ax.set_xlabel("samples per pixel")
    ax.set_ylabel("RMS error against the reference")
    ax.set_title(f"week09, {width}x{height}: error against samples")
    ax.legend()
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.output)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
