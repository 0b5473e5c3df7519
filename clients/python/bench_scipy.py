"""bench_scipy.py -- scipy.spatial.Voronoi against the voronoid client.

    make && /usr/bin/python3 clients/python/bench_scipy.py [--sizes 100000,1000000]
        [--rounds 3] [--daemon build/voronoid | --url http://host:port]

For uniform points in the unit square (fixed seed) it times, in this
process and in rounds (each round runs the three once, in the same order):

- scipy:  scipy.spatial.Voronoi(points), regions included (scipy builds
          them as lists);
- client: voronoid.voronoi(points) end to end -- the request, the
          service's computation, reading the binary answer into numpy
          arrays; then, separately, building all of .regions as lists of
          lists, as scipy does eagerly (the client does it on first use);
- JSON:   the same request as JSON, as a script without the client would
          send it: json.dumps of {"points": points.tolist()}, the POST,
          json.loads of the answer and numpy arrays of vertices and
          ridge_points.

and prints the median of each with the service's own compute time. Without
--url it starts the daemon (release build) on an ephemeral loopback port.
A measurement, not a test: the numbers depend on the machine and its load.
"""

import argparse
import json
import os
import re
import signal
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request

import numpy as np
from scipy.spatial import Voronoi

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import voronoid  # noqa: E402


def start_daemon(binary):
    log = tempfile.NamedTemporaryFile(prefix="voronoid-bench-", suffix=".log",
                                      delete=False)
    proc = subprocess.Popen([binary, "--port", "0"], stdout=subprocess.DEVNULL,
                            stderr=log)
    log.close()
    for _ in range(600):
        with open(log.name) as f:
            m = re.search(r"listening on (http://127\.0\.0\.1:\d+)/", f.read())
        if m:
            return proc, m.group(1), log.name
        time.sleep(0.05)
    proc.kill()
    raise RuntimeError(f"{binary} did not start")


def json_round_trip(url, xy):
    body = json.dumps({"points": xy.tolist()}).encode()
    req = urllib.request.Request(url + "/voronoi", data=body, method="POST",
                                 headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(req, timeout=3600) as r:
        j = json.loads(r.read())
    vertices = np.array(j["vertices"], dtype=float)
    ridge_points = np.array([e["sites"] for e in j["edges"]], dtype=np.intp)
    return j["timings"]["compute_ms"], vertices, ridge_points


def timed(f):
    t0 = time.perf_counter()
    out = f()
    return time.perf_counter() - t0, out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="100000,1000000")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--daemon", default="build/voronoid")
    ap.add_argument("--url")
    args = ap.parse_args()
    proc = None
    url = args.url
    if url is None:
        proc, url, logname = start_daemon(args.daemon)
    try:
        print(f"# {os.cpu_count()} CPUs, numpy {np.__version__}, "
              f"scipy {__import__('scipy').__version__}, service {url}")
        print("| points | scipy.spatial.Voronoi | client (binary) | of which the "
              "service's compute | all regions as lists | JSON round trip "
              "| scipy / client | JSON / client |")
        print("| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
        for n in [int(s) for s in args.sizes.split(",")]:
            xy = np.random.default_rng(args.seed).random((n, 2))
            t = {"scipy": [], "client": [], "regions": [], "json": [], "compute": []}
            for _ in range(args.rounds):
                dt, _ = timed(lambda: Voronoi(xy).regions)
                t["scipy"].append(dt)
                dt, d = timed(lambda: voronoid.voronoi(xy, url=url))
                t["client"].append(dt)
                t["compute"].append(d.timings["compute_ms"] / 1e3)
                dt, _ = timed(lambda: d.regions)
                t["regions"].append(dt)
                dt, _ = timed(lambda: json_round_trip(url, xy))
                t["json"].append(dt)
            m = {k: statistics.median(v) for k, v in t.items()}
            print(f"| {n:,} | {m['scipy']:.2f} s | {m['client']:.2f} s | "
                  f"{m['compute']:.2f} s | {m['regions']:.2f} s | {m['json']:.2f} s | "
                  f"{m['scipy'] / m['client']:.1f}x | {m['json'] / m['client']:.1f}x |",
                  flush=True)
    finally:
        if proc is not None:
            proc.send_signal(signal.SIGTERM)
            proc.wait(timeout=60)
            os.unlink(logname)


if __name__ == "__main__":
    main()
