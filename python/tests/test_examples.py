"""Every example in examples/python/, run against nclink-sim as a user runs it."""

from __future__ import annotations

import csv
import json
import os
import subprocess
import sys
import time

import pytest

import nclink
from conftest import DEV, SOURCE_DIR, Sim

EXAMPLES = os.path.join(os.environ.get("NCLINK_SOURCE_DIR", SOURCE_DIR), "examples", "python")


def run(script: str, *args: str, timeout: float = 60) -> "subprocess.CompletedProcess[str]":
    return subprocess.run([sys.executable, os.path.join(EXAMPLES, script), *args], capture_output=True, text=True,
                          timeout=timeout, env=os.environ.copy())


def test_channel_to_csv(sim: Sim, workdir: str) -> None:
    out = os.path.join(workdir, "fast.csv")
    done = run("channel_to_csv.py", "--broker", sim.broker.url, "--device", DEV, "--channel", "ch_fast",
               "--rows", "300", "--seconds", "20", "--out", out)
    assert done.returncode == 0, done.stderr
    with open(out) as f:
        rows = list(csv.reader(f))
    assert rows[0][:3] == ["time", "x_position", "y_position"]
    assert len(rows) - 1 >= 300
    assert rows[1][0].endswith("Z")
    # A row's value may be null (a missed tick, written as an empty
    # cell); every other cell is a number, and most rows have them.
    values = [row[1] for row in rows[1:] if row[1] != ""]
    assert all(float(v) == float(v) for v in values)
    assert len(values) >= (len(rows) - 1) // 2


def test_channel_to_csv_unknown_device_fails_clearly(sim: Sim) -> None:
    done = run("channel_to_csv.py", "--broker", sim.broker.url, "--device", "no-such-device", "--seconds", "1")
    assert done.returncode == 1
    assert "203 Timeout" in done.stderr


def make_warning_setable(client: nclink.Client) -> None:
    """The mill's WARNING item made setable by Probe/Set, so the test can raise an alarm."""
    model = client.model(DEV)
    model.find("warning").raw["setable"] = True
    client.probe_set(DEV, model)


def test_state_summary(sim: Sim, client: nclink.Client) -> None:
    make_warning_setable(client)
    client.call(DEV, "reset")  # idle
    proc = subprocess.Popen([sys.executable, os.path.join(EXAMPLES, "state_summary.py"), "--broker", sim.broker.url,
                             "--device", DEV, "--duration", "6", "--sample-ms", "50", "--json"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=os.environ.copy())
    # The period starts when the script says its channel is registered, not
    # when it was started: a loaded machine can take seconds to import and
    # connect, and the idle stretch would then go unobserved.
    assert proc.stderr is not None
    ready = proc.stderr.readline()
    assert ready.startswith("state_summary: watching"), ready + proc.stderr.read()
    time.sleep(1.5)
    client.call(DEV, "cycle_start")  # running
    time.sleep(1.5)
    client.put(DEV, "warning", {"number": "1001", "text": "spindle overload"})  # alarm
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 0, err
    summary = json.loads(out)
    states = summary["states"]
    assert states["running"]["seconds"] > 0.3
    assert states["alarm"]["seconds"] > 0.3
    assert states["idle"]["seconds"] > 0.3
    assert summary["rows"] > 30


def test_notebook_dataframe(sim: Sim) -> None:
    pytest.importorskip("pandas", reason="pandas is not installed (Debian: apt-get install python3-pandas); "
                                         "the notebook example is left unrun")
    done = run("notebook_dataframe.py", "--broker", sim.broker.url, "--device", DEV, "--seconds", "1")
    assert done.returncode == 0, done.stderr
    assert "x_position" in done.stdout
    rows = int(done.stdout.strip().splitlines()[-1].split("=")[1])
    assert rows >= 300
