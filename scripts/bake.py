#!/usr/bin/env python3
"""Bake many maps on Dask.distributed: one hermetic `bsp2vdg MAP.bsp -o MAP.vdg` step per map.

    scripts/bake.py [options] MAPS... [-- BSP2VDG OPTIONS]

Why Dask.distributed: it installs from PyPI with pip (Bazel's remote execution is not
installable here from the reachable registries, and needs a REAPI server besides), it runs
on this machine with nothing set up (a LocalCluster of worker processes), and the same
command scales to a cluster by giving a scheduler address (`dask scheduler` plus
`dask worker ADDRESS` on each machine). Its scheduler re-runs the tasks of a worker that
dies on the remaining workers, so a killed worker loses nothing. Ray would serve too, but
is a much larger install for what is a map of independent subprocess steps.

Each step is hermetic: the map's bytes travel with the task, the worker compiles them in a
private temporary folder, and returns the .vdg's bytes and the log (bsp2vdg records no
path or file name, so the output depends on the bytes and options only). Results are cached
by a content key, sha256(map bytes) + options + `bsp2vdg --version`, in --cache (on the
client), so an unchanged map is never compiled again and identical maps are compiled once.
A failing map is reported in the summary; the others go on. Exit status 1 when a map failed.

Options:
  --scheduler ADDRESS   run on an existing cluster (tcp://host:8786); default: a local
                        cluster of --workers processes on 127.0.0.1
  --workers N           local worker processes (default 1); ignored with --scheduler
  --threads N           -threads of each bsp2vdg step (default 1: one map per core)
  --bsp2vdg PATH        the compiler on the workers (default target/release/bsp2vdg)
  --out DIR             where MAP.vdg go (default target/bake)
  --cache DIR           content-addressed cache (default target/bake-cache)
  --no-cache            compile everything again (the cache is still refreshed)
  --json                the summary as JSON on stdout
  --timeout SECONDS     kill a map's compile after SECONDS; the map fails, the others go on
  --budget SCALE        bsp2vdg's --budget for each map (its time and memory budget, which
                        fails a map with the reason; 0 = none); default: bsp2vdg's own

Progress: a line per finished map on stderr (self-updating on a terminal). Each map's
compile log goes to OUT/NAME.log. Two maps with one file name are refused (exit 2).
"""

import argparse
import hashlib
import json
import os
import subprocess
import sys
import time


def compile_step(map_bytes, options, exe, threads, timeout=None, budget=None):
    """The step a worker runs: bsp2vdg on the map's bytes in a private folder.

    Returns a dict with ok, log (the compile's log text), and vdg (bytes) and stats on
    success or error on failure; a failing map is a result, not an exception, so the
    batch goes on. A compile running longer than `timeout` seconds is killed and fails;
    `budget` is bsp2vdg's `--budget` scale (its own time and memory budget per map, which
    stops a compile with the reason before the timeout's kill)."""
    import socket
    import tempfile

    started = time.time()
    with tempfile.TemporaryDirectory(prefix="bsp2vdg-bake-") as d:
        bsp = os.path.join(d, "map.bsp")
        out = os.path.join(d, "map.vdg")
        with open(bsp, "wb") as f:
            f.write(map_bytes)
        log_path = os.path.join(d, "map.log")
        cmd = [exe, *options, "-threads", str(threads), "-quiet", "--json", "-o", out, bsp]
        if budget is not None:
            cmd[1:1] = ["--budget", f"{budget:g}"]
        where = f"{socket.gethostname()}:{os.getpid()}"

        def log_text():
            try:
                with open(log_path, encoding="utf-8", errors="replace") as f:
                    return f.read().replace(bsp, "{MAP}")
            except OSError:
                return ""

        try:
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            # bsp2vdg appends its log as it goes: what it did before the kill is kept.
            return {"ok": False, "error": f"timed out after {timeout:g} s (--timeout)",
                    "worker": where, "log": log_text()}
        except OSError as e:
            return {"ok": False, "error": f"cannot run {exe}: {e}", "log": ""}
        if p.returncode != 0 or not os.path.exists(out):
            lines = [l for l in (p.stderr or "").splitlines() if l.strip()]
            try:
                error = json.loads(p.stdout).get("error")
            except (ValueError, AttributeError):
                error = None
            error = error or (lines[-1] if lines else f"exit status {p.returncode}")
            # Name the map, not this step's private copy of it.
            return {"ok": False, "error": error.replace(bsp, "MAP"), "worker": where, "log": log_text()}
        with open(out, "rb") as f:
            vdg = f.read()
        stats = json.loads(p.stdout)
        return {"ok": True, "vdg": vdg, "stats": stats, "seconds": time.time() - started, "worker": where,
                "log": log_text()}


