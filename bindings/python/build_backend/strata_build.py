"""The package's build backend: maturin's, plus a second build of the
native module for x86-64-v3.

maturin builds one extension module, ``strata._strata``, portable to any
x86-64 CPU (.cargo/config.toml beside pyproject.toml sets the target
CPU). On an x86-64 build machine this backend first builds the same crate
with the ``v3`` feature and ``-C target-cpu=x86-64-v3`` into
``strata/_strata_v3.abi3.so``, which maturin then packs beside it;
``strata/_native.py`` imports it on CPUs that have AVX2 and the rest of
x86-64-v3. Set ``STRATA_NO_V3=1`` to build the portable module alone.
"""

import os
import pathlib
import platform
import shutil
import subprocess
import sys

import maturin
from maturin import *  # noqa: F401,F403  (every hook maturin offers)

HERE = pathlib.Path(__file__).resolve().parent.parent
V3 = HERE / "python" / "strata" / "_strata_v3.abi3.so"


def _build_v3():
    """Builds the v3 module into the package folder; its path, or None."""
    if platform.machine() not in ("x86_64", "AMD64") or os.environ.get("STRATA_NO_V3"):
        return None
    env = dict(os.environ)
    # RUSTFLAGS replaces the target CPU of every config file.
    env["RUSTFLAGS"] = "-C target-cpu=x86-64-v3"
    env.pop("CARGO_ENCODED_RUSTFLAGS", None)
    env.setdefault("PYO3_PYTHON", sys.executable)
    target = HERE / "target" / "v3"
    cmd = [
        "cargo", "build", "--release", "--lib", "--features", "v3",
        "--manifest-path", str(HERE / "Cargo.toml"), "--target-dir", str(target),
    ]  # fmt: skip
    print("strata: building the x86-64-v3 module:", " ".join(cmd), file=sys.stderr)
    subprocess.run(cmd, check=True, env=env)
    shutil.copyfile(target / "release" / "lib_strata.so", V3)
    return V3


def _with_v3(hook):
    def run(*args, **kwargs):
        made = _build_v3()
        try:
            return hook(*args, **kwargs)
        finally:
            if made is not None:
                made.unlink(missing_ok=True)

    run.__name__ = hook.__name__
    run.__doc__ = hook.__doc__
    return run


build_wheel = _with_v3(maturin.build_wheel)
build_editable = _with_v3(maturin.build_editable)
