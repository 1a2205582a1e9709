#!/usr/bin/env bash
# particle-lab in a browser.
#   bash scripts/web.sh build   installs what it needs, writes the static site to web/dist/
#   bash scripts/web.sh serve   serves web/dist/ on 127.0.0.1 and prints the address
#   bash scripts/web.sh serve --lan   serves it to the local network too (a classroom
#                                     with no hosting) and prints every address
# The site is static: copy web/dist/ to any web server (GitHub Pages, a school's
# server, `python3 -m http.server`) and open index.html there.
set -euo pipefail
cd "$(dirname "$0")/.."

# Where the wasm build keeps its files: outside the clone, so a fresh clone (CI) reuses
# what an earlier build compiled.
WEB_TARGET="${PARTICLE_LAB_WEB_TARGET:-$HOME/.cache/particle-lab/web-target}"
WASM_BINDGEN_VERSION="$(awk '/^name = "wasm-bindgen"$/ { getline; gsub(/[^0-9.]/, ""); print; exit }' Cargo.lock)"

install() {
    # Debian's rustc-web (with std's sources, built here for wasm32: rustup's toolchain
    # has no wasm32 target and cannot fetch one), wasm-bindgen, and from npm binaryen's
    # wasm-opt (Debian's, version 108, breaks wasm-bindgen's reference table) and the
    # browser tests' playwright-core.
    local packages=(rustc-web cargo-web rust-web-src)
    local missing=()
    for package in "${packages[@]}"; do
        dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
    done
    if [ ${#missing[@]} -gt 0 ]; then
        echo "installing: ${missing[*]}"
        local sudo=""
        [ "$(id -u)" -eq 0 ] || sudo="sudo"
        $sudo apt-get update -qq
        DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
    fi
    if [ "$(wasm-bindgen --version 2>/dev/null | awk '{print $2}')" != "$WASM_BINDGEN_VERSION" ]; then
        echo "installing wasm-bindgen-cli $WASM_BINDGEN_VERSION (the version in Cargo.lock; about 10 minutes)"
        cargo install -q wasm-bindgen-cli --version "$WASM_BINDGEN_VERSION" --no-default-features --bin wasm-bindgen
    fi
    command -v npm >/dev/null || { echo "scripts/web.sh needs Node.js and npm (https://nodejs.org)" >&2; exit 1; }
    if [ ! -x tests/web/node_modules/.bin/wasm-opt ]; then
        (cd tests/web && npm ci --no-audit --no-fund --loglevel=error)
    fi
}

build() {
    install
    # rustup's rust-lld links wasm (Debian ships none for rustc-web); asked of rustup's
    # rustc before RUSTC points at Debian's.
    local lld
    lld="$(rustc --print sysroot)/lib/rustlib/x86_64-unknown-linux-gnu/bin/rust-lld"
    echo "building the wasm (the first build compiles std and every crate: several minutes)"
    RUSTC=/usr/bin/rustc RUSTDOC=/usr/bin/rustdoc RUSTC_BOOTSTRAP=1 \
        CARGO_TARGET_WASM32_UNKNOWN_UNKNOWN_LINKER="$lld" CARGO_TARGET_DIR="$WEB_TARGET" \
        /usr/bin/cargo build -q -Zbuild-std=std,panic_abort --target wasm32-unknown-unknown --release --bin particle-lab
    local out=web/dist
    rm -rf "$out"
    mkdir -p "$out"
    wasm-bindgen --target web --no-typescript --out-dir "$out" \
        "$WEB_TARGET/wasm32-unknown-unknown/release/particle-lab.wasm"
    # The features Chrome, Firefox and Safari all have, as rustc emits them.
    # (WEB_QUICK=1 skips this for a quicker, larger build while working on the page.)
    [ -n "${WEB_QUICK:-}" ] || tests/web/node_modules/.bin/wasm-opt -O2 --enable-reference-types --enable-bulk-memory \
        --enable-nontrapping-float-to-int --enable-sign-ext --enable-mutable-globals --enable-multivalue \
        "$out/particle-lab_bg.wasm" -o "$out/particle-lab_bg.wasm"
    cp web/index.html "$out/"
    local raw gzipped
    raw=$(stat -c %s "$out/particle-lab_bg.wasm")
    gzipped=$(gzip -9 -c "$out/particle-lab_bg.wasm" | wc -c)
    echo "wrote $out/: the wasm is $((raw / 1024)) KB, $((gzipped / 1024)) KB gzipped"
}

serve() {
    [ -f web/dist/index.html ] || { echo "no web/dist/ yet: run 'bash scripts/web.sh build' first" >&2; exit 1; }
    case "${1:-}" in
        "") exec python3 scripts/serve.py web/dist "${PORT:-8000}" ;;
        --lan) exec python3 scripts/serve.py web/dist "${PORT:-8000}" --lan ;;
        *) echo "usage: bash scripts/web.sh serve [--lan]" >&2; exit 2 ;;
    esac
}

case "${1:-}" in
    build) build ;;
    serve) shift; serve "$@" ;;
    *) echo "usage: bash scripts/web.sh build|serve [--lan]" >&2; exit 2 ;;
esac
