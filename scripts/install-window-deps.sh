#!/usr/bin/env bash
# Installs what the real-window test needs: a virtual X server (xvfb-run) and Mesa's CPU
# Vulkan driver (lavapipe), so Bevy renders without a GPU or a display. Does nothing when
# they are already there.
set -euo pipefail
missing=()
command -v xvfb-run >/dev/null 2>&1 || missing+=(xvfb xauth)
ls /usr/share/vulkan/icd.d/lvp_icd*.json >/dev/null 2>&1 || missing+=(mesa-vulkan-drivers)
if [ ${#missing[@]} -eq 0 ]; then
    exit 0
fi
echo "installing ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
