#!/usr/bin/env bash
# Builds the browser page's WebAssembly module and its JavaScript glue
# into web/dist (`strata_web.js`, `strata_web_bg.wasm`): the entry points
# of web/src over the runner's library, compiled for wasm32-unknown-unknown
# with the `web` profile (LTO; wasm-bindgen drops the names), bound by the wasm-bindgen CLI of
# exactly the version web/Cargo.toml pins.
#
# Needs the wasm32-unknown-unknown target and wasm-bindgen-cli of that
# version (web/test.sh installs both); WASM_BINDGEN names another binary.
set -euo pipefail
cd "$(dirname "$0")/.."
version=$(sed -n 's/^wasm-bindgen = "=\(.*\)"$/\1/p' web/Cargo.toml)
[[ -n "$version" ]] || { echo "web/build.sh: no exact wasm-bindgen version in web/Cargo.toml" >&2; exit 1; }
bindgen=${WASM_BINDGEN:-wasm-bindgen}
if [[ "$("$bindgen" --version 2>/dev/null)" != "wasm-bindgen $version" ]]; then
  echo "web/build.sh: needs wasm-bindgen-cli $version" \
    "(cargo install wasm-bindgen-cli --version $version)" >&2
  exit 1
fi
cargo build --locked --profile web --target wasm32-unknown-unknown -p strata-web
rm -rf web/dist
"$bindgen" --target web --no-typescript --remove-name-section --remove-producers-section \
  --out-dir web/dist \
  target/wasm32-unknown-unknown/web/strata_web.wasm
# The glue is an ES module: say so, for Node versions that do not guess.
echo '{"type": "module"}' > web/dist/package.json
ls -l web/dist
