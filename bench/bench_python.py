#!/usr/bin/env python3
"""The Python package's cost over the C++ client (docs/python.md, "Performance").

1. Query round trip: nclink.Client.query() against nclink::Client::query()
   (through nclink._nclink.bench_cpp_query), same process, same broker and
   nclink-sim, alternating rounds so both see the same load. Goal: Python's
   median <= 1.3x the C++ median.
2. Sample rows handed to a Python callback: Sample DTUs of 100 rows x 6
   points (the sim's ch_fast shape) published at QoS 1 by mosquitto_pub, each
   row handed to the callback as a tuple (batch.rows). Goal: >= 200,000
   rows/s, none lost (the count must match what was published).

Starts its own mosquitto on a free loopback port and build/bin/nclink-sim.
Figures on a shared machine are noisy: run it more than once.

    PYTHONPATH=build/python python3 bench/bench_python.py [--queries N] [--dtus N] [--quick]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from typing import List

import nclink
from nclink import _nclink

HERE = os.path.dirname(os.path.abspath(__file__))
DEV = "nclink-sim-mill-01"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def wait_for_port(port: int) -> None:
    for _ in range(200):
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=0.2):
                return
        except OSError:
            time.sleep(0.05)
    raise RuntimeError("mosquitto did not start")


def percentile(values: List[float], p: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(p * len(ordered)))]


def bench_query(url: str, total: int, rounds: int) -> dict:
    py_times: List[float] = []
    cpp_times: List[float] = []
    per_round = max(1, total // rounds)
    with nclink.Client(url) as client:
        client.connect(register=False)
        for _ in range(50):  # warm up
            client.query(DEV, ["x_position"])
        _nclink.bench_cpp_query(url, "bench-cpp-warm", DEV, "x_position", 50)
        py_cpu = cpp_cpu = 0.0
        for r in range(rounds):
            c0 = time.process_time()
            for _ in range(per_round):
                t0 = time.perf_counter()
                client.query(DEV, ["x_position"])
                py_times.append((time.perf_counter() - t0) * 1e6)
            c1 = time.process_time()
            cpp_times.extend(_nclink.bench_cpp_query(url, f"bench-cpp-{r}", DEV, "x_position", per_round))
            py_cpu += c1 - c0
            cpp_cpu += time.process_time() - c1
    py_median, cpp_median = statistics.median(py_times), statistics.median(cpp_times)
    return {"queries_each": len(py_times),
            "python_median_us": round(py_median, 1), "python_p99_us": round(percentile(py_times, 0.99), 1),
            "cpp_median_us": round(cpp_median, 1), "cpp_p99_us": round(percentile(cpp_times, 0.99), 1),
            "ratio_median": round(py_median / cpp_median, 3), "goal_ratio": 1.3,
            # This process's CPU per query (every thread: MQTT, dispatch, the
            # caller), less dependent on the machine's other load than the
            # round trip; the C++ side includes its connect and stop.
            "python_cpu_us_per_query": round(py_cpu / len(py_times) * 1e6, 1),
            "cpp_cpu_us_per_query": round(cpp_cpu / len(cpp_times) * 1e6, 1)}


def sample_dtu(n: int, rows: int, points: int) -> str:
    data = [{"data": [round(1000.0 * p + n + r / 1000.0, 3) for r in range(rows)]} for p in range(points)]
    return json.dumps({"guid": "benchdev", "id": "ch", "beginTime": str(1_700_000_000_000 + n * rows),
                       "data": data}, separators=(",", ":"))


def bench_samples(url: str, port: int, dtus: int, rows: int = 100, points: int = 6, materialise: bool = True) -> dict:
    layout = {"id": "bench", "type": "NC_LINK_ROOT", "devices": [{"id": "d", "type": "MACHINE", "configs": [
        {"id": "ch", "type": "SAMPLE_CHANNEL", "sampleInterval": 1, "uploadInterval": 100,
         "ids": [{"id": f"p{i}"} for i in range(points)]}]}]}
    got = 0
    first = last = 0.0
    finished = threading.Event()
    expected = dtus * rows

    def on_batch(batch: nclink.SampleBatch) -> None:
        nonlocal got, first, last
        if got == 0:
            first = time.perf_counter()
        got += len(batch.rows) if materialise else len(batch)  # rows: each a tuple (time, p0, ..., p5)
        last = time.perf_counter()
        if got >= expected:
            finished.set()

    payload = "\n".join(sample_dtu(n, rows, points) for n in range(dtus)) + "\n"
    with nclink.Client(url, log_level="error") as client:
        client.connect(register=False)
        client.on_samples("benchdev", on_batch, "ch", model=layout)
        time.sleep(0.3)  # the subscription reaches the broker
        cpu0 = time.process_time()
        pub = subprocess.run(["mosquitto_pub", "-p", str(port), "-h", "127.0.0.1", "-q", "1", "-t",
                              "Sample/benchdev/ch", "-l"], input=payload.encode(), timeout=300)
        if pub.returncode != 0:
            raise RuntimeError("mosquitto_pub failed")
        finished.wait(120)
        time.sleep(0.5)  # anything beyond the expected count would show up now
        cpu = time.process_time() - cpu0
        stats = client.stats()
    elapsed = max(last - first, 1e-9)
    return {"dtus": dtus, "rows_published": expected, "rows_received": got, "lost": expected - got,
            "rows_as_tuples": materialise,
            "rows_per_s": round((got - rows) / elapsed) if got > rows else 0, "goal_rows_per_s": 200_000,
            # This process's CPU (MQTT receive, decoding, dispatch, Python) per
            # row: the capacity of one core, less dependent on other load.
            "rows_per_cpu_s": round(got / cpu) if cpu > 0 else 0,
            "client_samples": stats["samples"], "duplicates": stats["duplicates"]}


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--queries", type=int, default=4000)
    parser.add_argument("--dtus", type=int, default=5000)
    parser.add_argument("--quick", action="store_true", help="a short run (the test suite's smoke run)")
    parser.add_argument("--sim", default=os.environ.get("NCLINK_SIM",
                                                        os.path.join(HERE, "..", "build", "bin", "nclink-sim")))
    args = parser.parse_args()
    if args.quick:
        args.queries, args.dtus = 200, 200
    mosquitto = next((p for p in ("/usr/sbin/mosquitto", "/usr/bin/mosquitto") if os.access(p, os.X_OK)),
                     shutil.which("mosquitto"))
    if not mosquitto:
        print("bench_python: mosquitto not found", file=sys.stderr)
        return 2
    with tempfile.TemporaryDirectory(prefix="nclink-bench-py-") as d:
        port = free_port()
        url = f"tcp://127.0.0.1:{port}"
        conf = os.path.join(d, "mosquitto.conf")
        with open(conf, "w") as f:
            f.write(f"listener {port} 127.0.0.1\nallow_anonymous true\npersistence false\n"
                    "max_queued_messages 1000000\nmax_inflight_messages 0\nlog_dest none\n"
                    # Without it mosquitto's own sockets wait for delayed ACKs
                    # (Nagle): every round trip ~44 ms for Python and C++ alike,
                    # which hides the cost being measured.
                    "set_tcp_nodelay true\n")
        broker = subprocess.Popen([mosquitto, "-c", conf])
        sim = None
        try:
            wait_for_port(port)
            sim = subprocess.Popen([args.sim, "--broker", url, "--log-level", "warn"])
            with nclink.Client(url, timeout=0.5) as c:
                c.connect(register=False)
                for _ in range(100):
                    try:
                        c.get(DEV, "status")
                        break
                    except nclink.Error:
                        time.sleep(0.1)
            result: dict = {"machine": f"{os.cpu_count()} cores, load {os.getloadavg()[0]:.1f} at start (shared box)",
                      "query": bench_query(url, args.queries, 10),
                      "samples": bench_samples(url, port, args.dtus),
                      "samples_counted_only": bench_samples(url, port, args.dtus, materialise=False)}
            print(json.dumps(result, indent=2))
            lost = result["samples"]["lost"] + result["samples_counted_only"]["lost"]
            return 0 if lost == 0 else 1
        finally:
            if sim:
                sim.terminate()
                sim.wait()
            broker.terminate()
            broker.wait()


if __name__ == "__main__":
    sys.exit(main())
