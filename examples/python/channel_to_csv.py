#!/usr/bin/env python3
"""A sample channel into a CSV file: one line per row, its time (UTC, ISO 8601, ms)
and one column per point of the channel.

    PYTHONPATH=build/python python3 examples/python/channel_to_csv.py \
        --device nclink-sim-mill-01 --channel ch_fast --seconds 10 --out fast.csv

Runs until --seconds pass or --rows rows are written (Ctrl-C stops it too).
"""

from __future__ import annotations

import argparse
import csv
import datetime
import sys

import nclink


def iso(seconds: float) -> str:
    t = datetime.datetime.fromtimestamp(seconds, tz=datetime.timezone.utc)
    return t.isoformat(timespec="milliseconds").replace("+00:00", "Z")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--broker", default="tcp://127.0.0.1:1883")
    parser.add_argument("--device", default="nclink-sim-mill-01")
    parser.add_argument("--channel", default="ch_fast")
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--rows", type=int, default=None)
    parser.add_argument("--out", default="-", help="CSV file (default: standard output)")
    args = parser.parse_args()

    out = sys.stdout if args.out == "-" else open(args.out, "w", newline="")
    written = 0
    try:
        with nclink.connect(args.broker, register=False) as client:
            writer = None
            with client.samples(args.device, args.channel, timeout=10) as stream:
                for batch in stream.collect(seconds=args.seconds, rows=args.rows):
                    if writer is None:
                        writer = csv.writer(out)
                        writer.writerow(["time"] + batch.ids)
                    for row in batch.rows:
                        writer.writerow([iso(row[0])] + ["" if v is None else v for v in row[1:]])
                        written += 1
    except nclink.Error as e:
        print(f"channel_to_csv: {e}", file=sys.stderr)
        return 1
    finally:
        if out is not sys.stdout:
            out.close()
    print(f"channel_to_csv: {written} rows", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
