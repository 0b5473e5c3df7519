#!/usr/bin/env python3
"""soak.py -- voronoid under long, mixed and hostile load (make soak).

Starts a daemon (VOR_DAEMON, default build/asan/voronoid: the sanitizer
build, whose reports end up in its log) on an ephemeral loopback port and
runs one scenario against it, then prints what it saw. Not part of
`make test`: it measures, over minutes, what the integration tests check
in seconds.

Scenarios (--scenario):
  mixed      (make soak) SOAK_SECONDS (default 600) of: small requests on
             kept-alive connections, large ones (10^4..3x10^5 points, JSON,
             gzip, binary, /compare) read whole, slow readers, clients that
             never read, slow writers (headers and bodies trickled),
             aborted uploads, hostile framing, SIGHUP every 30 s; then the
             load stops, and after a rest SIGTERM under small load. Prints
             requests by status, small-request p50/p99, peak, post-warm-up
             and final RSS, resets seen by clients, sanitizer reports.
  nonreaders --clients N: N clients ask for 10^6-point JSON answers and
             never read, while a client sends a small request every 50 ms;
             prints peak RSS against the budget and the small client's
             success and latency.
  slowloris  --clients N (1100): N connections trickle request headers a
             byte a second (reconnecting when closed), from --attackers
             addresses (127.0.1.x), while a client on 127.0.0.1 sends a
             5-point POST every 50 ms on a new connection; prints its
             success rate and p50/p99.
  sigterm    --runs N: N daemons each stopped with SIGTERM under eight
             clients connecting in a loop; prints resets, unanswered
             requests and exit statuses.

Every loop is bounded in time and the daemon is always stopped. Only
loopback addresses are used.
"""
import argparse
import gzip
import http.client
import json
import os
import random
import resource
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SMALL = b'{"points":[[0,0],[1,0],[0,1],[1,1],[0.5,0.5]]}'


def now():
    return time.monotonic()


class Daemon:
    def __init__(self, args):
        binary = os.environ.get("VOR_DAEMON",
                                os.path.join(ROOT, "build/asan/voronoid"))
        self.dir = tempfile.mkdtemp(prefix="voronoid-soak-")
        self.log = os.path.join(self.dir, "daemon.log")
        env = dict(os.environ)
        env.setdefault("ASAN_OPTIONS", "detect_leaks=1:halt_on_error=0")
        env.setdefault("UBSAN_OPTIONS", "print_stacktrace=1:halt_on_error=0")
        self.proc = subprocess.Popen(
            [binary, "--bind", "127.0.0.1", "--port", "0"] + args,
            stdout=open(self.log, "wb"), stderr=subprocess.STDOUT, env=env)
        self.port = None
        until = now() + 60
        while now() < until and self.port is None:
            with open(self.log, "rb") as f:
                text = f.read().decode("latin-1")
            i = text.find("listening on http://127.0.0.1:")
            if i >= 0:
                self.port = int(text[i + 30:].split("/")[0])
            elif self.proc.poll() is not None:
                break
            time.sleep(0.02)
        if self.port is None:
            raise SystemExit("soak: the daemon did not start:\n" + text[-2000:])

    def rss(self):
        try:
            with open("/proc/%d/status" % self.proc.pid) as f:
                for line in f:
                    if line.startswith("VmRSS:"):
                        return int(line.split()[1]) * 1024
        except OSError:
            pass
        return 0

    def signal(self, sig):
        if self.proc.poll() is None:
            self.proc.send_signal(sig)

    def stop(self, timeout=120):
        self.signal(signal.SIGTERM)
        try:
            return self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            return self.proc.wait()

    def sanitizer_reports(self):
        with open(self.log, "rb") as f:
            text = f.read().decode("latin-1")
        return (text.count("ERROR: AddressSanitizer") +
                text.count("ERROR: LeakSanitizer") +
                text.count("runtime error:") +
                text.count("WARNING: ThreadSanitizer"))

    def metric(self, series):
        try:
            c = http.client.HTTPConnection("127.0.0.1", self.port, timeout=10)
            c.request("GET", "/metrics")
            text = c.getresponse().read().decode()
            c.close()
        except OSError:
            return None
        for line in text.splitlines():
            if line.startswith(series + " "):
                return float(line.split()[-1])
        return None


