#!/usr/bin/env bash
# The tests: installs what the real-window test needs (xvfb, Mesa's CPU Vulkan driver), then
# runs every test of the workspace. Honours CARGO_TARGET_DIR.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-window-deps.sh
cargo test --workspace "$@"
