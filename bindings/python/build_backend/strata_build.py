"""The package's build backend: maturin's, plus a second build of the
native module for x86-64-v3.

maturin builds one extension module, ``strata._strata``, portable to any
x86-64 CPU (pyproject.toml's `config` sets the target CPU). On a Linux
x86-64 build machine this backend first builds the same crate
with the ``v3`` feature and ``-C target-cpu=x86-64-v3`` into
``strata/_strata_v3.abi3.so``, which maturin then packs beside it;
``strata/_native.py`` imports it on CPUs that have AVX2 and the rest of
x86-64-v3. Set ``STRATA_NO_V3=1`` to build the portable module alone
(a cross build, ``CARGO_BUILD_TARGET``, or another system gets it alone
too). No sdist is offered (``build_sdist`` says why).
"""

import os
import pathlib
import platform
import shutil
import subprocess
import sys

import maturin
from maturin import *  # noqa: F401,F403  (the hooks not redefined below)

HERE = pathlib.Path(__file__).resolve().parent.parent
V3 = HERE / "python" / "strata" / "_strata_v3.abi3.so"
# The crate: beside pyproject.toml in the repository; in an sdist, maturin
# puts pyproject.toml at the top and the crate at its repository path.
MANIFEST = next(
    p for p in (HERE / "bindings" / "python" / "Cargo.toml", HERE / "Cargo.toml") if p.exists()
)


def _build_v3():
    """Builds the v3 module into the package folder; its path, or None
    where there is none to build (not Linux x86-64, a cross build, or
    STRATA_NO_V3 set)."""
    V3.unlink(missing_ok=True)  # never pack a module left by an earlier build
    if (
        platform.system() != "Linux"
        or platform.machine() != "x86_64"
        or os.environ.get("CARGO_BUILD_TARGET")
        or os.environ.get("STRATA_NO_V3")
    ):
        return None
    env = dict(os.environ)
    # Appended: the caller's flags (a linker, -L) stay; RUSTFLAGS replaces
    # the target CPU of every config file, and the last one counts.
    env["RUSTFLAGS"] = (env.get("RUSTFLAGS", "") + " -C target-cpu=x86-64-v3").strip()
    env.pop("CARGO_ENCODED_RUSTFLAGS", None)
    env.setdefault("PYO3_PYTHON", sys.executable)
    target = HERE / "target" / "v3"
    cmd = [
        "cargo", "build", "--release", "--locked", "--lib", "--features", "v3",
        "--manifest-path", str(MANIFEST), "--target-dir", str(target),
    ]  # fmt: skip
    print("strata: building the x86-64-v3 module:", " ".join(cmd), file=sys.stderr)
    subprocess.run(cmd, check=True, env=env)
    shutil.copyfile(target / "release" / "lib_strata.so", V3)
    return V3


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    """maturin's wheel, with the v3 module packed beside the portable one
    (and removed from the source tree again)."""
    made = _build_v3()
    try:
        return maturin.build_wheel(wheel_directory, config_settings, metadata_directory)
    finally:
        if made is not None:
            made.unlink(missing_ok=True)


def build_editable(wheel_directory, config_settings=None, metadata_directory=None):
    """maturin's editable install, which imports from python/strata/: the
    v3 module stays there (it is rebuilt by the next install)."""
    _build_v3()
    return maturin.build_editable(wheel_directory, config_settings, metadata_directory)


def build_sdist(sdist_directory, config_settings=None):
    """Not offered: the crates the package builds inherit their settings
    from the repository's Cargo workspace, which an sdist does not carry
    whole. Build from the repository, or pass a wheel around."""
    raise RuntimeError(
        "strata builds from the repository (pip install ./bindings/python) or as a wheel "
        "(pip wheel ./bindings/python); it offers no sdist"
    )
