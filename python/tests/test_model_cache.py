"""The model cache (follow_model, cached_model, wait_model, afollow_model), the
event registration count, re-registration after an adapter restart, and the
less used client options: what nclink::Client offers beyond requests."""

from __future__ import annotations

import asyncio
import copy
import queue
import time
from typing import Any, Dict, List, Tuple

import pytest

import nclink
from conftest import DEV, Broker, Sim, wait_until



def version_of(model: Dict[str, Any]) -> str:
    return str(model["devices"][0]["version"])


def with_version(model: Dict[str, Any], version: str) -> Dict[str, Any]:
    changed = copy.deepcopy(model)
    changed["version"] = version
    changed["devices"][0]["version"] = version
    return changed


def test_follow_model_fetches_the_model_and_each_new_version(sim: Sim, client: nclink.Client) -> None:
    fetched: List[Tuple[str, Dict[str, Any]]] = []
    assert client.cached_model(DEV) is None and client.cached_model_version(DEV) == ""
    client.follow_model(DEV, lambda dev, model: fetched.append((dev, model)))
    model = client.wait_model(DEV)
    assert model["type"] == "NC_LINK_ROOT"
    assert model == client.probe(DEV)
    assert client.cached_model_version(DEV) == version_of(model) != ""
    assert wait_until(lambda: len(fetched) == 1)
    assert fetched[0] == (DEV, model)
    fetches = client.model_reprobes
    assert fetches >= 1

    # Another application changes the model (Probe/Set, 8.2.9); the adapter
    # announces the new version (Probe/Version, 8.2.5) and the cache fetches it.
    with nclink.Client(client.broker) as other:
        other.connect(register=False)
        other.probe_set(DEV, with_version(model, "7.1.0"))
    assert wait_until(lambda: client.cached_model_version(DEV) == "7.1.0")
    cached = client.cached_model(DEV)
    assert cached is not None and version_of(cached) == "7.1.0" and cached["version"] == "7.1.0"
    assert wait_until(lambda: len(fetched) == 2)
    assert fetched[1][0] == DEV and version_of(fetched[1][1]) == "7.1.0"
    assert client.model_reprobes == fetches + 1
    # After an adapter restart the cache holds the model the adapter serves
    # (the same one, or its configured model again if it kept no Probe/Set).
    sim.restart()
    served = client.probe(DEV)
    assert wait_until(lambda: client.cached_model(DEV) == served)
    assert client.cached_model_version(DEV) == version_of(served)


def test_follow_model_misuse_is_an_exception(sim: Sim, broker: Broker, client: nclink.Client) -> None:
    with nclink.Client(broker.url) as idle:
        with pytest.raises(nclink.Unavailable):
            idle.follow_model(DEV)  # before connect()
    with pytest.raises(nclink.ValueTypeError):
        client.follow_model("bad/device")
    # Following a device that does not answer: no model, a Timeout, no hang.
    client.follow_model("no-such-device")
    started = time.monotonic()
    with pytest.raises(nclink.Timeout):
        client.wait_model("no-such-device", timeout=0.5)
    assert time.monotonic() - started < 3
    assert client.cached_model("no-such-device") is None

    # wait_model() in a callback would wait for its own thread: it raises.
    raised: "queue.SimpleQueue[BaseException]" = queue.SimpleQueue()

    def on_model(dev: str, model: Dict[str, Any]) -> None:
        try:
            client.wait_model(dev)
        except nclink.Error as error:
            raised.put(error)

    client.follow_model(DEV, on_model)
    assert isinstance(raised.get(timeout=5), nclink.Unavailable)


def test_afollow_model(sim: Sim, client: nclink.Client) -> None:
    fetched: List[str] = []

    async def main() -> None:
        model = await client.afollow_model(DEV, lambda dev, m: fetched.append(version_of(m)))
        assert model["type"] == "NC_LINK_ROOT" and client.cached_model(DEV) == model
        with pytest.raises(nclink.Timeout):
            await client.afollow_model("no-such-device", timeout=0.3)

    asyncio.run(main())
    assert fetched and fetched[0] == client.cached_model_version(DEV)


