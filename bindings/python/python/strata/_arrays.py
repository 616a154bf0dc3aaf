"""Input checks shared by the package's functions: what a caller passes
becomes the exact dtype and shape the native module takes, or a clear
``TypeError`` (a wrong kind of value) or ``ValueError`` (a wrong shape,
size or range)."""

from __future__ import annotations

import numbers
import operator
import secrets

import numpy as np

U32_MAX = 2**32 - 1
U64_MAX = 2**64 - 1


def count(value, name: str, *, low: int = 0, high: int | None = None) -> int:
    """An integer in ``[low, high]`` (bools and floats refused)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Integral, np.integer)):
        raise TypeError(f"{name} must be an integer, not {type(value).__name__}")
    value = operator.index(value)
    if value < low or (high is not None and value > high):
        upper = "" if high is None else f" and at most {high}"
        raise ValueError(f"{name} must be at least {low}{upper}, not {value}")
    return value


def floats(values, name: str, cols: int) -> tuple[np.ndarray, tuple[int, ...]]:
    """``values`` as contiguous float32 rows of ``cols``, and the leading
    shape to give the result back in. Integers and floats of any width
    are taken (float64 rounds to the nearest float32, the core's type);
    anything else is a ``TypeError``."""
    a = np.asarray(values)
    if a.dtype.kind not in "fiu":
        raise TypeError(f"{name}: expected an array of real numbers, not dtype {a.dtype}")
    if a.ndim == 0 or a.shape[-1] != cols:
        raise ValueError(f"{name}: expected shape (..., {cols}), not {a.shape}")
    lead = a.shape[:-1]
    return np.ascontiguousarray(a.reshape(-1, cols), dtype=np.float32), lead


def pair(value, name: str, *, low: int = 0) -> tuple[int, int]:
    """Two integers in ``[low, 2**32 - 1]``, such as a pixel or a
    resolution."""
    try:
        a, b = value
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a pair of integers, not {value!r}") from None
    return count(a, name, low=low, high=U32_MAX), count(b, name, low=low, high=U32_MAX)


def uints(values, name: str) -> np.ndarray:
    """``values`` as a contiguous uint32 array: integers in
    ``[0, 2**32 - 1]`` only (floats and bools are a ``TypeError``; an
    empty list is taken whatever numpy makes of it)."""
    a = np.asarray(values)
    if a.size == 0 and a.dtype.kind in "fiu":
        return np.zeros(a.shape, np.uint32)
    if a.dtype.kind not in "iu":
        raise TypeError(f"{name}: expected integers, not dtype {a.dtype}")
    if a.size and (a.min() < 0 or a.max() > U32_MAX):
        raise ValueError(f"{name}: values must lie in [0, {U32_MAX}]")
    # (not ascontiguousarray, which makes a 0-d array 1-d)
    return np.asarray(a, dtype=np.uint32, order="C")


def seed_of(seed=None, rng=None) -> int:
    """A 64-bit seed from ``seed`` or ``rng`` (one of them): an integer, a
    ``numpy.random.Generator`` or ``SeedSequence`` (one 64-bit draw), or
    None for a fresh seed from the operating system."""
    if seed is not None and rng is not None:
        raise ValueError("give seed or rng, not both")
    value = rng if seed is None else seed
    if value is None:
        return secrets.randbits(64)
    if isinstance(value, np.random.Generator):
        return int(value.bit_generator.random_raw())
    if isinstance(value, np.random.SeedSequence):
        return int(value.generate_state(1, np.uint64)[0])
    return count(value, "seed", high=U64_MAX)
