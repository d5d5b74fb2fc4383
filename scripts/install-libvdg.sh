#!/usr/bin/env bash
# Installs libvdg (the C ABI of vdgformat) under PREFIX, as a Unix library is
# installed: lib/libvdg.so.VERSION with the links libvdg.so.ABI (its SONAME) and
# libvdg.so, lib/libvdg.a, include/vdg.h and lib/pkgconfig/vdg.pc, so a build finds
# it with `pkg-config --cflags --libs vdg` (PKG_CONFIG_PATH=PREFIX/lib/pkgconfig).
# usage: scripts/install-libvdg.sh PREFIX        (builds the release library first)
set -euo pipefail
cd "$(dirname "$0")/.."
PREFIX=${1:?usage: scripts/install-libvdg.sh PREFIX}
cargo build --release -q -p vdgformat-capi
VERSION=$(sed -n 's/^version = "\(.*\)"/\1/p' Cargo.toml | head -1)
ABI=$(sed -n 's/^pub const VDG_ABI_VERSION: c_int = \([0-9]*\);/\1/p' vdgformat/capi/src/lib.rs)
[ -n "$VERSION" ] && [ -n "$ABI" ] || { echo "cannot read the version or the ABI version" >&2; exit 1; }
mkdir -p "$PREFIX/lib/pkgconfig" "$PREFIX/include"
PREFIX=$(cd "$PREFIX" && pwd)
install -m 644 vdgformat/capi/include/vdg.h "$PREFIX/include/vdg.h"
install -m 644 target/release/libvdg.a "$PREFIX/lib/libvdg.a"
install -m 755 target/release/libvdg.so "$PREFIX/lib/libvdg.so.$VERSION"
ln -sf "libvdg.so.$VERSION" "$PREFIX/lib/libvdg.so.$ABI"
ln -sf "libvdg.so.$ABI" "$PREFIX/lib/libvdg.so"
sed -e "s|@PREFIX@|$PREFIX|" -e "s|@VERSION@|$VERSION|" vdgformat/capi/vdg.pc.in \
    >"$PREFIX/lib/pkgconfig/vdg.pc"
echo "installed libvdg $VERSION (ABI $ABI) in $PREFIX"
