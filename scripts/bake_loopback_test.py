#!/usr/bin/env python3
"""The bake on a real Dask cluster on loopback, with a worker killed mid-batch.

    scripts/bake_loopback_test.py [--bsp2vdg PATH] MAPS... [-- BSP2VDG OPTIONS]

Starts `dask scheduler` and two `dask worker` processes on 127.0.0.1 (no nanny, so a
kill is final), bakes MAPS through scripts/bake.py with --scheduler, and when the first
map is done kills (SIGKILL) a worker that is compiling a map. Checks that every map
still gets its graph, that the killed worker's maps were redone by the other, and that
each graph is byte-identical to a direct `bsp2vdg` run. Exit 0 on success, 1 on a
failed check, 77 (skip) when dask.distributed is missing.
"""

import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def main(argv):
    try:
        from dask.distributed import Client
    except ImportError:
        print("skipped: the Python package dask.distributed is missing (pip install distributed)")
        return 77
    import bake

    if "--" in argv:
        i = argv.index("--")
        argv, options = argv[:i], argv[i + 1:]
    else:
        options = []
    exe = "target/release/bsp2vdg"
    if argv[:1] == ["--bsp2vdg"]:
        exe, argv = argv[1], argv[2:]
    exe = os.path.abspath(exe)
    maps = argv
    if len(maps) < 3:
        print("give at least three maps, so a worker is busy when the other is killed")
        return 2

    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    # The step function lives in scripts/bake.py, imported here as a module: the
    # scheduler and the workers import it too (run as a script, bake.py's functions
    # travel by value and workers need nothing).
    procs = []
    work = tempfile.mkdtemp(prefix="bake-loopback-")
    # The workers' private folders (bake.compile_step's temporary directories) go inside
    # the work folder: the killed worker cannot remove its own, and removing the work
    # folder at the end removes it.
    env = dict(os.environ, TMPDIR=work,
               PYTHONPATH=os.pathsep.join([HERE, os.environ.get("PYTHONPATH", "")]))
    ok = False
    logs = open(os.path.join(work, "cluster.log"), "w")
    try:
        procs.append(subprocess.Popen(
            ["dask", "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
            stdout=logs, stderr=logs, env=env))
        workers = {}
        for name in ("w0", "w1"):
            p = subprocess.Popen(
                ["dask", "worker", address, "--name", name, "--nthreads", "1", "--no-nanny",
                 "--host", "127.0.0.1", "--no-dashboard"],
                stdout=logs, stderr=logs, env=env)
            procs.append(p)
            workers[name] = p
        client = Client(address, timeout=60)
        client.wait_for_workers(2, timeout=60)
        names = {addr: w["name"] for addr, w in client.scheduler_info()["workers"].items()}
        killed = {}

        def on_result(row):
            if killed or row["status"] != "built":
                return
            busy = {a: ks for a, ks in client.processing().items() if ks}
            for addr, keys in busy.items():
                name = names.get(addr)
                if name in workers:
                    workers[name].send_signal(signal.SIGKILL)
                    workers[name].wait()
                    killed.update(name=name, keys=[str(k) for k in keys], at=time.time())
                    print(f"killed worker {name} (pid {workers[name].pid}) while it compiled {len(keys)} map(s)")
                    return

        out = os.path.join(work, "out")
        rows = bake.bake(maps, options, exe, out, os.path.join(work, "cache"), client,
                         use_cache=False, on_result=on_result)
        client.close()
        ok = True
        if not killed:
            print("FAILED: no worker was busy when the first map finished; nothing was killed")
            ok = False
        for r in rows:
            print(f"  {r['name']:<32} {r['status']:<7} {r.get('worker', '')}")
            if not r["ok"]:
                print(f"FAILED: {r['name']}: {r.get('error')}")
                ok = False
        redone = [r for r in rows if killed and f"bsp2vdg-{r['key']}" in killed["keys"]]
        if killed and not redone:
            print("FAILED: the killed worker's maps are not in the results")
            ok = False
        for r in redone:
            print(f"  {r['name']} was on the killed worker and was redone: {r['status']}")
        # Determinism: each baked graph equals a direct compile.
        for r in rows:
            if not r["ok"]:
                continue
            direct = os.path.join(work, r["name"] + ".direct.vdg")
            subprocess.run([exe, *options, "-threads", "1", "-nolog", "-quiet", "-o", direct, r["map"]],
                           check=True)
            with open(direct, "rb") as a, open(os.path.join(out, r["name"] + ".vdg"), "rb") as b:
                if a.read() != b.read():
                    print(f"FAILED: {r['name']}: the baked graph differs from a direct compile")
                    ok = False
        print("ok: every map baked, the killed worker's maps redone elsewhere, outputs identical"
              if ok else f"cluster log: {logs.name}")
        return 0 if ok else 1
    finally:
        for p in procs:
            if p.poll() is None:
                p.terminate()
        for p in procs:
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
        logs.close()
        # A failed run keeps its folder (the cluster log is in it); a passed one leaves nothing.
        if ok:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
