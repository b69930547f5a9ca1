"""Fixtures of the Python tests: a real mosquitto on a free loopback port and
nclink-sim (the simulated 3-axis mill) connected to it, both started here and
stopped after each test; ctest (python/tests/CMakeLists.txt) passes the
programs' paths in NCLINK_SIM and PYTHONPATH=build/python."""

from __future__ import annotations

import json
import os
import shutil
import signal
import socket
import subprocess
import tempfile
import time
from typing import Any, Callable, Dict, Iterator, List, Optional

import pytest

import nclink

DEV = "nclink-sim-mill-01"
HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE_DIR = os.path.dirname(os.path.dirname(HERE))


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def wait_for_port(port: int, timeout: float = 10.0) -> None:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=0.2):
                return
        except OSError:
            time.sleep(0.05)
    raise RuntimeError(f"nothing listens on 127.0.0.1:{port}")


def stop_process(process: "Optional[subprocess.Popen[bytes]]", grace: float, sig: int = signal.SIGTERM) -> None:
    """Stops a program the tests started: `sig`, then SIGKILL after `grace` seconds."""
    if process and process.poll() is None:
        process.send_signal(sig)
        try:
            process.wait(grace)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def wait_until(condition: Callable[[], bool], timeout: float = 10.0) -> bool:
    """Polls `condition` until it holds or `timeout` seconds passed; its last value."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if condition():
            return True
        time.sleep(0.02)
    return condition()


def mosquitto_binary() -> str:
    for path in ("/usr/sbin/mosquitto", "/usr/bin/mosquitto", "/usr/local/sbin/mosquitto"):
        if os.access(path, os.X_OK):
            return path
    found = shutil.which("mosquitto")
    if not found:
        pytest.fail("mosquitto not found (tools/install-deps.sh installs it)")
    return found


class Broker:
    """mosquitto on 127.0.0.1:port; stop() and start() again on the same port."""

    def __init__(self, directory: str, extra: str = "") -> None:
        self.port = free_port()
        self.url = f"tcp://127.0.0.1:{self.port}"
        self.config = os.path.join(directory, "mosquitto.conf")
        with open(self.config, "w") as f:
            f.write(f"listener {self.port} 127.0.0.1\n")
            f.write("allow_anonymous true\n" if "password_file" not in extra else "allow_anonymous false\n")
            f.write("persistence false\nmax_queued_messages 1000000\nlog_dest none\n")
            f.write(extra)
        self.process: Optional[subprocess.Popen[bytes]] = None
        self.start()

    def start(self) -> None:
        log = open(self.config + ".log", "ab")
        self.process = subprocess.Popen([mosquitto_binary(), "-c", self.config], stdout=log, stderr=log)
        log.close()
        try:
            wait_for_port(self.port)
        except RuntimeError:
            with open(self.config + ".log") as f:
                raise RuntimeError(f"mosquitto did not start: {f.read()}") from None

    def stop(self) -> None:
        stop_process(self.process, 5)
        self.process = None


def sim_binary() -> str:
    path = os.environ.get("NCLINK_SIM") or os.path.join(SOURCE_DIR, "build", "bin", "nclink-sim")
    if not os.access(path, os.X_OK):
        pytest.fail(f"nclink-sim not found at {path} (build the target nclink-sim)")
    return path


class Sim:
    """nclink-sim serving DEV on the broker; restart() is a new run of the adapter."""

    def __init__(self, broker: Broker, directory: str, config: Optional[Dict[str, Any]] = None,
                 args: Optional[List[str]] = None) -> None:
        self.broker = broker
        self.dev = DEV
        self.args = list(args or [])
        self.config_file: Optional[str] = None
        if config is not None:
            self.config_file = os.path.join(directory, "sim.json")
            with open(self.config_file, "w") as f:
                json.dump(config, f)
        self.process: Optional[subprocess.Popen[bytes]] = None
        self.log = os.path.join(directory, "sim.log")
        self.start()

    def start(self, wait: bool = True) -> None:
        command = [sim_binary(), "--broker", self.broker.url, "--log-level", "warn", *self.args]
        if self.config_file:
            command += ["--config", self.config_file]
        with open(self.log, "ab") as log:
            self.process = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT)
        if wait:
            self.wait_online()

    def wait_online(self, timeout: float = 15.0) -> None:
        """Until the adapter answers a Query (it subscribed and serves)."""
        end = time.monotonic() + timeout
        with nclink.Client(self.broker.url, timeout=0.5) as probe:
            probe.connect(timeout=5, register=False)
            while True:
                try:
                    probe.get(self.dev, "status")
                    return
                except nclink.Error:
                    if time.monotonic() > end:
                        raise
                    assert self.process is not None and self.process.poll() is None, open(self.log).read()

    def stop(self, sig: int = signal.SIGTERM) -> None:
        stop_process(self.process, 10, sig)
        self.process = None

    def restart(self) -> None:
        self.stop()
        self.start()


def agent_binary() -> str:
    path = os.environ.get("NCLINK_AGENT") or os.path.join(SOURCE_DIR, "build", "bin", "nclink-agent")
    if not os.access(path, os.X_OK):
        pytest.fail(f"nclink-agent not found at {path} (build the target nclink-agent)")
    return path


class Agent:
    """nclink-agent on the broker (registration, discovery, DEV_UNREACHABLE), its state in `directory`."""

    def __init__(self, broker: Broker, directory: str) -> None:
        self.log = os.path.join(directory, "agent.log")
        command = [agent_binary(), "--broker", broker.url, "--state-dir", os.path.join(directory, "agent-state")]
        with open(self.log, "ab") as log:
            self.process: Optional[subprocess.Popen[bytes]] = subprocess.Popen(
                command, stdout=log, stderr=subprocess.STDOUT)

    def stop(self) -> None:
        stop_process(self.process, 10)
        self.process = None


class Pki:
    """The TLS tests' certificates, made by the C++ tests' own helper
    tests/support/make-test-pki.sh: ca.pem, other-ca.pem, server.pem/.key and,
    per client name, <name>.pem, <name>.key and <name>-expired.pem."""

    def __init__(self, directory: str, clients: List[str]) -> None:
        if not shutil.which("openssl"):
            pytest.skip("openssl not found: the TLS tests need it to make their certificates")
        self.dir = os.path.join(directory, "pki")
        os.makedirs(self.dir)
        made = subprocess.run(["bash", os.path.join(SOURCE_DIR, "tests", "support", "make-test-pki.sh"), self.dir,
                               *clients], capture_output=True, text=True)
        if made.returncode != 0:
            raise RuntimeError(f"make-test-pki.sh failed: {made.stdout}{made.stderr}")

    def file(self, name: str) -> str:
        return os.path.join(self.dir, name)

    def listener(self, port: int, require_certificate: bool) -> str:
        """mosquitto lines of a TLS listener on 127.0.0.1:port (mutual TLS: the certificate's CN is the user)."""
        lines = (f"listener {port} 127.0.0.1\ncafile {self.file('ca.pem')}\n"
                 f"certfile {self.file('server.pem')}\nkeyfile {self.file('server.key')}\n")
        if require_certificate:
            lines += "require_certificate true\nuse_identity_as_username true\n"
        return lines


@pytest.fixture
def workdir() -> Iterator[str]:
    with tempfile.TemporaryDirectory(prefix="nclink-py-") as d:
        # Started as root, mosquitto drops to its own user, which must read
        # its configuration, password file and certificates here.
        os.chmod(d, 0o755)
        yield d


@pytest.fixture
def broker(workdir: str) -> Iterator[Broker]:
    b = Broker(workdir)
    yield b
    b.stop()


@pytest.fixture
def sim(broker: Broker, workdir: str) -> Iterator[Sim]:
    s = Sim(broker, workdir)
    yield s
    s.stop()


@pytest.fixture
def client(broker: Broker) -> Iterator[nclink.Client]:
    c = nclink.Client(broker.url, timeout=2.0)
    c.connect(timeout=5, register=False)
    yield c
    c.close()
