#!/usr/bin/env python3
"""Timing driver of scripts/peers/bench-delaunay.sh: medians of RUNS runs of ours, CGAL (when
CGAL_BIN names the built peer) and qhull (unless SKIP_QHULL=1) on every point file of OUT
(argv[1]), printed as a table. Ours and CGAL are run alternately, so both see the same
machine load."""
import json
import os
import re
import signal
import statistics
import subprocess
import sys
import tempfile

OURS = os.environ.get("OURS", "target/release/examples/tetrahedralize")
ORDER = ["uniform-100k", "uniform-1M", "walls-112k", "walls-112k-jitter", "walls-475k",
         "walls-475k-jitter", "de_dust2"]


def timed(cmd, stdin=None, timeout=None):
    """Run cmd under /usr/bin/time; return (stdout, wall s, peak MB, cpu s) or None."""
    with tempfile.NamedTemporaryFile("r") as tf:
        full = ["/usr/bin/time", "-f", "%e %M %U %S", "-o", tf.name] + cmd
        with open(stdin) if stdin else open(os.devnull) as inp:
            # Own process group, so a timeout kills the measured program too, not only
            # /usr/bin/time.
            proc = subprocess.Popen(full, stdin=inp, stdout=subprocess.PIPE,
                                    stderr=subprocess.PIPE, text=True, start_new_session=True)
            try:
                stdout, stderr = proc.communicate(timeout=timeout)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.communicate()
                sys.stderr.write("timeout after %.0f s: %s\n" % (timeout, " ".join(cmd)))
                return "timeout"
        out = subprocess.CompletedProcess(full, proc.returncode, stdout, stderr)
        if out.returncode != 0:
            sys.stderr.write("failed: %s: %s\n" % (" ".join(cmd), out.stderr[-300:]))
            return None
        wall, kb, user, system = tf.read().split()[-4:]
        return out.stdout, float(wall), int(kb) / 1024.0, float(user) + float(system)


def main():
    out_dir = sys.argv[1]
    runs = int(os.environ.get("RUNS", "3"))
    qruns = int(os.environ.get("QHULL_RUNS", "3"))
    # qhull needs ~5 minutes per run on the 475k wall samples: allow fewer runs there.
    qruns_large = int(os.environ.get("QHULL_RUNS_LARGE", str(qruns)))
    qtimeout = float(os.environ.get("QHULL_TIMEOUT", "900"))
    only = re.compile(os.environ.get("ONLY", "."))
    have_qhull = os.environ.get("SKIP_QHULL", "0") != "1" and subprocess.run(
        ["sh", "-c", "command -v qdelaunay"], capture_output=True).returncode == 0
    cgal = os.environ.get("CGAL_BIN")
    rows = []
    for name in ORDER:
        path = os.path.join(out_dir, name + ".txt")
        if not os.path.exists(path) or not only.search(name):
            continue
        ours, cg = [], []
        for _ in range(runs):
            r = timed([OURS, path])
            if r is None:
                break
            info = json.loads(r[0])
            ours.append((info["seconds"], r[1], r[2], info, r[3]))
            if cgal:
                r = timed([cgal, path])
                if r is not None:
                    c = json.loads(r[0])
                    cg.append((c["seconds"], r[1], r[2], c, r[3]))
        if not ours:
            continue
        info = ours[0][3]
        row = {
            "input": name,
            "points": info["points"],
            "tets": info["tetrahedra"],
            "tri_s": statistics.median(o[0] for o in ours),
            "proc_s": statistics.median(o[1] for o in ours),
            "mb": max(o[2] for o in ours),
            "cpu_s": statistics.median(o[4] for o in ours),
            "q_tets": None, "q_s": None, "q_mb": None, "q_cpu_s": None,
            "c_tets": None, "c_tri_s": None, "c_s": None, "c_mb": None, "c_cpu_s": None,
        }
        if cg:
            row["c_tets"] = cg[0][3]["tetrahedra"]
            row["c_tri_s"] = statistics.median(c[0] for c in cg)
            row["c_s"] = statistics.median(c[1] for c in cg)
            row["c_mb"] = max(c[2] for c in cg)
            row["c_cpu_s"] = statistics.median(c[4] for c in cg)
        if have_qhull:
            qs = []
            for _ in range(qruns if info["points"] <= 200000 else qruns_large):
                r = timed(["qdelaunay", "Qt", "i"], stdin=path, timeout=qtimeout)
                if r == "timeout":
                    row["q_timeout"] = True
                if r is None or r == "timeout":
                    break
                qs.append(r)
            if qs:
                row["q_tets"] = int(qs[0][0].split("\n", 1)[0])
                row["q_s"] = statistics.median(q[1] for q in qs)
                row["q_mb"] = max(q[2] for q in qs)
                row["q_cpu_s"] = statistics.median(q[3] for q in qs)
                row["q_runs"] = len(qs)
        rows.append(row)
        print_row(row, header=len(rows) == 1)
    print("\nours and CGAL: median of %d runs each, alternating; tri = triangulation only (JSON "
          "'seconds'), proc = whole process incl. file parsing (/usr/bin/time), cpu = user+sys "
          "of the process, peak = max RSS; CGAL = Delaunay_triangulation_3, Epick, range insert "
          "(spatial sort), g++ -O3; tri ratio = ours tri / CGAL tri, proc ratio = ours proc / "
          "CGAL proc, cpu ratio = ours cpu / CGAL cpu; qhull: `qdelaunay Qt i`, median of up to %d runs; q ratio = ours proc / "
          "qhull proc" % (runs, qruns))


def print_row(r, header):
    if header:
        print("| input | points | ours tets | ours tri s | ours proc s | ours cpu s | ours peak MB "
              "| CGAL tets | CGAL tri s | CGAL proc s | CGAL cpu s | CGAL peak MB | tri ratio "
              "| proc ratio | cpu ratio "
              "| qhull tets | qhull s | qhull cpu s | qhull peak MB | q ratio |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    f = lambda v, fmt: "-" if v is None else fmt % v
    ratio = None if not r["q_s"] else r["proc_s"] / r["q_s"]
    c_tri = None if not r["c_tri_s"] else r["tri_s"] / r["c_tri_s"]
    c_proc = None if not r["c_s"] else r["proc_s"] / r["c_s"]
    c_cpu = None if not r["c_cpu_s"] else r["cpu_s"] / r["c_cpu_s"]
    timeout = float(os.environ.get("QHULL_TIMEOUT", "900"))
    q_s = (">%.0f (timeout)" % timeout) if r.get("q_timeout") and r["q_s"] is None else (
        f(r["q_s"], "%.2f") + ("" if r["q_s"] is None or r["q_runs"] >= 3
                               else " (%d run)" % r["q_runs"]))
    print("| %s | %d | %d | %.3f | %.3f | %.3f | %.0f | %s | %s | %s | %s | %s | %s | %s | %s "
          "| %s | %s | %s | %s | %s |" % (
              r["input"], r["points"], r["tets"], r["tri_s"], r["proc_s"], r["cpu_s"], r["mb"],
              f(r["c_tets"], "%d"), f(r["c_tri_s"], "%.3f"), f(r["c_s"], "%.3f"),
              f(r["c_cpu_s"], "%.3f"), f(r["c_mb"], "%.0f"), f(c_tri, "%.2f"),
              f(c_proc, "%.2f"), f(c_cpu, "%.2f"),
              f(r["q_tets"], "%d"), q_s, f(r["q_cpu_s"], "%.2f"), f(r["q_mb"], "%.0f"),
              f(ratio, "%.4f")), flush=True)


if __name__ == "__main__":
    main()
