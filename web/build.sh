#!/usr/bin/env bash
# Builds the browser page into web/dist, a folder any static server can
# serve (README, "Strata in a browser"):
#   index.html, main.js, worker.js, style.css   the page (web/)
#   strata_web.js                               wasm-bindgen's glue
#   strata_web_simd128.wasm.gz                  the module with WebAssembly SIMD
#   strata_web.wasm.gz                          the module without (the fallback)
# The modules are web/src's entry points over the runner's library,
# compiled for wasm32-unknown-unknown with the `web` profile (LTO) and
# bound by the wasm-bindgen CLI of exactly the version web/Cargo.toml
# pins; gzip-compressed here (the page inflates one with the browser's
# DecompressionStream), so the download is the same from any server.
#
# Needs the wasm32-unknown-unknown target, gzip and wasm-bindgen-cli of
# that version (web/test.sh installs both); WASM_BINDGEN names another
# binary.
set -euo pipefail
cd "$(dirname "$0")/.."
version=$(sed -n 's/^wasm-bindgen = "=\(.*\)"$/\1/p' web/Cargo.toml)
[[ -n "$version" ]] || { echo "web/build.sh: no exact wasm-bindgen version in web/Cargo.toml" >&2; exit 1; }
bindgen=${WASM_BINDGEN:-wasm-bindgen}
if [[ "$("$bindgen" --version 2>/dev/null)" != "wasm-bindgen $version" ]]; then
  echo "web/build.sh: needs wasm-bindgen-cli $version" \
    "(cargo install wasm-bindgen-cli --version $version --no-default-features)" >&2
  exit 1
fi
rm -rf web/dist target/web-bindgen
mkdir -p web/dist
# Each build in its own target folder (switching flags in one would
# rebuild everything each time), both at once: each ends in a long
# one-thread LTO step. With --target, RUSTFLAGS reaches only the module,
# not build scripts.
# `exec`: the PIDs below are cargo's, so a failure can stop the other.
build() {
  RUSTFLAGS="$2" CARGO_TARGET_DIR=target/web-$1 \
    exec cargo build --locked --quiet --profile web --target wasm32-unknown-unknown -p strata-web
}
build plain "" & plain=$!
build simd128 "-C target-feature=+simd128" & simd=$!
wait $plain || { kill $simd 2>/dev/null; echo "web/build.sh: the plain module failed to build" >&2; exit 1; }
wait $simd || { echo "web/build.sh: the simd128 module failed to build" >&2; exit 1; }
for variant in plain simd128; do
  "$bindgen" --target web --no-typescript --remove-name-section --remove-producers-section \
    --out-dir "target/web-bindgen/$variant" "target/web-$variant/wasm32-unknown-unknown/web/strata_web.wasm"
done
# One glue serves both modules: the page picks the module, not the glue.
cmp target/web-bindgen/plain/strata_web.js target/web-bindgen/simd128/strata_web.js || {
  echo "web/build.sh: wasm-bindgen's glue differs between the plain and the simd128 module" >&2
  exit 1
}
cp target/web-bindgen/plain/strata_web.js web/dist/
gzip -9n < target/web-bindgen/plain/strata_web_bg.wasm > web/dist/strata_web.wasm.gz
gzip -9n < target/web-bindgen/simd128/strata_web_bg.wasm > web/dist/strata_web_simd128.wasm.gz
cp web/index.html web/main.js web/worker.js web/style.css web/dist/
# The glue is an ES module: say so, for Node versions that do not guess.
echo '{"type": "module"}' > web/dist/package.json
ls -l web/dist
