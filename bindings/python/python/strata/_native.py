"""The native module this machine runs.

The package holds two builds of the same Rust code: ``_strata``, portable
to any x86-64 CPU (SSE2), and on x86-64 also ``_strata_v3``, built for
x86-64-v3 (AVX2, about three times faster in the samplers' loops). The
v3 one is imported when the CPU has every feature it needs (the portable
module checks) and is not older than the portable one (``maturin
develop`` rebuilds only that); ``STRATA_SIMD=portable`` in the
environment keeps the portable one. Both give the same bits: only speed
differs.
"""

import importlib.util
import os

from . import _strata as portable

native = portable
_choice = os.environ.get("STRATA_SIMD", "auto")
if _choice not in ("auto", "portable"):
    raise ImportError(f"STRATA_SIMD={_choice!r}: expected 'auto' or 'portable'")

def _stale_v3() -> bool:
    """Whether the v3 module is older than the portable one: `maturin
    develop` rebuilds only the portable module of an editable install."""
    v3 = importlib.util.find_spec(__package__ + "._strata_v3")
    if v3 is None or v3.origin is None or portable.__file__ is None:
        return True
    # (A wheel unpacks both at once: a second apart is not stale.)
    return os.path.getmtime(v3.origin) + 2 < os.path.getmtime(portable.__file__)


if _choice == "auto" and portable.cpu_supports_v3() and not _stale_v3():
    try:
        from . import _strata_v3 as native  # noqa: F811
    except ImportError:  # a build without it (maturin alone, or not x86-64)
        pass