class Tally:
    """Outcomes of requests, by kind and status, thread-safe."""

    def __init__(self):
        self.lock = threading.Lock()
        self.status = {}
        self.resets = 0
        self.lat = []

    def add(self, kind, status, seconds=None):
        with self.lock:
            key = (kind, status)
            self.status[key] = self.status.get(key, 0) + 1
            if seconds is not None:
                self.lat.append(seconds)

    def reset(self):
        with self.lock:
            self.resets += 1


def percentile(xs, p):
    if not xs:
        return float("nan")
    xs = sorted(xs)
    return xs[min(len(xs) - 1, int(len(xs) * p))]


def raw_request(port, data, read=True, timeout=60, src=None):
    """Sends data, reads until the peer closes; returns (status, reset)."""
    s = socket.socket()
    s.settimeout(timeout)
    if src:
        s.bind((src, 0))
    try:
        try:
            s.connect(("127.0.0.1", port))
        except ConnectionRefusedError:
            return -1, False  # nobody listening: not an accepted request
        s.sendall(data)
        out = b""
        if read:
            while True:
                b = s.recv(65536)
                if not b:
                    break
                out += b
        st = int(out[9:12]) if out.startswith(b"HTTP/1.1 ") else 0
        return st, False
    except ConnectionResetError:
        return 0, True
    except (socket.timeout, BrokenPipeError, ConnectionRefusedError, OSError):
        return 0, False
    finally:
        s.close()


def post(port, body, path="/voronoi", headers=None, timeout=120, conn=None):
    """One POST; returns (status, body, conn-to-reuse)."""
    c = conn or http.client.HTTPConnection("127.0.0.1", port, timeout=timeout)
    h = {"Content-Type": "application/json"}
    h.update(headers or {})
    c.request("POST", path, body=body, headers=h)
    r = c.getresponse()
    data = r.read()
    if r.getheader("Connection", "").lower() == "close":
        c.close()
        c = None
    return r.status, data, c


# ---- mixed ---------------------------------------------------------------