def test_event_registrations_are_counted(sim: Sim, client: nclink.Client) -> None:
    client.put(DEV, "feed_override", 100)
    assert client.event_registrations == 0
    first = client.register_event(DEV, "feed_override", lambda e: None)
    assert client.event_registrations == 1
    second = client.register_event(DEV, "feed_override", lambda e: None,
                                   filters=[{"type": "range", "from": 40, "to": 60}])
    assert client.event_registrations == 2
    # A once registration leaves after its first event.
    fired: "queue.SimpleQueue[nclink.Event]" = queue.SimpleQueue()
    client.register_event(DEV, "feed_override", fired.put, trigger="once",
                          filters=[{"type": "range", "from": 10, "to": 20}])
    assert client.event_registrations == 3
    client.put(DEV, "feed_override", 15)
    assert fired.get(timeout=5).value == 15
    assert wait_until(lambda: client.event_registrations == 2)
    # A refused registration is not counted.
    with pytest.raises(nclink.NodeNotExists):
        client.register_event(DEV, "nope", lambda e: None)
    assert client.event_registrations == 2
    first.close()
    assert client.event_registrations == 1
    second.close()
    assert client.event_registrations == 0


def test_registrations_made_again_after_an_adapter_restart(sim: Sim, client: nclink.Client) -> None:
    events: "queue.SimpleQueue[nclink.Event]" = queue.SimpleQueue()
    client.put(DEV, "feed_override", 100)
    registration = client.register_event(DEV, "feed_override", events.put,
                                         filters=[{"type": "range", "from": 40, "to": 60}])
    assert client.reregistrations == 0
    sim.restart()
    assert wait_until(lambda: client.reregistrations >= 1, 15)
    assert client.event_registrations == 1
    client.put(DEV, "feed_override", 55)
    assert events.get(timeout=5).value == 55
    registration.close()  # the id given at first still unregisters
    assert client.event_registrations == 0


def test_less_used_client_options(sim: Sim, broker: Broker) -> None:
    # Each option reaches the C++ client (an unknown value would raise);
    # max_queued_requests is the one a test can see.
    with nclink.Client(broker.url, max_queued_requests=1, duplicate_memory=0, stop_flush_timeout=0.1,
                       mqtt_version=5, mqtt_keepalive=5, reconnect_min=0.1, outbox_max_bytes=1 << 20,
                       outbox_max_in_flight=8, tcp_nodelay=True,
                       last_will=("py-test/will", "gone", 1, False)) as c:
        c.connect(register=False)
        assert c.get(DEV, "status")
        broker.stop()
        assert wait_until(lambda: c.link_state != "connected")
        # max_queued_requests=1: the first request is held, the second refused at once (404).
        results: List[Any] = []

        async def two() -> None:
            results.extend(await asyncio.gather(c.aget(DEV, "status", timeout=0.5),
                                                c.aget(DEV, "status", timeout=0.5), return_exceptions=True))

        asyncio.run(two())
        assert isinstance(results[0], nclink.Timeout)
        assert isinstance(results[1], nclink.MemoryConfigured)
        broker.start()
    with pytest.raises(ValueError):
        nclink.Client(broker.url, mqtt_version=3)
    with pytest.raises(ValueError):
        nclink.Client(broker.url, stop_flush_timeout=-1.0)


def test_mqtt_version_auto(sim: Sim, broker: Broker, capfd: pytest.CaptureFixture[str]) -> None:
    # "auto", as the programs' "mqtt_version": MQTT 5 first, 3.1.1 after a
    # broker refused 5 (docs/configuration.md). mosquitto speaks 5: the C++
    # client says which level it settled on, and requests work over it.
    with nclink.Client(broker.url, mqtt_version="auto", log_level="info") as c:
        c.connect(register=False)
        assert c.get(DEV, "status")
    assert "speaks MQTT 5 (mqtt_version auto)" in capfd.readouterr().err
    with pytest.raises(ValueError, match="auto"):
        nclink.Client(broker.url, mqtt_version="sometimes")
