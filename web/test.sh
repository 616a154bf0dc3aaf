#!/usr/bin/env bash
# The browser page's tests (test.sh calls this): installs what the build
# needs (the wasm32 target, wasm-bindgen-cli of the pinned version, into
# target/tools), builds web/dist with web/build.sh, and runs the module
# under Node (web/test/node.mjs: every golden row, sample patterns,
# refusals).
set -euo pipefail
cd "$(dirname "$0")/.."
version=$(sed -n 's/^wasm-bindgen = "=\(.*\)"$/\1/p' web/Cargo.toml)
rustup target list --installed | grep -qx wasm32-unknown-unknown ||
  rustup target add wasm32-unknown-unknown
tools="$PWD/target/tools"
export WASM_BINDGEN="${WASM_BINDGEN:-$tools/bin/wasm-bindgen}"
if [[ "$("$WASM_BINDGEN" --version 2>/dev/null)" != "wasm-bindgen $version" ]]; then
  cargo install --quiet wasm-bindgen-cli --version "$version" --root "$tools"
fi
bash web/build.sh
node web/test/node.mjs
