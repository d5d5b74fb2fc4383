#!/usr/bin/env python3
"""Checks of scripts/bake.py that need no Dask cluster: the per-map timeout, the log
each step returns, the refusal of two maps with one file name, the progress lines (plain
when piped, one self-rewriting line on a terminal), and a whole bake() on an in-process
stand-in for the Dask client: one log per map in OUT/NAME.log and a progress report per
map as it finishes. Run by `cargo test -p bsp2vdg --test bake`.

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
    tty = Terminal()
    p = bake.Progress(3, stream=tty)
    for name in ("e1m1", "e1m2", "e1m3"):
        p({"name": name, "status": "built", "ok": True, "seconds": 1.0})
    good &= check(tty.getvalue() == "\r\x1b[K[1/3] e1m1 built 1.0 s\r\x1b[K[2/3] e1m2 built 1.0 s"
                  "\r\x1b[K[3/3] e1m3 built 1.0 s\n", f"one self-rewriting line on a terminal ({tty.getvalue()!r})")
    good &= bake_in_process(exe, maps[:2])
    return 0 if good else 1


class Terminal(io.StringIO):
    """A stream that says it is a terminal."""

    def isatty(self):
        return True


class Done:
    """A finished stand-in for a Dask future."""

    def __init__(self, value):
        self.value = value

    def result(self):
        return self.value


class InProcessClient:
    """Runs each submitted step at once, in this process, as a Dask client would on a worker."""

    def submit(self, fn, *args, key=None, pure=None):
        return Done(fn(*args))


def bake_in_process(exe, maps):
    """bake() with the stand-in client: a log per map beside its graph, progress per map."""
    import types

    fake = types.ModuleType("dask.distributed")
    fake.as_completed = iter
    saved = {k: sys.modules.get(k) for k in ("dask", "dask.distributed")}
    sys.modules["dask"] = types.ModuleType("dask")
    sys.modules["dask.distributed"] = fake
    d = tempfile.mkdtemp(prefix="bake-test-")
    good = True
    try:
        seen = []
        rows = bake.bake(maps, ["-rl", "1.0"], exe, os.path.join(d, "out"), os.path.join(d, "cache"),
                         InProcessClient(), on_result=seen.append)
        names = [os.path.splitext(os.path.basename(m))[0] for m in maps]
        good &= check([r["name"] for r in seen] == names and all(r["ok"] for r in rows),
                      f"bake() reports each map as it finishes ({[r.get('status') for r in seen]})")
        for m, name in zip(maps, names):
            log = os.path.join(d, "out", name + ".log")
            text = open(log).read() if os.path.exists(log) else ""
            good &= check("Loading model" in text and m in text and "{MAP}" not in text,
                          f"OUT/{name}.log holds the map's compile log, naming the map")
            good &= check(os.path.getsize(os.path.join(d, "out", name + ".vdg")) > 0, f"OUT/{name}.vdg written")
    finally:
        shutil.rmtree(d)
        for k, v in saved.items():
            if v is None:
                sys.modules.pop(k, None)
            else:
                sys.modules[k] = v
    return good


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