def tool_version(exe):
    p = subprocess.run([exe, "--version"], capture_output=True, text=True, check=True)
    return p.stdout.strip()


def content_key(map_bytes, options, version):
    h = hashlib.sha256()
    h.update(map_bytes)
    h.update(b"\0" + "\0".join(options).encode() + b"\0" + version.encode())
    return h.hexdigest()


def write_atomic(path, data):
    tmp = f"{path}.tmp{os.getpid()}"
    with open(tmp, "wb") as f:
        f.write(data)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def duplicate_names(maps):
    """The first two maps that would write one NAME.vdg, or None."""
    seen = {}
    for m in maps:
        name = os.path.splitext(os.path.basename(m))[0]
        if name in seen:
            return seen[name], m
        seen[name] = m
    return None


class Progress:
    """One line per finished map on stderr ("[3/12] e1m1 built 4.2 s"); on a terminal
    the line rewrites itself, piped output stays plain lines."""

    def __init__(self, total, stream=sys.stderr):
        self.total, self.done, self.stream = total, 0, stream
        self.tty = stream.isatty()

    def __call__(self, row):
        self.done += 1
        what = row["status"] if row["ok"] else f"FAILED: {row.get('error', '')}"
        line = f"[{self.done}/{self.total}] {row['name']} {what} {row.get('seconds', 0.0):.1f} s"
        try:
            if self.tty:
                end = "\n" if self.done == self.total or not row["ok"] else ""
                self.stream.write("\r\x1b[K" + line[:200] + end)
            else:
                self.stream.write(line + "\n")
            self.stream.flush()
        except OSError:
            pass  # progress never stops the bake


def bake(maps, options, exe, out_dir, cache_dir, client, threads=1, use_cache=True, on_result=None,
         timeout=None, budget=None):
    """Compiles `maps` on the Dask `client`; returns one summary row per map, in order.
    Each map's log goes to OUT/NAME.log as its compile finishes.

    `on_result(row)` is called as each map finishes (the tests kill a worker there)."""
    from dask.distributed import as_completed

    version = tool_version(exe)
    os.makedirs(out_dir, exist_ok=True)
    os.makedirs(cache_dir, exist_ok=True)
    rows = {}
    futures = {}
    for m in maps:
        name = os.path.splitext(os.path.basename(m))[0]
        with open(m, "rb") as f:
            data = f.read()
        key = content_key(data, options, version)
        cached = os.path.join(cache_dir, key + ".vdg")
        row = {"map": m, "name": name, "key": key}
        if use_cache and os.path.exists(cached):
            with open(cached, "rb") as f:
                write_atomic(os.path.join(out_dir, name + ".vdg"), f.read())
            row.update(status="cached", ok=True, seconds=0.0, worker="-")
            rows[m] = row
            if on_result:
                on_result(row)
            continue
        if key in futures.values():  # the same bytes twice: compiled once
            row["same_as_key"] = True
        # The budget is left out of the cache key: it decides whether a compile may
        # finish, never what it writes.
        fut = client.submit(compile_step, data, options, exe, threads, timeout, budget,
                            key=f"bsp2vdg-{key}", pure=False)
        futures[fut] = key
        rows[m] = row
    by_key = {}
    for fut in as_completed(list(futures)):
        key = futures[fut]
        try:
            result = fut.result()
        except Exception as e:  # e.g. KilledWorker after repeated worker deaths
            result = {"ok": False, "error": f"{type(e).__name__}: {e}", "worker": "-"}
        by_key[key] = result
        if result["ok"]:
            write_atomic(os.path.join(cache_dir, key + ".vdg"), result["vdg"])
        for m, row in rows.items():
            if row["key"] != key or "status" in row:
                continue
            if result.get("log"):
                write_atomic(os.path.join(out_dir, row["name"] + ".log"),
                             result["log"].replace("{MAP}", m).encode())
            if result["ok"]:
                write_atomic(os.path.join(out_dir, row["name"] + ".vdg"), result["vdg"])
                row.update(status="built", ok=True, seconds=result["seconds"], worker=result["worker"],
                           vertices=result["stats"].get("vertices"), bytes=result["stats"].get("bytes"))
            else:
                row.update(status="FAILED", ok=False, error=result["error"].replace("MAP", m),
                           worker=result.get("worker", "-"))
            if on_result:
                on_result(row)
    return [rows[m] for m in maps]


