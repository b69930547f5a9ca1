#!/usr/bin/env python3
"""The machine's state over a period (an hour by default), summarised: how long it
was running, idle and in alarm.

A dynamic sample channel (Register/Sample) reads the run status, the active
alarms and the emergency stop every --sample-ms; each row counts for that long:
  alarm    an alarm is active (WARNING item not empty) or the emergency stop is pressed
  running  otherwise, status "running"
  idle     otherwise (free, holding)
The client keeps the channel's registration alive for the whole period.

    PYTHONPATH=build/python python3 examples/python/state_summary.py --device nclink-sim-mill-01
    PYTHONPATH=build/python python3 examples/python/state_summary.py --duration 60 --json
"""

from __future__ import annotations

import argparse
import json
import sys
import threading
import time
from typing import Any, Dict

import nclink

STATES = ("running", "idle", "alarm")


def classify(status: Any, warning: Any, emergency: Any) -> str:
    if emergency is True or (isinstance(warning, (list, dict)) and len(warning) > 0):
        return "alarm"
    return "running" if status == "running" else "idle"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--broker", default="tcp://127.0.0.1:1883")
    parser.add_argument("--device", default="nclink-sim-mill-01")
    parser.add_argument("--duration", type=float, default=3600.0, help="seconds to watch (default 3600)")
    parser.add_argument("--sample-ms", type=float, default=100.0)
    parser.add_argument("--json", action="store_true", help="print the summary as JSON")
    args = parser.parse_args()

    seconds: Dict[str, float] = {s: 0.0 for s in STATES}
    lock = threading.Lock()
    rows = 0

    def on_batch(batch: nclink.SampleBatch) -> None:  # on the client's dispatch thread
        nonlocal rows
        with lock:
            for _, status, warning, emergency in batch.rows:
                seconds[classify(status, warning, emergency)] += batch.interval_ms / 1000.0
                rows += 1

    try:
        with nclink.connect(args.broker, register=False) as client:
            upload_ms = max(args.sample_ms, 1000.0)
            with client.sample(args.device, ["status", "warning", "emergency_stop"], args.sample_ms, upload_ms,
                               on_batch):
                # Said once the channel is registered: the period starts here
                # (a script driving the machine waits for this line).
                print(f"state_summary: watching {args.device} for {args.duration:g} s (Ctrl-C ends early)",
                      file=sys.stderr, flush=True)
                time.sleep(args.duration)
    except nclink.Error as e:
        print(f"state_summary: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        pass

    with lock:
        total = sum(seconds.values())
        summary = {s: {"seconds": round(seconds[s], 3), "percent": round(100 * seconds[s] / total, 1) if total else 0}
                   for s in STATES}
        summary["rows"] = {"seconds": round(total, 3), "percent": 100.0 if total else 0}
        n = rows
    if args.json:
        print(json.dumps({"device": args.device, "rows": n, "states": summary}))
    else:
        print(f"{args.device}: {total:.1f} s observed ({n} rows)")
        for s in STATES:
            print(f"  {s:<8} {seconds[s]:10.1f} s  {summary[s]['percent']:5.1f} %")
    return 0


if __name__ == "__main__":
    sys.exit(main())
