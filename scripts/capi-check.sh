#!/usr/bin/env bash
# libvdg's C proof under a memory checker, and its camera timed against the Rust API.
#
# 0. Installs libvdg into a temporary prefix and builds a C program against it with
#    pkg-config alone, shared and static (scripts/libvdg-install-check.sh; no root).
# 1. Runs the C proof (vdgformat/capi/tests/c_smoke.rs) in the release profile, keeping
#    the compiled tests/c/smoke.c, the generated complex.vdg, the script and a corrupt
#    copy in $OUT (the test checks the C output bit for bit against the Rust API).
# 2. Runs smoke under valgrind (memcheck: invalid reads/writes, uninitialised values,
#    definite/indirect leaks are errors) and requires 0 errors and the same output as
#    without valgrind. Without valgrind (apt-get install valgrind) it rebuilds smoke with
#    AddressSanitizer instead (CHECKER=asan forces that).
# 3. Times the 600 camera frames: smoke (C API, REPEAT runs, median us/frame) and the
#    camera_frames example (Rust API, same frames), alternated ROUNDS times under nice.
# Environment: OUT (default target/capi-check), REPEAT=30, ROUNDS=5, CHECKER=valgrind|asan.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-target/capi-check}
REPEAT=${REPEAT:-30}
ROUNDS=${ROUNDS:-5}
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)

echo "== install into a temporary prefix, build with pkg-config" >&2
scripts/libvdg-install-check.sh

echo "== C proof (release): cargo test -p vdgformat-capi --test c_smoke" >&2
SMOKE_KEEP="$OUT" nice cargo test --release -q -p vdgformat-capi --test c_smoke >&2
ARGS=("$OUT/complex.vdg" "$OUT/script.txt" "$OUT/corrupt.vdg")
"$OUT/smoke" "${ARGS[@]}" >"$OUT/plain.out"

CHECKER=${CHECKER:-$(command -v valgrind >/dev/null && echo valgrind || echo asan)}
if [ "$CHECKER" = valgrind ]; then
    echo "== valgrind memcheck" >&2
    valgrind --error-exitcode=99 --leak-check=full \
        --errors-for-leak-kinds=definite,indirect --track-origins=yes \
        --log-file="$OUT/valgrind.log" "$OUT/smoke" "${ARGS[@]}" >"$OUT/checked.out" || {
        echo "valgrind found errors:" >&2
        cat "$OUT/valgrind.log" >&2
        exit 1
    }
    grep -E "ERROR SUMMARY|definitely lost|indirectly lost" "$OUT/valgrind.log" >&2
else
    echo "== AddressSanitizer + UndefinedBehaviorSanitizer" >&2
    LIB=$(ls target/release/deps/libvdg.a 2>/dev/null || echo target/release/libvdg.a)
    ${CC:-cc} -std=c99 -O1 -g -fsanitize=address,undefined -fno-omit-frame-pointer \
        -Ivdgformat/capi/include vdgformat/capi/tests/c/smoke.c "$LIB" \
        -lgcc_s -lutil -lrt -lpthread -lm -ldl -lc -o "$OUT/smoke-asan"
    ASAN_OPTIONS=detect_leaks=1:halt_on_error=1 UBSAN_OPTIONS=halt_on_error=1 \
        "$OUT/smoke-asan" "${ARGS[@]}" >"$OUT/checked.out"
    echo "asan/ubsan: 0 errors" >&2
fi
cmp "$OUT/plain.out" "$OUT/checked.out" || { echo "output differs under $CHECKER" >&2; exit 1; }

echo "== camera time per frame, C API vs Rust API ($ROUNDS rounds, $REPEAT runs each)" >&2
nice cargo build --release -q -p vdgformat-capi --example camera_frames
for round in $(seq "$ROUNDS"); do
    nice -n 10 "$OUT/smoke" "${ARGS[@]}" "$REPEAT" 2>&1 >/dev/null | sed "s/^/round $round: /"
    nice -n 10 target/release/examples/camera_frames "$OUT/complex.vdg" "$OUT/script.txt" "$REPEAT" 2>&1 \
        | sed "s/^/round $round: /"
done | tee "$OUT/timing.txt" >&2
# Median over the rounds of each API's median, and their ratio.
awk '/C camera/ {c[nc++] = $6} /Rust camera/ {r[nr++] = $6}
    function med(a, n,   i, j, t) {
        for (i = 0; i < n; i++) for (j = i + 1; j < n; j++) if (a[j] < a[i]) { t = a[i]; a[i] = a[j]; a[j] = t }
        return a[int(n / 2)]
    }
    END { mc = med(c, nc); mr = med(r, nr)
          printf "camera per frame: C API %.1f us, Rust API %.1f us (medians of %d rounds), C/Rust %.3f\n", mc, mr, nc, mc / mr }' \
    "$OUT/timing.txt"
