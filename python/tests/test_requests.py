"""Connect, discovery and state, probe, query and set, errors, statistics."""

from __future__ import annotations

import copy
import os
import subprocess
import time

import pytest

import nclink
from conftest import DEV, SOURCE_DIR, Broker, Sim, free_port


def test_connect_without_agent_is_no_answer(broker: Broker) -> None:
    with nclink.Client(broker.url, "py-connect") as c:
        assert c.connect(timeout=5, register=True, register_timeout=0.3) == "no_answer"
        assert c.link_state == "connected"
        assert c.client_state == "normal"
        assert c.client_id == "py-connect"


def test_broker_down_is_a_timeout_that_names_the_broker() -> None:
    url = f"tcp://127.0.0.1:{free_port()}"
    started = time.monotonic()
    with nclink.Client(url) as c:
        with pytest.raises(nclink.Timeout) as raised:
            c.connect(timeout=0.5)
    assert time.monotonic() - started < 20  # the 0.5 s connect timeout, not a hang
    assert raised.value.code == 203
    assert url in raised.value.message
    assert isinstance(raised.value, TimeoutError)


def test_failover_list_reaches_the_second_broker(sim: Sim, broker: Broker) -> None:
    down = f"tcp://127.0.0.1:{free_port()}"  # nothing listens: the connect attempt is refused
    with nclink.Client(down, "py-failover", failover=[broker.url], reconnect_min=0.05) as c:
        assert c.connect(timeout=10, register=False) == "not_sent"
        assert c.get(DEV, "status")  # the adapter answers through the second broker
        transport = c.stats()["transport"]
        assert transport["broker"] == broker.url
        assert transport["failovers"] == 1
        assert transport["connect_failures"] >= 1
    with pytest.raises(ValueError):
        nclink.Client(down, failover=broker.url)  # one URL, not a list of them
    with pytest.raises(nclink.ValueTypeError):
        nclink.Client(down, failover=["ssl://127.0.0.1:8883"])  # TLS only where the broker has it


def test_user_and_password(workdir: str) -> None:
    passwords = os.path.join(workdir, "passwords")
    subprocess.run(["mosquitto_passwd", "-b", "-c", passwords, "mes", "secret"], check=True)
    os.chmod(passwords, 0o644)
    b = Broker(workdir, extra=f"password_file {passwords}\n")
    try:
        with nclink.Client(b.url, username="mes", password="wrong") as c:
            with pytest.raises(nclink.PermissionDenied) as raised:
                c.connect(timeout=3, register=False)
            assert "refused" in raised.value.message
        with nclink.Client(b.url, username="mes", password="secret") as c:
            assert c.connect(timeout=3, register=False) == "not_sent"
    finally:
        b.stop()


def test_requests_before_connect_fail_at_once() -> None:
    c = nclink.Client("tcp://127.0.0.1:1")
    with pytest.raises(nclink.Unavailable):
        c.get(DEV, "status")
    c.close()


def test_device_state_and_discovery_without_agent(sim: Sim, client: nclink.Client) -> None:
    assert client.device_state(DEV) == "online"
    with pytest.raises(nclink.Timeout):
        client.device_state("no-such-device", timeout=0.3)
    # Discovery is the agent's: without one nobody answers.
    with pytest.raises(nclink.Timeout):
        client.discover(timeout=0.3)


def test_probe_as_dicts_and_as_model(sim: Sim, client: nclink.Client) -> None:
    raw = client.probe(DEV)
    assert raw["type"] == "NC_LINK_ROOT"
    assert raw["devices"][0]["guid"] == DEV
    model = client.model(DEV)
    node = model.find("x_position")
    assert node.kind == "item" and node.type == "POSITION"
    assert node.path == "mill/axis_x/x_position"
    assert model.at("mill/axis_x/x_position") is node
    assert node.parent is not None and node.parent.id == "axis_x"
    assert {c.id for c in model.channels} == {"ch_fast", "ch_slow"}
    assert model.channel_layouts()["ch_fast"][0] == 1.0
    assert "x_position" in model.channel_layouts()["ch_fast"][1]
    assert {m.id for m in model.methods} >= {"cycle_start", "program_transfer"}
    assert model.find("tools").get("datatype") == "list"
    with pytest.raises(KeyError):
        model.find("nope")


def test_query_with_list_and_dict_operations(sim: Sim, client: nclink.Client) -> None:
    results = client.query(DEV, ["x_position", ("tools", {"operation": "get_length"}), "nope"])
    assert [r.id for r in results] == ["x_position", "tools", "nope"]
    assert results[0].ok and isinstance(results[0].values, list) and len(results[0].values) == 1
    assert results[1].ok and isinstance(results[1].values[0], int)  # type: ignore[index]
    length = results[1].values[0]  # type: ignore[index]
    assert not results[2].ok and results[2].code == 401 and results[2].reason == "Node not exists"
    assert isinstance(results[2].error(), nclink.NodeNotExists)
    with pytest.raises(nclink.NodeNotExists):
        client.query(DEV, ["x_position", "nope"], check=True)
    # list elements by index, dict elements by key
    tools = client.get(DEV, "tools", indexes=[0])
    assert len(tools) == 1
    assert client.get(DEV, "tools", operation="get_length") == [length]
    keys = client.get(DEV, "parameters", operation="get_keys")
    assert "P0001" in keys
    client.put(DEV, "parameters", key="P0001", value=3.5)
    assert client.get(DEV, "parameters", keys=["P0001"]) == [3.5]
    with pytest.raises(nclink.BadKey):
        client.put(DEV, "parameters", key="no-such-key", value=1)
    # dict form of query items
    as_dict = client.query(DEV, {"feed_override": None, "tools": {"operation": "get_length"}})
    assert [r.id for r in as_dict] == ["feed_override", "tools"]


