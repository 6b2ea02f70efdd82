#!/usr/bin/env bash
# web/build.sh: builds raystep's app for the browser into dist/ at the repository root, a static
# site (any web server or static host serves it as it is):
#   dist/index.html          the page (web/static/index.html)
#   dist/coi.js              its service worker, for cross-origin isolation (web/static/coi.js)
#   dist/raystep_web.js      wasm-bindgen's loader
#   dist/raystep_web_bg.wasm the app (the `raystep-web` crate in web/, built for wasm32)
#   dist/snippets/           the script each render Web Worker starts with (wasm-bindgen-rayon's)
#
# Threads: the wasm is built for WebAssembly threads (atomics and bulk memory, its memory shared
# between the page and its Web Workers), so the render can run on every core where the page is
# cross-origin isolated (web/static/coi.js, a service worker, sees to that on any static host).
# The standard library must then be compiled with the same features, from its source
# (`-Zbuild-std`, allowed on a stable compiler by RUSTC_BOOTSTRAP=1). Where the page is not
# isolated, index.html loads the same wasm on one thread (see web/static/index.html).
#
# Toolchain, picked in this order:
#   1. rustup's toolchain, where its wasm32-unknown-unknown target and the standard library's
#      source (`rustup component add rust-src`) are installed.
#   2. Otherwise Debian's Rust for Firefox/Chromium builds (rustc-web, cargo-web, rust-web-src,
#      rust-web-llvm, lld-22; installed with apt when missing, as root or through sudo). This is
#      the path on a machine whose rustup cannot download targets (CI's).
# wasm-bindgen-cli must be the exact version of the `wasm-bindgen` crate in Cargo.lock: it is
# read from there and installed with `cargo install` when missing or different.
# The wasm is built with the `web` profile (Cargo.toml: release, opt-level 2, no debug info, no
# LTO: see the measurements there). wasm-opt (binaryen) shrinks it further where it is installed;
# it is not required.
#
# Environment: CARGO_TARGET_DIR (default target/), RAYSTEP_WEB_PROFILE (default web; e.g.
# `dev` for a quicker build while working on the page), RAYSTEP_WEB_DIST (default dist).
set -euo pipefail
cd "$(dirname "$0")/.."

PROFILE="${RAYSTEP_WEB_PROFILE:-web}"
DIST="${RAYSTEP_WEB_DIST:-dist}"
TARGET_DIR="${CARGO_TARGET_DIR:-target}"
case "$PROFILE" in dev) PROFILE_DIR=debug ;; *) PROFILE_DIR="$PROFILE" ;; esac
# Locally installed tools (cargo install) come after rustup's shims.
export PATH="$PATH:${CARGO_HOME:-$HOME/.cargo}/bin"

as_root() {
  if [ "$(id -u)" = 0 ]; then "$@"; else sudo "$@"; fi
}

echo "== web: toolchain"
if command -v rustup >/dev/null 2>&1 \
   && rustup target list --installed 2>/dev/null | grep -qx wasm32-unknown-unknown \
   && rustup component list --installed 2>/dev/null | grep -q '^rust-src'; then
  echo "rustup's toolchain with its wasm32-unknown-unknown target, std built from source"
  BUILD=(env RUSTC_BOOTSTRAP=1 cargo build -Zbuild-std=std,panic_abort)
  cargo --version; rustc --version
else
  echo "rustup has no wasm32-unknown-unknown target or no rust-src here: Debian's rustc-web," \
       "std built from source"
  PKGS=(rustc-web cargo-web rust-web-src rust-web-llvm lld-22)
  if ! dpkg -s "${PKGS[@]}" >/dev/null 2>&1; then
    echo "installing ${PKGS[*]} with apt"
    as_root apt-get update -qq
    DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -qq "${PKGS[@]}" >/dev/null
  fi
  # By path: rustup's shims come first on PATH and would pick rustup's compiler.
  BUILD=(env RUSTC=/usr/bin/rustc RUSTC_BOOTSTRAP=1 /usr/bin/cargo build
         -Zbuild-std=std,panic_abort)
  /usr/bin/cargo --version; /usr/bin/rustc --version
fi
# WebAssembly threads: atomic instructions, and a memory the module imports shared (so that the
# page can hand it to its Web Workers), with the thread-local storage's symbols exported that
# wasm-bindgen's thread start-up calls. Its maximum is wasm32's 4 GiB: a shared memory cannot
# grow past the maximum it declares, and a million-triangle scene's BVH needs more than a
# gigabyte in the page.
LINK="--shared-memory --import-memory --max-memory=4294967296 --export=__wasm_init_tls"
LINK="$LINK --export=__tls_size --export=__tls_align --export=__tls_base"
RUSTFLAGS_WEB="-C target-feature=+atomics,+bulk-memory,+mutable-globals"
for a in $LINK; do RUSTFLAGS_WEB="$RUSTFLAGS_WEB -C link-arg=$a"; done
export CARGO_TARGET_WASM32_UNKNOWN_UNKNOWN_RUSTFLAGS="$RUSTFLAGS_WEB"