def connect(scheduler, workers):
    """A client: to the given scheduler, or to a new local cluster on loopback."""
    from dask.distributed import Client, LocalCluster

    if scheduler:
        return Client(scheduler), None
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                           host="127.0.0.1", dashboard_address=None)
    return Client(cluster), cluster


def main(argv):
    if "--" in argv:
        i = argv.index("--")
        argv, options = argv[:i], argv[i + 1:]
    else:
        options = []
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("maps", nargs="+")
    ap.add_argument("--scheduler")
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--bsp2vdg", default="target/release/bsp2vdg")
    ap.add_argument("--out", default="target/bake")
    ap.add_argument("--cache", default="target/bake-cache")
    ap.add_argument("--no-cache", action="store_true")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--timeout", type=float, default=None)
    ap.add_argument("--budget", type=float, default=None)
    a = ap.parse_args(argv)
    if a.budget is not None and not a.budget >= 0:
        print(f"bake.py: error: --budget must be zero or a positive scale, got {a.budget:g}", file=sys.stderr)
        return 2
    if a.timeout is not None and not a.timeout > 0:
        print(f"bake.py: error: --timeout must be a positive number of seconds, got {a.timeout:g}",
              file=sys.stderr)
        return 2
    exe = os.path.abspath(a.bsp2vdg)
    if not os.access(exe, os.X_OK):
        print(f"bake.py: error: {exe} is not an executable bsp2vdg (cargo build --release -p bsp2vdg)", file=sys.stderr)
        return 2
    for m in a.maps:
        if not os.path.isfile(m):
            print(f"bake.py: error: {m}: no such map file", file=sys.stderr)
            return 2
    dup = duplicate_names(a.maps)
    if dup:
        print(f"bake.py: error: {dup[0]} and {dup[1]} would both be written to "
              f"{os.path.splitext(os.path.basename(dup[1]))[0]}.vdg; give the maps different names",
              file=sys.stderr)
        return 2
    try:
        import distributed  # noqa: F401
    except ImportError:
        print("bake.py: error: the Python package dask.distributed is missing (pip install distributed)", file=sys.stderr)
        return 2
    client, cluster = connect(a.scheduler, a.workers)
    started = time.time()
    try:
        rows = bake(a.maps, options, exe, a.out, a.cache, client, a.threads, not a.no_cache,
                    on_result=Progress(len(a.maps)), timeout=a.timeout, budget=a.budget)
    finally:
        client.close()
        if cluster:
            cluster.close()
    wall = time.time() - started
    failed = sum(1 for r in rows if not r["ok"])
    if a.json:
        print(json.dumps({"maps": rows, "seconds": wall, "failed": failed}))
    else:
        print(f"{'map':<36} {'status':<7} {'seconds':>8}  worker / error")
        for r in rows:
            tail = r.get("error") or r.get("worker", "")
            print(f"{r['name']:<36} {r['status']:<7} {r.get('seconds', 0.0):>8.2f}  {tail}")
        print(f"{len(rows)} maps in {wall:.1f} s ({60 * len(rows) / wall:.1f} maps/min), {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
