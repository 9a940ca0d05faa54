#!/usr/bin/env bash
# `make web`: the playground (docs/playground.md) into a folder a static web
# server can serve, or a browser open from file:// (target/web/site, or
# $WEB_OUT): index.html, the page's bundled scripts with the WebAssembly
# module inside, and nothing fetched at run time.
#
# The module is crates/web built for wasm32-unknown-unknown by Debian's
# rustc and cargo (rustc-web, cargo-web), whose std sources (rust-web-src)
# `-Zbuild-std` compiles for that target with panic = "abort": rustup's
# toolchains here have no wasm32 std. They are installed when missing,
# with lld-22 (the linker) and binaryen (wasm-opt), as `make bench`
# installs what it needs. The page's scripts come from npm (web/package-lock.json)
# and are bundled by esbuild.
set -euo pipefail
cd "$(dirname "$0")/.."

OUT=${WEB_OUT:-target/web/site}
PACKAGES="rustc-web cargo-web rust-web-src lld-22 binaryen"
if ! dpkg -s $PACKAGES >/dev/null 2>&1; then
    echo "installing $PACKAGES" >&2
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $PACKAGES >/dev/null
fi

# Debian's tools by full path: rustup's come first on PATH.
RUSTC=/usr/bin/rustc RUSTC_BOOTSTRAP=1 CARGO_TARGET_DIR=target/web/cargo \
CARGO_PROFILE_RELEASE_PANIC=abort CARGO_PROFILE_RELEASE_LTO=fat \
CARGO_PROFILE_RELEASE_CODEGEN_UNITS=1 \
    /usr/bin/cargo build --release --locked -p raytracer-web \
    --config 'profile.release.package."*".opt-level="z"' \
    --config 'profile.release.package.raytracer-scene.opt-level="z"' \
    -Zbuild-std=std,panic_abort --target wasm32-unknown-unknown
WASM=target/web/cargo/wasm32-unknown-unknown/release/raytracer_web.wasm
mkdir -p target/web
# The features rustc 1.96 enables for wasm32 by default, which binaryen
# 108 wants named.
wasm-opt -Oz --enable-bulk-memory --enable-sign-ext --enable-mutable-globals \
    --enable-nontrapping-float-to-int --enable-multivalue --enable-reference-types \
    "$WASM" -o target/web/raytracer.wasm

(cd web && npm ci --no-audit --no-fund --silent)
rm -rf "$OUT"
mkdir -p "$OUT"
node web/build.mjs target/web/raytracer.wasm "$OUT"
echo "built $OUT ($(gzip -9c target/web/raytracer.wasm | wc -c) bytes of wasm gzipped)" >&2
