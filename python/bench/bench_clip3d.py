"""The cost of calling clip3d from Python against the C++ call it wraps.

    PYTHONPATH=build/rel/python /usr/bin/python3 python/bench/bench_clip3d.py \\
        [--domain ../shared/data/tetmeshes/sphere-fine.mesh] [--sites 1000000] [--runs 5] \\
        [--cli build/rel/bin/voroclip]

Per run: the wall time of voroclip.clip3d(domain, sites) seen from Python (argument
checks, the call with the GIL released, the result arrays and the Cells object) against
the time of ClippedVoronoi3::compute inside that same call (cells.seconds['total']), and,
with --cli, against the command-line tool's `clip3d --stats json` "total" on the same
sites (another process: the same compute, its own timing). The domain is validated once,
before the runs (as a user who computes several diagrams in it does). Prints per run and
the median of the per-run ratios."""

import argparse
import json
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import voroclip


def sites_in(domain, n, seed):
    lo, hi = np.array(domain.bounds[:3]), np.array(domain.bounds[3:])
    rng = np.random.default_rng(seed)
    out = np.empty((0, 3))
    while len(out) < n:
        p = lo + rng.random((2 * n, 3)) * (hi - lo)
        out = np.vstack([out, p[domain.locate(p) > 0]])
    return np.ascontiguousarray(out[:n])


def main():
    here = pathlib.Path(__file__).resolve().parents[2]
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--domain", default=str(here.parent / "shared/data/tetmeshes/sphere-fine.mesh"))
    ap.add_argument("--sites", type=int, default=1000000)
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--threads", type=int, default=None)
    ap.add_argument("--cli", default=None)
    a = ap.parse_args()
    domain = voroclip.domain3(a.domain)
    sites = sites_in(domain, a.sites, 1)
    print(f"{a.domain}: {a.sites} sites, {a.runs} runs, threads {a.threads or 'all'}")
    inner, cli = [], []
    with tempfile.TemporaryDirectory() as tmp:
        path = pathlib.Path(tmp) / "sites.txt"
        if a.cli:
            np.savetxt(path, sites, fmt="%.17g")
        for run in range(a.runs):
            t0 = time.perf_counter()
            cells = voroclip.clip3d(domain, sites, threads=a.threads)
            wall = time.perf_counter() - t0
            compute = cells.seconds["total"]
            inner.append(wall / compute)
            line = (f"run {run}: python {wall:.4f} s, C++ compute {compute:.4f} s, "
                    f"ratio {wall / compute:.4f}")
            if a.cli:
                args = [a.cli, "clip3d", a.domain, "--sites", str(path), "--stats", "json", "-q"]
                if a.threads:
                    args[1:1] = ["--threads", str(a.threads)]
                out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
                total = json.loads(out.strip().splitlines()[-1])["seconds"]["total"]
                cli.append(wall / total)
                line += f"; CLI compute {total:.4f} s, ratio {wall / total:.4f}"
            print(line, flush=True)
    print(f"median ratio python / C++ compute (same call): {statistics.median(inner):.4f}")
    if cli:
        print(f"median ratio python / CLI compute: {statistics.median(cli):.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
