#!/usr/bin/env bash
# Installs what the tests need when it is missing, then runs every test.
# Usage: bash scripts/test.sh   (root, or sudo, for the system packages)
set -euo pipefail
cd "$(dirname "$0")/.."

# Debian packages: a software Vulkan driver for headless rendering, a virtual X
# display with a window manager (openbox, wmctrl) and xdotool for driving the real
# window, ImageMagick for screenshots of the screen, Chromium for the web build.
packages=(mesa-vulkan-drivers libvulkan1 xvfb xdotool openbox wmctrl imagemagick chromium)
missing=()
for package in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
    echo "installing: ${missing[*]}"
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# No circle of imports among the source files (STYLE.md: rooms import one way).
python3 scripts/imports.py

# Every target: unit, integration and end-to-end tests, and the benchmarks once each
# in test mode (so they are known to build and run).
cargo test --release --all-targets

# The engine's unit tests under Miri, which stops at any undefined behaviour in the
# `unsafe` code (issue 36): installs nightly's Miri where missing, and where it cannot,
# says Miri was skipped and goes on.
bash scripts/miri.sh

# The web build (issue 20): built as `bash scripts/web.sh build` builds it (which
# installs its own toolchain), then every scene opened by link in headless Chromium on
# WebGPU and WebGL2 and compared with the desktop's `simulate`.
bash scripts/web.sh build
node tests/web/page.test.mjs target/release/particle-lab web/dist
