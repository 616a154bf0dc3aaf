#!/usr/bin/env bash
# Every test of the repository, one command: the Cargo workspace's tests,
# then each binding's (the C API's: bindings/c/test.sh; the Python
# package's: bindings/python/test.sh; the browser module's: web/test.sh;
# each installs what it needs).
# `.ci/run` calls this.
set -euo pipefail
cd "$(dirname "$0")"
cargo test --workspace
bash bindings/c/test.sh
bash bindings/python/test.sh
bash web/test.sh
