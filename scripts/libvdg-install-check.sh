#!/usr/bin/env bash
# libvdg as a C project consumes it: installed with scripts/install-libvdg.sh into a
# temporary prefix (no root), then a C program (vdgformat/capi/tests/c/c89.c: the
# header under -std=c89 -pedantic, the version functions, the error string's lifetime)
# is built with nothing but `pkg-config --cflags --libs vdg`, once against the shared
# library (run through the SONAME link, checked with readelf) and once statically
# (`pkg-config --static`); each must end its output with "ok". Prints one line per check and exits non-zero on the first
# failure. Environment: PREFIX (default: a fresh temporary folder, removed at exit), CC.
# scripts/capi-check.sh runs it first.
set -euo pipefail
cd "$(dirname "$0")/.."
CC=${CC:-cc}
if [ -z "${PREFIX:-}" ]; then
    PREFIX=$(mktemp -d /tmp/libvdg-prefix-XXXXXX)
    trap 'rm -rf "$PREFIX"' EXIT
fi
nice -n 10 scripts/install-libvdg.sh "$PREFIX" >&2
export PKG_CONFIG_PATH="$PREFIX/lib/pkgconfig"
pkg-config --exists vdg || { echo "FAILED: pkg-config does not find vdg in $PKG_CONFIG_PATH" >&2; exit 1; }
echo "pkg-config: vdg $(pkg-config --modversion vdg): $(pkg-config --cflags --libs vdg)"
SRC=vdgformat/capi/tests/c/c89.c
WARN=(-std=c89 -pedantic -Wall -Wextra -Werror)
# shellcheck disable=SC2046 # pkg-config's flags are words
$CC "${WARN[@]}" $(pkg-config --cflags vdg) "$SRC" -o "$PREFIX/c89-shared" $(pkg-config --libs vdg)
SONAME=$(readelf -d "$PREFIX/lib/libvdg.so" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')
NEEDED=$(readelf -d "$PREFIX/c89-shared" | sed -n 's/.*(NEEDED).*\[\(libvdg[^]]*\)\]/\1/p')
[ -n "$SONAME" ] && [ "$SONAME" = "$NEEDED" ] && [ -e "$PREFIX/lib/$SONAME" ] || {
    echo "FAILED: the program needs '$NEEDED', the library's SONAME is '$SONAME'" >&2; exit 1; }
echo "shared: the program needs $NEEDED, the SONAME of the installed library"
OUT=$(LD_LIBRARY_PATH="$PREFIX/lib" "$PREFIX/c89-shared" | tail -1)
[ "$OUT" = ok ] || { echo "FAILED: the shared build printed: $OUT" >&2; exit 1; }
echo "shared: c89.c built with pkg-config --cflags --libs vdg runs: $OUT"
# The static build: only the archive in the library folder, so the linker cannot pick
# the shared library.
mkdir -p "$PREFIX/static/lib/pkgconfig"
cp "$PREFIX/lib/libvdg.a" "$PREFIX/static/lib/"
sed "s|^prefix=.*|prefix=$PREFIX/static|; s|^includedir=.*|includedir=$PREFIX/include|" \
    "$PREFIX/lib/pkgconfig/vdg.pc" >"$PREFIX/static/lib/pkgconfig/vdg.pc"
# shellcheck disable=SC2046
$CC "${WARN[@]}" $(PKG_CONFIG_PATH="$PREFIX/static/lib/pkgconfig" pkg-config --cflags vdg) "$SRC" \
    -o "$PREFIX/c89-static" $(PKG_CONFIG_PATH="$PREFIX/static/lib/pkgconfig" pkg-config --static --libs vdg)
if readelf -d "$PREFIX/c89-static" | grep -q 'NEEDED.*libvdg'; then
    echo "FAILED: the static build still needs libvdg.so" >&2; exit 1
fi
OUT=$("$PREFIX/c89-static" | tail -1)
[ "$OUT" = ok ] || { echo "FAILED: the static build printed: $OUT" >&2; exit 1; }
echo "static: c89.c built with pkg-config --static --libs vdg runs: $OUT"
echo "libvdg install check: ok"
