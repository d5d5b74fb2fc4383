#!/usr/bin/env python3
"""Checks of scripts/bake.py that need no Dask cluster: the per-map timeout, the log
each step returns, the refusal of two maps with one file name, and the progress lines.

    scripts/bake_test.py [--bsp2vdg PATH]      (default target/release/bsp2vdg)

Uses the generated maps of testdata/maps. Exit 0 on success, 1 on a failed check.
"""

import io
import os
import shutil
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import bake  # noqa: E402

ROOT = os.path.dirname(HERE)


def check(ok, what):
    print(("ok     " if ok else "FAILED ") + what)
    return ok


def main(argv):
    exe = os.path.abspath(argv[1] if argv[:1] == ["--bsp2vdg"] else os.path.join(ROOT, "target/release/bsp2vdg"))
    maps = sorted(os.path.join(ROOT, "testdata/maps", m) for m in os.listdir(os.path.join(ROOT, "testdata/maps"))
                  if m.endswith(".bsp"))
    good = True
    with open(maps[0], "rb") as f:
        data = f.read()
    r = bake.compile_step(data, ["-rl", "1.0"], exe, 1)
    good &= check(r["ok"] and "Loading model" in r["log"] and "{MAP}" in r["log"], "a step returns its log")
    # Fine sampling keeps this compile busy far longer than the timeout.
    r = bake.compile_step(data, ["-sd", "1", "-ms", "100000000"], exe, 1, timeout=0.5)
    good &= check(not r["ok"] and "timed out" in r["error"], f"--timeout kills a long compile ({r.get('error')})")
    good &= check("Loading model" in r.get("log", ""), "a timed-out step keeps the log written so far")

    r = bake.compile_step(data, ["-rl", "1.0"], exe, 1, budget=0)
    good &= check(r["ok"], f"--budget is passed to bsp2vdg ({r.get('error')})")
    r = bake.compile_step(data, ["-rl", "1.0"], exe, 1, budget=-1)
    good &= check(not r["ok"] and "--budget" in r["error"], f"a bad --budget is bsp2vdg's error ({r.get('error')})")

    d = tempfile.mkdtemp(prefix="bake-test-")
    try:
        for sub in ("a", "b"):
            os.mkdir(os.path.join(d, sub))
            shutil.copy(maps[0], os.path.join(d, sub, "x.bsp"))
        a, b = os.path.join(d, "a/x.bsp"), os.path.join(d, "b/x.bsp")
        good &= check(bake.duplicate_names([a, b]) == (a, b), "duplicate names are found")
        err = io.StringIO()
        old, sys.stderr = sys.stderr, err
        try:
            code = bake.main(["--bsp2vdg", exe, "--out", os.path.join(d, "out"), a, b])
        finally:
            sys.stderr = old
        good &= check(code == 2 and a in err.getvalue() and b in err.getvalue(),
                      "two maps with one name: exit 2 naming both")
    finally:
        shutil.rmtree(d)

    out = io.StringIO()
    p = bake.Progress(2, stream=out)
    p({"name": "e1m1", "status": "built", "ok": True, "seconds": 1.5})
    p({"name": "e1m2", "status": "FAILED", "ok": False, "error": "boom", "seconds": 0.1})
    good &= check(out.getvalue() == "[1/2] e1m1 built 1.5 s\n[2/2] e1m2 FAILED: boom 0.1 s\n",
                  "progress lines when piped")
    return 0 if good else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