echo "== web: wasm-bindgen-cli"
WBG_VERSION="$(awk '/^name = "wasm-bindgen"$/ { getline; gsub(/"/, "", $3); print $3; exit }' Cargo.lock)"
if [ -z "$WBG_VERSION" ]; then
  echo "web/build.sh: Cargo.lock names no wasm-bindgen version" >&2
  exit 1
fi
if [ "$(wasm-bindgen --version 2>/dev/null || true)" != "wasm-bindgen $WBG_VERSION" ]; then
  echo "installing wasm-bindgen-cli $WBG_VERSION (Cargo.lock's wasm-bindgen)"
  # --locked builds it with the dependencies its authors tested; a registry mirror that lacks one
  # of those versions refuses it, and then it is built with the newest compatible ones.
  # Without its default feature (a TLS stack for downloading, which this build never asks it
  # to do): a fifth less to compile. Unoptimized (CARGO_PROFILE_RELEASE_OPT_LEVEL=0): it runs
  # once a build, and its own build is on the critical path of a fresh machine. Measured on a
  # 2-core machine, alone (2026-12-02, 0.2.130): its install took 101 s of CPU against 271 s
  # at opt-level 1 (398 s at release's 3, measured earlier), and it wrote the same files, byte
  # for byte, for raystep's 28 MB wasm in 11 s of CPU against 3 s.
  CARGO_PROFILE_RELEASE_OPT_LEVEL=0 cargo install --quiet wasm-bindgen-cli \
      --version "$WBG_VERSION" --no-default-features --locked \
    || CARGO_PROFILE_RELEASE_OPT_LEVEL=0 cargo install --quiet wasm-bindgen-cli \
      --version "$WBG_VERSION" --no-default-features
  hash -r
fi
if [ "$(wasm-bindgen --version 2>/dev/null || true)" != "wasm-bindgen $WBG_VERSION" ]; then
  echo "web/build.sh: the wasm-bindgen on the PATH ($(command -v wasm-bindgen || echo none):" \
       "$(wasm-bindgen --version 2>&1 || true)) is not Cargo.lock's $WBG_VERSION" >&2
  exit 1
fi
wasm-bindgen --version

echo "== web: build (profile $PROFILE)"
start=$(date +%s)
"${BUILD[@]}" -p raystep-web --target wasm32-unknown-unknown --profile "$PROFILE"
echo "built in $(( $(date +%s) - start )) s"
WASM="$TARGET_DIR/wasm32-unknown-unknown/$PROFILE_DIR/raystep_web.wasm"

echo "== web: $DIST/"
rm -rf "$DIST"
mkdir -p "$DIST"
wasm-bindgen --target web --no-typescript --out-dir "$DIST" "$WASM"
cp web/static/index.html web/static/coi.js "$DIST/"
if command -v wasm-opt >/dev/null 2>&1; then
  before=$(stat -c %s "$DIST/raystep_web_bg.wasm")
  # Rust's wasm32 target uses these proposals; wasm-opt must be told it may keep them.
  if wasm-opt -O2 --enable-threads --enable-bulk-memory --enable-nontrapping-float-to-int --enable-sign-ext \
       --enable-mutable-globals --enable-multivalue --enable-reference-types \
       "$DIST/raystep_web_bg.wasm" -o "$DIST/raystep_web_bg.opt.wasm"; then
    mv "$DIST/raystep_web_bg.opt.wasm" "$DIST/raystep_web_bg.wasm"
    echo "wasm-opt -O2: $before -> $(stat -c %s "$DIST/raystep_web_bg.wasm") bytes"
  else
    rm -f "$DIST/raystep_web_bg.opt.wasm"
    echo "wasm-opt failed: dist/ keeps wasm-bindgen's output as it is"
  fi
else
  echo "(no wasm-opt here: not shrunk further)"
fi

raw=$(stat -c %s "$DIST/raystep_web_bg.wasm")
gz=$(gzip -9 -c "$DIST/raystep_web_bg.wasm" | wc -c)
echo "== web: done"
find "$DIST" -type f | sort
echo "wasm: $raw bytes ($(( raw / 1024 )) KiB), gzipped $gz bytes ($(( gz / 1024 )) KiB)"
