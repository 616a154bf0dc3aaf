#!/usr/bin/env bash
# The browser page's tests (test.sh calls this): installs what the build
# needs (the wasm32 target, wasm-bindgen-cli of the pinned version, into
# target/tools), builds web/dist with web/build.sh, and runs the module
# under Node (web/test/node.mjs: every golden row, sample patterns,
# refusals).
set -euo pipefail
cd "$(dirname "$0")/.."
version=$(sed -n 's/^wasm-bindgen = "=\(.*\)"$/\1/p' web/Cargo.toml)
[[ -n "$version" ]] || { echo "web/test.sh: no exact wasm-bindgen version in web/Cargo.toml" >&2; exit 1; }
command -v node >/dev/null || { echo "web/test.sh: needs Node.js (apt-get install nodejs)" >&2; exit 1; }
rustup target list --installed | grep -qx wasm32-unknown-unknown ||
  rustup target add wasm32-unknown-unknown
tools="$PWD/target/tools"
if [[ -n "${WASM_BINDGEN:-}" ]]; then
  # A binary of the caller's: it must be the pinned version (build.sh checks).
  export WASM_BINDGEN
else
  export WASM_BINDGEN="$tools/bin/wasm-bindgen"
  if [[ "$("$WASM_BINDGEN" --version 2>/dev/null)" != "wasm-bindgen $version" ]]; then
    # The CLI's own lock file first; where the registry lacks one of its
    # locked versions, the newest compatible ones.
    cargo install --quiet --locked wasm-bindgen-cli --version "$version" --root "$tools" ||
      cargo install --quiet wasm-bindgen-cli --version "$version" --root "$tools"
  fi
fi
bash web/build.sh
node web/test/node.mjs
