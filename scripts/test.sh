#!/usr/bin/env bash
# The tests: installs what the real-window test needs (xvfb, Mesa's CPU Vulkan driver), then
# runs every test of the workspace, then the physics core's tests once more with its
# `portable` feature (the plain-integer box comparison that processors other than x86-64
# run). Honours CARGO_TARGET_DIR.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-window-deps.sh
cargo test --workspace "$@"
cargo test -p sphere_physics --features portable "$@"
