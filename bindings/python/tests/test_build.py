"""What was built: a portable module, whatever machine built it."""

import platform

import strata


def test_the_module_is_the_portable_build():
    # The repository builds its own binaries for the host CPU (AVX2 or
    # AVX-512 here); the package must not: SSE2 on x86-64, NEON on aarch64.
    want = {"x86_64": "sse2", "AMD64": "sse2", "aarch64": "neon", "arm64": "neon"}[platform.machine()]
    assert strata.simd_level() == want


def test_versions_are_the_crates():
    assert strata.__version__.count(".") == 2
    assert strata.output_revision() > 0
    assert set(strata.SAMPLERS) == set(strata.ENGINES)