def mixed(args):
    seconds = float(os.environ.get("SOAK_SECONDS", "600"))
    d = Daemon(["--drain", "1", "--grace", "30", "--send-timeout", "5",
                "--header-timeout", "5", "--max-connections-per-ip", "0"])
    print("soak: daemon pid %d port %d, %g s of mixed load" %
          (d.proc.pid, d.port, seconds))
    t = Tally()
    stop = threading.Event()
    rnd = random.Random(12)

    def guarded(kind, fn):
        def loop():
            r = random.Random(hash(kind) & 0xffff)
            while not stop.is_set():
                try:
                    fn(r)
                except ConnectionResetError:
                    t.reset()
                except (OSError, http.client.HTTPException):
                    t.add(kind, "error")
        th = threading.Thread(target=loop, daemon=True)
        th.start()
        return th

    conns = {}

    def small(r):
        tid = threading.get_ident()
        t0 = now()
        st, _, c = post(d.port, SMALL, conn=conns.get(tid), timeout=30)
        conns[tid] = c
        t.add("small", st, now() - t0)
        time.sleep(0.005)

    def large(r):
        n = r.choice([10000, 50000, 100000, 300000])
        fmt = r.choice(["json", "json", "binary", "geojson", "timings"])
        body = json.dumps({"generate": {"distribution": r.choice(
            ["uniform", "gaussian", "clustered"]), "n": n, "seed": r.randrange(99)},
            "format": fmt}).encode()
        path = "/compare" if r.random() < 0.15 else "/voronoi"
        hdr = {"Accept-Encoding": "gzip"} if r.random() < 0.3 else {}
        st, data, _ = post(d.port, body, path=path, headers=hdr)
        if st == 200 and hdr and data[:2] == b"\x1f\x8b":
            gzip.decompress(data)
        t.add("large", st)

    def slow_reader(r):
        body = json.dumps({"generate": {"n": r.choice([100000, 300000])}}).encode()
        s = socket.create_connection(("127.0.0.1", d.port), timeout=30)
        s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 8192)
        s.sendall(b"POST /voronoi HTTP/1.1\r\nHost: x\r\nContent-Length: %d\r\n\r\n"
                  % len(body) + body)
        got = 0
        end = now() + r.uniform(2, 8)
        stalled = r.random() < 0.4  # stop reading entirely
        try:
            while now() < end and not stop.is_set():
                if not stalled:
                    b = s.recv(4096)
                    if not b:
                        break
                    got += len(b)
                time.sleep(0.05)
            st = "read" if got else "stalled"
            t.add("slow-reader", st)
        finally:
            s.close()

    def slow_writer(r):
        s = socket.create_connection(("127.0.0.1", d.port), timeout=30)
        try:
            if r.random() < 0.5:
                req = b"GET /healthz HTTP/1.1\r\nHost: x\r\nX-Slow: " + b"a" * 40
            else:
                req = (b"POST /voronoi HTTP/1.1\r\nHost: x\r\nContent-Length: 5000"
                       b"\r\n\r\n" + b"0 0\n" * 10)
            for i in range(len(req)):
                s.send(req[i:i + 1])
                time.sleep(0.3)
                if stop.is_set():
                    break
        except (BrokenPipeError, ConnectionResetError, OSError):
            pass
        try:
            out = s.recv(4096)
            t.add("slow-writer", int(out[9:12]) if out.startswith(b"HTTP/1.1") else 0)
        except OSError:
            t.add("slow-writer", 0)
        s.close()

    def aborted(r):
        s = socket.create_connection(("127.0.0.1", d.port), timeout=30)
        body = b"0 0\n1 1\n" * 5000
        s.sendall(b"POST /voronoi HTTP/1.1\r\nHost: x\r\nContent-Type: text/plain\r\n"
                  b"Content-Length: %d\r\n\r\n" % len(body) + body[: len(body) // 2])
        time.sleep(r.uniform(0, 0.5))
        s.close()
        t.add("aborted", "closed")
        time.sleep(0.2)

    def hostile(r):
        reqs = [
            b"POST /voronoi HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: gzip, chunked\r\n\r\n",
            b"POST /voronoi HTTP/1.1\r\nHost: x\r\nContent-Length: 5\r\nContent-Length: 7\r\n\r\n12345",
            b"GET /" + b"a" * 16100 + b" HTTP/1.1\r\nHost: x\r\n\r\n",
            b"POST /voronoi HTTP/1.1\r\nHost: x\r\nContent-Encoding: gzip\r\nContent-Length: "
            + str(len(BOMB)).encode() + b"\r\n\r\n" + BOMB,
            b"\x16\x03\x01garbage\r\n\r\n",
        ]
        st, reset = raw_request(d.port, r.choice(reqs), timeout=30)
        if reset:
            t.reset()
        t.add("hostile", st)
        time.sleep(0.05)

    BOMB = gzip.compress(b" " * (256 << 20), 9)
    threads = [guarded("small", small) for _ in range(4)]
    threads += [guarded("large", large), guarded("slow-reader", slow_reader),
                guarded("slow-reader", slow_reader), guarded("slow-writer", slow_writer),
                guarded("aborted", aborted), guarded("hostile", hostile)]
    t0 = now()
    peak = 0
    warm = None
    next_hup = t0 + 30
    hups = 0
    while now() - t0 < seconds:
        rss = d.rss()
        peak = max(peak, rss)
        if warm is None and now() - t0 > min(60, seconds / 5):
            warm = rss
        if now() >= next_hup:
            d.signal(signal.SIGHUP)
            hups += 1
            next_hup += 30
        time.sleep(0.5)
    stop.set()
    for th in threads:
        th.join(60)
    time.sleep(10)  # the load has stopped: what stays?
    rest = d.rss()
    # SIGTERM under small load.
    term = Tally()
    tstop = threading.Event()

    def small_loop():
        while not tstop.is_set():
            st, reset = raw_request(d.port, b"POST /voronoi HTTP/1.1\r\nHost: x\r\n"
                                    b"Connection: close\r\n"
                                    b"Content-Length: %d\r\n\r\n" % len(SMALL) + SMALL)
            if reset:
                term.reset()
            elif st == -1:
                break  # no longer listening
            else:
                term.add("term", st)
    tl = [threading.Thread(target=small_loop, daemon=True) for _ in range(4)]
    for th in tl:
        th.start()
    time.sleep(1)
    rc = d.stop()
    tstop.set()
    for th in tl:
        th.join(30)
    reports = d.sanitizer_reports()

    print("soak: %.0f s of load, %d SIGHUP" % (now() - t0 - 10, hups))
    print("requests by kind and status:")
    for (kind, st), n in sorted(t.status.items(), key=lambda kv: (kv[0][0], str(kv[0][1]))):
        print("  %-12s %-8s %d" % (kind, st, n))
    print("small requests: p50 %.1f ms, p99 %.1f ms" %
          (1000 * percentile(t.lat, 0.5), 1000 * percentile(t.lat, 0.99)))
    print("RSS: peak %.0f MiB, after warm-up %.0f MiB, after the load %.0f MiB "
          "(%+.0f%%)" % (peak / 2**20, (warm or 0) / 2**20, rest / 2**20,
                         100.0 * (rest - (warm or rest)) / (warm or rest or 1)))
    print("resets seen by clients: %d during the load, %d during SIGTERM" %
          (t.resets, term.resets))
    print("SIGTERM under load: %s, exit %d" %
          (", ".join("%s x %d" % (st, n) for (_, st), n in sorted(term.status.items(),
                                                                  key=lambda kv: str(kv[0][1]))),
           rc))
    print("sanitizer reports in the daemon's log: %d (%s)" % (reports, d.log))
    # Only 200, 4xx and 503 -- and 501, the answer the hostile requests
    # with a Transfer-Encoding other than chunked must get.
    bad = [k for k in t.status if isinstance(k[1], int) and not (
        k[1] == 200 or 400 <= k[1] < 500 or k[1] == 503 or k[1] == 0 or
        (k[0] == "hostile" and k[1] == 501))]
    ok = not bad and rc == 0 and reports == 0 and term.resets == 0
    print("soak: %s" % ("ok" if ok else "FAILED (statuses %s)" % bad))
    return 0 if ok else 1


# ---- the targets -----------------------------------------------------

def small_client(port, stop, out, src="127.0.0.1", every=0.05):
    while not stop.is_set():
        t0 = now()
        st, reset = raw_request(port, b"POST /voronoi HTTP/1.1\r\nHost: x\r\n"
                                b"Connection: close\r\nContent-Length: %d\r\n\r\n"
                                % len(SMALL) + SMALL, timeout=10, src=src)
        out.append((st, now() - t0, reset))
        rest = every - (now() - t0)
        if rest > 0:
            time.sleep(rest)


def summary(out):
    ok = sum(1 for st, _, _ in out if st == 200)
    lat = [dt for _, dt, _ in out]
    return ("%d/%d ok (%.2f%%), p50 %.1f ms, p99 %.1f ms" %
            (ok, len(out), 100.0 * ok / max(1, len(out)),
             1000 * percentile(lat, 0.5), 1000 * percentile(lat, 0.99)))


def nonreaders(args):
    d = Daemon(["--drain", "0"] + args.flags)
    budget = d.metric("voronoid_answer_memory_capacity_bytes") or 0
    body = b'{"generate":{"n":1000000,"seed":1}}'
    socks = []
    for i in range(args.clients):
        s = socket.socket()
        s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        s.connect(("127.0.0.1", d.port))
        s.sendall(b"POST /voronoi HTTP/1.1\r\nHost: x\r\nContent-Length: %d\r\n\r\n"
                  % len(body) + body)
        socks.append(s)
    stop = threading.Event()
    out = []
    th = threading.Thread(target=small_client, args=(d.port, stop, out))
    th.start()
    peak = 0
    t0 = now()
    while now() - t0 < args.seconds:
        peak = max(peak, d.rss())
        time.sleep(0.1)
    stop.set()
    th.join()
    statuses = {}
    for s in socks:
        s.settimeout(1)
        try:
            b = s.recv(64)
            st = b[9:12].decode() if b.startswith(b"HTTP/1.1") else "closed"
        except OSError:
            st = "closed"
        statuses[st] = statuses.get(st, 0) + 1
        s.close()
    refused = d.metric("voronoid_answer_memory_refused_total")
    bpeak = d.metric("voronoid_answer_memory_peak_bytes")
    time.sleep(1)
    final = d.rss()
    rc = d.stop()
    print("non-readers: %d clients of 10^6-point JSON; budget %.0f MiB (peak "
          "accounted %.0f MiB); peak RSS %.0f MiB, final %.0f MiB; first bytes "
          "they got: %s; refused by the budget: %d; small client: %s; exit %d" %
          (args.clients, budget / 2**20, (bpeak or 0) / 2**20, peak / 2**20,
           final / 2**20, statuses, refused or 0, summary(out), rc))
    return 0 if peak <= budget and rc == 0 else 1


def slowloris(args):
    d = Daemon(["--drain", "0"] + args.flags)
    srcs = ["127.0.1.%d" % (1 + i % 250) for i in range(args.attackers)]
    stop = threading.Event()
    state = {"opened": 0, "closed_by_server": 0, "408": 0}

    def attacker():
        conns = []
        req = b"GET /healthz HTTP/1.1\r\nHost: x\r\nX-Slow: " + b"a" * 4000
        import select
        last = 0
        while not stop.is_set():
            while len(conns) < args.clients and not stop.is_set():
                s = socket.socket()
                s.setblocking(False)
                try:
                    s.bind((srcs[len(conns) % len(srcs)], 0))
                    s.connect_ex(("127.0.0.1", d.port))
                except OSError:
                    s.close()
                    break
                conns.append([s, 0])
                state["opened"] += 1
            if now() - last >= 1.0:  # one byte a second each
                last = now()
                for c in conns:
                    try:
                        c[0].send(req[c[1]:c[1] + 1])
                        c[1] = (c[1] + 1) % len(req)
                    except OSError:
                        pass
            poller = select.poll()
            for c in conns:
                poller.register(c[0], select.POLLIN)
            r = [fd for fd, _ in poller.poll(50)]
            if r:
                keep = []
                dead = set(r)
                for c in conns:
                    if c[0].fileno() in dead:
                        try:
                            b = c[0].recv(4096)
                        except OSError:
                            b = b""
                        if b.startswith(b"HTTP/1.1 408"):
                            state["408"] += 1
                        state["closed_by_server"] += 1
                        c[0].close()
                    else:
                        keep.append(c)
                conns = keep
        for c in conns:
            c[0].close()

    at = threading.Thread(target=attacker)
    at.start()
    time.sleep(3)  # let the tricklers take their connections
    out = []
    cstop = threading.Event()
    th = threading.Thread(target=small_client, args=(d.port, cstop, out))
    th.start()
    time.sleep(args.seconds)
    cstop.set()
    th.join()
    stop.set()
    at.join()
    conns = d.metric("voronoid_connections")
    rc = d.stop()
    print("slowloris: %d trickling connections from %d address(es) (%d opened, "
          "%d closed by the server, %d with a 408); client on 127.0.0.1: %s; "
          "exit %d" % (args.clients, args.attackers, state["opened"],
                       state["closed_by_server"], state["408"], summary(out), rc))
    ok = sum(1 for st, _, _ in out if st == 200) >= 0.99 * len(out)
    return 0 if ok and rc == 0 else 1


def sigterm_runs(args):
    total_resets = total_unanswered = 0
    for run in range(args.runs):
        d = Daemon(["--drain", "1", "--grace", "30"] + args.flags)
        stop = threading.Event()
        res = []

        def loop():
            while not stop.is_set():
                st, reset = raw_request(d.port, b"POST /voronoi HTTP/1.1\r\nHost: x\r\n"
                                        b"Connection: close\r\n"
                                        b"Content-Length: %d\r\n\r\n" % len(SMALL) + SMALL,
                                        timeout=30)
                if st == -1:
                    break  # the daemon stopped listening
                res.append((st, reset))
        ths = [threading.Thread(target=loop) for _ in range(8)]
        for th in ths:
            th.start()
        time.sleep(0.5)
        d.signal(signal.SIGTERM)
        rc = d.proc.wait(120)
        stop.set()
        for th in ths:
            th.join(30)
        resets = sum(1 for _, r in res if r)
        by = {}
        for st, r in res:
            if not r:
                by[st] = by.get(st, 0) + 1
        unanswered = by.pop(0, 0)
        total_resets += resets
        total_unanswered += unanswered
        print("run %d: %s; %d resets; %d accepted but unanswered; exit %d" %
              (run + 1, ", ".join("%s x %d" % kv for kv in sorted(by.items())),
               resets, unanswered, rc))
    print("sigterm: %d runs, %d resets and %d unanswered in all" %
          (args.runs, total_resets, total_unanswered))
    return 0 if total_resets == 0 and total_unanswered == 0 else 1


def main():
    resource.setrlimit(resource.RLIMIT_NOFILE, (20000, 20000))
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--scenario", default="mixed",
                   choices=["mixed", "nonreaders", "slowloris", "sigterm"])
    p.add_argument("--clients", type=int, default=12)
    p.add_argument("--attackers", type=int, default=1)
    p.add_argument("--runs", type=int, default=10)
    p.add_argument("--seconds", type=float, default=40)
    p.add_argument("flags", nargs="*", help="more flags for the daemon")
    args = p.parse_args()
    fn = {"mixed": mixed, "nonreaders": nonreaders, "slowloris": slowloris,
          "sigterm": sigterm_runs}[args.scenario]
    return fn(args)


if __name__ == "__main__":
    sys.exit(main())
