"""What was built: a portable module, whatever machine built it."""

import platform

import strata


import os
import subprocess
import sys

import numpy as np
import pytest
from strata import _native

X86 = platform.machine() in ("x86_64", "AMD64")


def test_the_portable_module_is_portable_and_the_v3_one_is_chosen_where_it_runs():
    # The repository builds its own binaries for the host CPU (AVX-512
    # here); the package must not: its portable module is SSE2 on x86-64
    # (NEON on aarch64), and on a CPU with x86-64-v3 the AVX2 module is
    # imported instead, unless STRATA_SIMD=portable.
    assert _native.portable.simd() == ("sse2" if X86 else "neon")
    if X86 and _native.portable.cpu_supports_v3() and os.environ.get("STRATA_SIMD") != "portable":
        assert strata.simd_level() == "avx2"
        assert _native.native.__name__ == "strata._strata_v3"
    else:
        assert strata.simd_level() == _native.portable.simd()
    code = "import strata; print(strata.simd_level())"
    env = dict(os.environ, STRATA_SIMD="portable")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == _native.portable.simd()


def test_both_modules_give_the_same_bits():
    try:
        from strata import _strata_v3
    except ImportError:
        pytest.skip("no x86-64-v3 module in this build")
    if not _native.portable.cpu_supports_v3():
        pytest.skip("this CPU cannot run the x86-64-v3 module")
    assert _strata_v3.simd() == "avx2"
    values = set()
    for m in (_native.portable, _strata_v3):
        s = m.Sampler("sobol", 1 << 10, 5, 1, 1)
        out = np.empty((1000, 37))
        s.run_into(0, 0, 3, out)
        pts = m.map("sample", "cosine_hemisphere", 0.0, out[:, :2].astype(np.float32))
        film = m.render(["--scene", "cover", "--width", "24", "--height", "14", "--spp", "2"], 2)
        values.add((out.tobytes(), pts.tobytes(), film.hash()))
    assert len(values) == 1


def test_versions_are_the_crates():
    assert strata.__version__.count(".") == 2
    assert strata.output_revision() > 0
    assert set(strata.SAMPLERS) == set(strata.ENGINES)
