#!/usr/bin/env bash
# The C API's tests, from a clean checkout: builds the portable library
# (libstrata.a and libstrata.so for baseline x86-64, whatever this
# machine is), checks that the committed header is what cbindgen makes of
# the source, compiles the C tests with -Wall -Wextra -Werror against both
# libraries, runs them against the core's value locks, and runs the
# shared-library build under valgrind's memcheck (0 errors, no leaks).
# Installs cbindgen, gcc and valgrind when missing.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$PWD
out=$root/target/c-api
mkdir -p "$out"

CBINDGEN_VERSION=0.29.2
if ! command -v cbindgen >/dev/null || [[ "$(cbindgen --version)" != "cbindgen $CBINDGEN_VERSION" ]]; then
  cargo install --locked --quiet cbindgen --version "$CBINDGEN_VERSION"
fi
need=()
command -v gcc >/dev/null || need+=(gcc)
command -v g++ >/dev/null || need+=(g++)
command -v valgrind >/dev/null || need+=(valgrind)
if ((${#need[@]})); then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq && apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
fi

# Portable by default: the repository's target-cpu=native must not reach
# a library others link (RUSTFLAGS replaces the config's flags).
case "$(uname -m)" in
  x86_64) flags="-C target-cpu=x86-64"; level=sse2 ;;
  aarch64) flags=""; level=neon ;;
  *) flags=""; level="" ;;
esac
RUSTFLAGS="$flags" cargo build --locked --release -p strata-c --target-dir "$out/build"
lib=$out/build/release

echo "== header is current"
cbindgen --quiet --config bindings/c/cbindgen.toml --crate strata-c --output "$out/strata.h"
if ! diff -u bindings/c/include/strata.h "$out/strata.h"; then
  echo "bindings/c/include/strata.h is not what cbindgen makes of bindings/c/src/lib.rs:" >&2
  echo "  cbindgen --config bindings/c/cbindgen.toml --crate strata-c --output bindings/c/include/strata.h" >&2
  exit 1
fi

cflags=(-std=c11 -O2 -Wall -Wextra -Werror -pedantic -ffp-contract=off -pthread -I bindings/c/include)
echo "== C tests, static library"
gcc "${cflags[@]}" bindings/c/tests/locks.c "$lib/libstrata.a" \
  -lgcc_s -lutil -lrt -lpthread -lm -ldl -o "$out/locks_static"
"$out/locks_static" core/tests/data/locks.json std-runner/tests/data/golden.json "$level"

echo "== C tests, shared library, under memcheck"
gcc "${cflags[@]}" bindings/c/tests/locks.c -L"$lib" -lstrata -Wl,-rpath,"$lib" -lm -o "$out/locks_shared"
# A whole-frame render's pool and its threads end with the call, but the
# calling thread keeps two thread-local blocks until it ends (Rust's
# handle for the thread, the pool's epoch registration: 2,352 bytes once
# per thread, not per call); memcheck counts the main thread's as
# possibly lost at exit. Definite and indirect leaks fail the test.
valgrind --quiet --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite,indirect \
  --show-possibly-lost=no "$out/locks_shared" core/tests/data/locks.json std-runner/tests/data/golden.json "$level"
echo "== the header alone, as C99"
printf '#include "strata.h"\nint main(void) { return strata_output_revision() == 0; }\n' > "$out/c99.c"
gcc -std=c99 -Wall -Wextra -Werror -pedantic -I bindings/c/include -fsyntax-only "$out/c99.c"

echo "== examples: the same path tracer in C and in C++, under memcheck"
gcc "${cflags[@]}" bindings/c/examples/render.c -L"$lib" -lstrata -Wl,-rpath,"$lib" -lm -o "$out/render_c"
g++ -std=c++17 -O2 -Wall -Wextra -Werror -pedantic -ffp-contract=off -I bindings/c/include \
  bindings/c/examples/render.cpp -L"$lib" -lstrata -Wl,-rpath,"$lib" -o "$out/render_cpp"
memcheck() {
  valgrind --quiet --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite,indirect "$@"
}
c_hash=$(memcheck "$out/render_c" "$out/render_c.ppm")
cpp_hash=$(memcheck "$out/render_cpp" "$out/render_cpp.ppm")
echo "C: $c_hash, C++: $cpp_hash"
[[ -n "$c_hash" && "$c_hash" == "$cpp_hash" ]]
cmp "$out/render_c.ppm" "$out/render_cpp.ppm"
# The C++ side renders a golden row through the renderer API too.
golden=$(memcheck --show-possibly-lost=no "$out/render_cpp" --golden-week09-sobol)
want=$(grep '"week09/sobol"' std-runner/tests/data/golden.json | sed 's/.*"0x\([0-9a-f]*\)".*/\1/')
echo "C++ golden week09/sobol: $golden (row: $want)"
[[ -n "$want" && "$golden" == "$want" ]]
echo "C API: all tests passed"
