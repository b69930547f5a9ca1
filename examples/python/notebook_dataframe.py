#!/usr/bin/env python3
"""A pandas DataFrame of a sample channel, for a notebook (each "# %%" is a cell;
Jupyter and VS Code run them as such). Needs pandas (Debian: python3-pandas).

    PYTHONPATH=build/python python3 examples/python/notebook_dataframe.py --seconds 2
"""

# %%
from __future__ import annotations

import argparse
import sys

import nclink

parser = argparse.ArgumentParser(description="a sample channel as a pandas DataFrame")
parser.add_argument("--broker", default="tcp://127.0.0.1:1883")
parser.add_argument("--device", default="nclink-sim-mill-01")
parser.add_argument("--channel", default="ch_fast")
parser.add_argument("--seconds", type=float, default=2.0)
args, _ = parser.parse_known_args()  # a notebook passes its own arguments

try:
    import pandas as pd
except ImportError:
    print("notebook_dataframe: needs pandas (apt-get install python3-pandas)", file=sys.stderr)
    sys.exit(2)

# %% Connect and read the channel for a while.
client = nclink.connect(args.broker, register=False)
model = client.model(args.device)
with client.samples(args.device, args.channel, timeout=10) as stream:
    frame = nclink.dataframe(stream.collect(seconds=args.seconds))
client.close()

# %% One row per sample, indexed by UTC time; a column per point.
print(frame.head())
units = {n.id: n.get("units", "") for n in model.items}
print({c: units.get(c, "") for c in frame.columns if c != "channel"})

# %% What a data team does next: resample to 10 ms means, describe.
numeric = frame.drop(columns=["channel"]).apply(pd.to_numeric, errors="coerce")
print(numeric.resample("10ms").mean().describe())
print(f"rows={len(frame)}")
