#!/usr/bin/env bash
# Installs what the real-window test needs: a virtual X server (xvfb-run), Mesa's CPU
# Vulkan driver (lavapipe), so Bevy renders without a GPU or a display, and the X11 libraries
# winit loads when it opens a window (cursor, input and keyboard). Does nothing when they are
# already there.
set -euo pipefail
missing=()
command -v xvfb-run >/dev/null 2>&1 || missing+=(xvfb xauth)
ls /usr/share/vulkan/icd.d/lvp_icd*.json >/dev/null 2>&1 || missing+=(mesa-vulkan-drivers)
# winit's X11 backend opens these at run time (not at link time, so a build does not notice).
# ldconfig lives in /sbin, off a normal user's PATH; its list is read once, whole (a `grep -q`
# reading a pipe may stop early and, under pipefail, fail the pipe at random).
libraries=$(PATH="$PATH:/sbin:/usr/sbin" ldconfig -p 2>/dev/null || true)
for pair in libX11-xcb.so.1:libx11-xcb1 libXcursor.so.1:libxcursor1 libXi.so.6:libxi6 \
    libxkbcommon-x11.so.0:libxkbcommon-x11-0; do
    [[ "$libraries" == *"${pair%%:*}"* ]] || missing+=("${pair##*:}")
done
if [ ${#missing[@]} -eq 0 ]; then
    exit 0
fi
echo "installing ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
