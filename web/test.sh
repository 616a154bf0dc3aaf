#!/usr/bin/env bash
# The browser page's tests (test.sh calls this): installs what the build
# needs (the wasm32 target, wasm-bindgen-cli of the pinned version, into
# target/tools), builds web/dist with web/build.sh, runs both modules
# under Node (web/test/node.mjs: every golden row the page computes,
# patterns, renders, refusals), then the page in headless Chromium
# (web/test/browser.mjs, puppeteer-core from web/test/package-lock.json;
# screenshots in target/web/).
#
# Needs Node.js with npm, gzip and Chromium (installs Debian's nodejs,
# npm, gzip and chromium with apt-get when missing); CHROMIUM names
# another browser binary.
set -euo pipefail
cd "$(dirname "$0")/.."
version=$(sed -n 's/^wasm-bindgen = "=\(.*\)"$/\1/p' web/Cargo.toml)
[[ -n "$version" ]] || { echo "web/test.sh: no exact wasm-bindgen version in web/Cargo.toml" >&2; exit 1; }
need=()
command -v node >/dev/null || need+=(nodejs)
command -v npm >/dev/null || need+=(npm)
command -v gzip >/dev/null || need+=(gzip)
[[ -n "${CHROMIUM:-}" ]] || command -v chromium >/dev/null || need+=(chromium)
if ((${#need[@]})); then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq && apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null ||
    { echo "web/test.sh: needs ${need[*]} (Debian: apt-get install ${need[*]})" >&2; exit 1; }
fi
chromium=${CHROMIUM:-$(command -v chromium)}
[[ -x "$chromium" ]] || { echo "web/test.sh: CHROMIUM=$chromium is not a program" >&2; exit 1; }
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
    # locked versions, the newest compatible ones. No TLS stack: the page
    # needs only the bindings generator.
    cargo install --quiet --locked --no-default-features wasm-bindgen-cli --version "$version" --root "$tools" ||
      cargo install --quiet --no-default-features wasm-bindgen-cli --version "$version" --root "$tools"
  fi
fi
bash web/build.sh
node web/test/node.mjs
(cd web/test && npm ci --no-audit --no-fund --loglevel=error)
CHROMIUM="$chromium" node web/test/browser.mjs
