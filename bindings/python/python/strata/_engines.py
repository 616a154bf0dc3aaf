"""Strata's pixel samplers as SciPy quasi-Monte Carlo engines.

An engine is **one pixel of a Strata sampler** built for ``n_max``
samples per pixel (its pattern size): point ``i`` is sample index ``i``
of that pixel, coordinate ``j`` is dimension ``j``. Dimensions 0 and 1
are the sampler's 2-D pixel position, then come 2-D pairs, and a last
1-D value when ``d`` is odd: exactly what a Strata render draws, so an
engine's points are the renderer's, bit for bit (float32 values, given
as float64).

When SciPy is installed the engines subclass
``scipy.stats.qmc.QMCEngine``, so SciPy's functions that take an engine
(``qmc_quad``, ``MultivariateNormalQMC``, ``qmc.discrepancy`` on their
points) accept them. ``random(n)``, ``random_base2(m)``, ``reset()`` and
``fast_forward(n)`` mean what they mean in SciPy. Every engine is
scrambled (Owen's nested scramble for Sobol', Halton and ZSobol'): the
seed picks the scramble, and the same seed always gives the same points.

Strata's Sobol' is pbrt's *padded* Sobol': each 2-D pair of dimensions
is the first two dimensions of Sobol' (a (0, 2)-sequence), independently
scrambled, so every pair is stratified but the ``d`` dimensions together
are not a ``d``-dimensional Sobol' net (SciPy's ``Sobol`` is one). For a
renderer, whose integrand couples each bounce's pair far more than
pairs across bounces, this is the better pattern; for a smooth
``d``-dimensional integral, SciPy's ``Sobol`` may do better.
"""

from __future__ import annotations

import numpy as np

from ._native import native as _strata
from ._arrays import U32_MAX, count, pair, seed_of

try:  # SciPy is optional: without it the engines stand alone.
    from scipy.stats.qmc import QMCEngine as _Base

    HAVE_SCIPY = True
except ImportError:  # pragma: no cover - exercised by the no-SciPy test
    HAVE_SCIPY = False

    class _Base:  # type: ignore[no-redef]
        """The part of SciPy's QMCEngine the engines rely on."""

        def random(self, n=1, *, workers=1):
            sample = self._random(n, workers=workers)
            self.num_generated += n
            return sample

        def reset(self):
            self.num_generated = 0
            return self


#: The default pattern size: 2**24 samples per pixel, the float32
#: resolution of a sampler's values (Sobol' strata stop refining there).
N_MAX = 2**24


class _Engine(_Base):
    """One pixel of a Strata sampler as a QMC engine (see the module)."""

    _kind = ""

    def __init__(
        self,
        d,
        *,
        seed=None,
        rng=None,
        n_max=N_MAX,
        pixel=(0, 0),
        resolution=None,
        optimization=None,
    ):
        d = count(d, "d", high=1 << 20)
        n_max = count(n_max, "n_max", low=1, high=U32_MAX)
        px, py = pair(pixel, "pixel")
        if resolution is None:
            resolution = (min(px + 1, U32_MAX), min(py + 1, U32_MAX))
        width, height = pair(resolution, "resolution", low=1)
        self.seed = seed_of(seed, rng)
        self._sampler = _strata.Sampler(self._kind, n_max, self.seed, width, height)
        self._pixel = (px, py)
        # What scipy.integrate.qmc_quad needs to make more engines of this
        # kind (it passes a new seed).
        self._init_quad = {
            "d": d,
            "n_max": n_max,
            "pixel": (px, py),
            "resolution": (width, height),
            "optimization": optimization,
        }
        if HAVE_SCIPY:
            generator = np.random.default_rng(self.seed)
            try:
                super().__init__(d=d, optimization=optimization, rng=generator)
            except TypeError:  # SciPy before 1.15 calls it `seed`
                super().__init__(d=d, optimization=optimization, seed=generator)
        else:
            if optimization is not None:
                raise ValueError("optimization needs SciPy")
            self.d = d
            self.num_generated = 0

    @property
    def n_max(self) -> int:
        """The sampler's samples per pixel (its pattern size)."""
        return self._sampler.spp

    def _random(self, n=1, *, workers=1):
        n = count(n, "n")
        first = self.num_generated
        if first + n > U32_MAX + 1:
            raise ValueError(
                f"{first} points drawn and {n} more pass the last sample index, {U32_MAX}"
            )
        out = np.empty((n, self.d))
        if n == 0:
            return out
        self._sampler.run_into(self._pixel[0], self._pixel[1], first, out)
        return out

    def random_base2(self, m):
        """``2**m`` points, keeping the balance of a base-2 net: the total
        drawn must stay a power of two (SciPy's rule)."""
        m = count(m, "m", high=32)
        total = self.num_generated + 2**m
        if total & (total - 1):
            raise ValueError(
                "The balance properties of a base-2 sequence require n to be a "
                f"power of 2: {self.num_generated} points drawn before, then "
                f"n={self.num_generated}+2**{m}={total}. Use random() to draw anyway."
            )
        return self.random(2**m)

    def fast_forward(self, n):
        """Skips ``n`` points (no values are computed)."""
        n = count(n, "n")
        if self.num_generated + n > U32_MAX + 1:
            raise ValueError(f"fast_forward({n}) passes the last sample index, {U32_MAX}")
        self.num_generated += n
        return self

    def __repr__(self):
        return (
            f"strata.{type(self).__name__}(d={self.d}, seed={self.seed}, n_max={self.n_max}, "
            f"pixel={self._pixel})"
        )


class Independent(_Engine):
    """Uniform random points: a hashed stream per (seed, pixel, index,
    dimension), so any point can be drawn alone."""

    _kind = "independent"


class Grid(_Engine):
    """Centres of ``n_max`` strata (an ``nx × ny`` grid for the first pair,
    shuffled 1-D strata after): stratified once all ``n_max`` points are
    drawn, aliasing on purpose. Set ``n_max`` to the points you draw."""

    _kind = "grid"


class Stratified(_Engine):
    """Jittered ``n_max`` strata per dimension, shuffled per dimension:
    stratified once all ``n_max`` points are drawn (then each pass of
    ``n_max`` is a fresh set). Set ``n_max`` to the points you draw."""

    _kind = "stratified"


class Sobol(_Engine):
    """Owen-scrambled Sobol', padded in 2-D pairs (pbrt's): every aligned
    block of ``2**k`` points is a stratified net in each pair."""

    _kind = "sobol"


class Halton(_Engine):
    """Owen-scrambled Halton over the prime bases (2 and 3 for the first
    pair); dimensions past 63 are independent uniforms."""

    _kind = "halton"


class ZSobol(_Engine):
    """Sobol' along a hashed Morton curve over an image of ``resolution``
    pixels (pbrt's ZSobol): neighbouring pixels' engines complement each
    other. ``n_max`` is the samples per pixel."""

    _kind = "zsobol"


ENGINES = {cls._kind: cls for cls in (Independent, Grid, Stratified, Sobol, Halton, ZSobol)}
