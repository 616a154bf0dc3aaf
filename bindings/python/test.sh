#!/usr/bin/env bash
# The Python package's tests, from this checkout: a fresh virtual
# environment, `pip install ./bindings/python` (two builds of the native
# module on x86-64: portable SSE2 and x86-64-v3, see
# build_backend/strata_build.py), then the pytest suite (values against
# the Rust locks and golden rows, SciPy's use of the engines, bad input,
# the renderer) once with the module the machine picks and once with the
# portable one, the docstrings' examples, the week-9 example (a small
# run) and the benchmark script (a short run: it checks its values; its
# speeds are printed, not judged). Installs python3-venv with apt if the
# interpreter has no venv module. The root test.sh calls this.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
out="$root/target/python"
mkdir -p "$out"
py=${PYTHON:-python3}

if ! "$py" -c 'import ensurepip, venv' 2>/dev/null; then
  export DEBIAN_FRONTEND=noninteractive
  timeout 600 apt-get update -qq
  timeout 900 apt-get install -y -qq --no-install-recommends python3-venv >/dev/null
fi

echo "== a fresh virtual environment ($out/venv)"
rm -rf "$out/venv"
"$py" -m venv "$out/venv"
vpy="$out/venv/bin/python"
"$vpy" -m pip install -q --disable-pip-version-check -r "$here/requirements-test.txt"

echo "== pip install ./bindings/python"
# The repository's RUSTFLAGS, if any, would replace the package's target
# CPU: leave them out, as a user's install has none.
(cd "$root" && env -u RUSTFLAGS -u CARGO_ENCODED_RUSTFLAGS \
  "$vpy" -m pip install -q --disable-pip-version-check ./bindings/python)

echo "== pytest ($("$vpy" -c 'import strata; print(strata.simd_level())'))"
# From the tests' folder, so `import strata` is the installed package.
(cd "$here/tests" && "$vpy" -m pytest -q -p no:cacheprovider .)
echo "== pytest (STRATA_SIMD=portable)"
(cd "$here/tests" && STRATA_SIMD=portable "$vpy" -m pytest -q -p no:cacheprovider .)
echo "== the docstrings' examples"
(cd "$out" && "$vpy" -m pytest -q -p no:cacheprovider --doctest-modules --pyargs strata)
echo "== examples/week9.py --quick"
(cd "$out" && "$vpy" "$here/examples/week9.py" --quick -o "$out/week9-convergence.png")
echo "== benchmarks/samplers.py --quick"
"$vpy" "$here/benchmarks/samplers.py" --quick
echo "Python package: all tests passed"