def test_set_values_and_refusals(sim: Sim, client: nclink.Client) -> None:
    client.set(DEV, {"feed_override": 80})
    assert client.value(DEV, "feed_override") == 80
    client.put(DEV, "feed_override", 90)
    assert client.value(DEV, "feed_override") == 90
    # not setable: 301, raised as NotSetable (a PermissionDenied) with every item's result
    with pytest.raises(nclink.NotSetable) as raised:
        client.set(DEV, {"feed_override": 70, "spindle_speed": 100})
    assert raised.value.code == 301
    assert isinstance(raised.value, nclink.PermissionDenied)
    results = raised.value.results  # type: ignore[attr-defined]
    assert [r.ok for r in results] == [True, False]
    # a wrong value type: 405; unchecked, the results come back
    results = client.set(DEV, {"feed_override": "fast"}, check=False)
    assert results[0].code == 405
    with pytest.raises(nclink.ValueTypeError):
        client.put(DEV, "feed_override", "fast")


def test_unknown_device_times_out(sim: Sim, client: nclink.Client) -> None:
    started = time.monotonic()
    with pytest.raises(nclink.Timeout) as raised:
        client.get("no-such-device", "status", timeout=0.3)
    assert time.monotonic() - started < 3
    assert raised.value.code == 203


def test_adapter_gone_times_out_and_comes_back(sim: Sim, client: nclink.Client) -> None:
    sim.stop()
    with pytest.raises(nclink.Timeout):
        client.get(DEV, "status", timeout=0.3)
    sim.start()
    assert client.get(DEV, "status")


def test_malformed_model_is_refused_and_the_adapter_keeps_serving(sim: Sim, client: nclink.Client) -> None:
    with pytest.raises(nclink.Error) as raised:
        client.probe_set(DEV, {"id": "broken", "devices": "not a list"})
    assert raised.value.code != 0
    with pytest.raises(TypeError):
        client.probe_set(DEV, {"id": object()})  # type: ignore[dict-item]
    assert client.get(DEV, "status")


def test_probe_set_and_version_notification(sim: Sim, client: nclink.Client) -> None:
    versions: list[nclink.VersionChange] = []
    client.on_version(DEV, versions.append)
    model = copy.deepcopy(client.probe(DEV))
    model["version"] = "2.0.0"
    model["devices"][0]["version"] = "2.0.0"
    client.probe_set(DEV, model)
    end = time.monotonic() + 5
    while not any(v.version == "2.0.0" for v in versions) and time.monotonic() < end:
        time.sleep(0.05)
    assert client.probe(DEV)["version"] == "2.0.0"
    assert any(v.version == "2.0.0" and v.dev == DEV for v in versions)


def test_statistics(sim: Sim, client: nclink.Client) -> None:
    before = client.stats()
    client.get(DEV, "status")
    with pytest.raises(nclink.Timeout):
        client.get("no-such-device", "status", timeout=0.2)
    after = client.stats()
    assert after["requests"] >= before["requests"] + 2
    assert after["responses"] >= before["responses"] + 1
    assert after["timeouts"] == before["timeouts"] + 1
    assert after["transport"]["connects"] >= 1
    assert client.pending_requests == 0


def test_closed_client_fails_pending_and_new_requests(sim: Sim, broker: Broker) -> None:
    c = nclink.Client(broker.url)
    c.connect(timeout=5, register=False)
    c.close()
    c.close()  # idempotent
    with pytest.raises(nclink.Unavailable):
        c.get(DEV, "status")


def test_tls_with_the_brokers_ca(workdir: str) -> None:
    pki = os.path.join(workdir, "pki")
    os.makedirs(pki)
    subprocess.run(["bash", os.path.join(SOURCE_DIR, "tests", "support",
                                         "make-test-pki.sh"), pki, "mes"],
                   check=True, capture_output=True)
    tls_port = free_port()
    extra = (f"listener {tls_port} 127.0.0.1\ncafile {pki}/ca.pem\ncertfile {pki}/server.pem\n"
             f"keyfile {pki}/server.key\n")
    b = Broker(workdir, extra=extra)
    try:
        url = f"ssl://127.0.0.1:{tls_port}"
        with nclink.Client(url, tls=nclink.Tls(ca_file=f"{pki}/ca.pem")) as c:
            assert c.connect(timeout=5, register=False) == "not_sent"
            assert c.link_state == "connected"
        with nclink.Client(url, tls=nclink.Tls(ca_file=f"{pki}/other-ca.pem")) as c:
            with pytest.raises(nclink.Error) as raised:
                # A refused handshake ends the wait at once; the timeout only
                # bounds a loaded machine's first attempt.
                c.connect(timeout=30, register=False)
            assert "certificate" in raised.value.message
    finally:
        b.stop()
