"""Discovery and registration with an agent (nclink-agent) and without one;
TLS to the broker: the broker's CA, mutual TLS with a client certificate, and
the certificates a broker or the client refuses, each a clear exception."""

from __future__ import annotations

import asyncio
import time
from typing import Iterator

import pytest

import nclink
from conftest import DEV, Agent, Broker, Pki, Sim, free_port, wait_until



@pytest.fixture
def agent(broker: Broker, workdir: str) -> Iterator[Agent]:
    a = Agent(broker, workdir)
    # The agent answers Discovery once it is subscribed.
    with nclink.Client(broker.url, timeout=0.5) as probe:
        probe.connect(timeout=5, register=False)

        def answers() -> bool:
            assert a.process is not None and a.process.poll() is None, open(a.log).read()
            try:
                probe.discover()
                return True
            except nclink.Timeout:
                return False

        assert wait_until(answers, 20), open(a.log).read()
    yield a
    a.stop()


def test_discovery_and_registration_with_an_agent(agent: Agent, broker: Broker, workdir: str) -> None:
    sim = Sim(broker, workdir)  # registers with the agent (Register/Request, 8.2.1)
    try:
        with nclink.Client(broker.url, "py-mes", timeout=2.0) as c:
            assert c.connect(timeout=5) == "accepted"
            assert c.register() == "accepted"

            def listed_online() -> bool:
                return any(d.guid == DEV and d.status == "online" for d in c.discover())

            assert wait_until(listed_online, 20)
            device = next(d for d in c.discover() if d.guid == DEV)
            assert isinstance(device, nclink.Device) and device.last_alive
            assert c.get(DEV, "status")

            async def asynchronous() -> None:
                assert await c.aregister() == "accepted"
                assert any(d.guid == DEV for d in await c.adiscover())

            asyncio.run(asynchronous())

            # With an agent, a request to an adapter that is gone is answered
            # DEV_UNREACHABLE (202) instead of timing out.
            sim.stop()
            assert wait_until(lambda: any(d.guid == DEV and d.status == "offline" for d in c.discover()), 20)
            with pytest.raises(nclink.Unavailable):
                c.get(DEV, "status", timeout=5)
    finally:
        sim.stop()


def test_discovery_without_an_agent(sim: Sim, broker: Broker) -> None:
    # Nobody answers Register/Request or Discovery: the outcome no_answer, and a Timeout.
    with nclink.Client(broker.url, "py-mes-alone") as c:
        assert c.connect(timeout=5, register_timeout=0.3) == "no_answer"
        with pytest.raises(nclink.Timeout):
            c.discover(timeout=0.3)
        assert c.register(timeout=0.3) == "no_answer"
        assert c.get(DEV, "status")  # the adapter serves without an agent


@pytest.fixture
def pki(workdir: str) -> Pki:
    return Pki(workdir, ["mes"])


def tls_broker(workdir: str, pki: Pki, require_certificate: bool) -> "tuple[Broker, str]":
    port = free_port()
    return Broker(workdir, extra=pki.listener(port, require_certificate)), f"ssl://127.0.0.1:{port}"


def test_tls_with_a_client_certificate(workdir: str, pki: Pki) -> None:
    broker, url = tls_broker(workdir, pki, require_certificate=True)
    sim = Sim(broker, workdir)  # on the broker's plain listener
    try:
        tls = nclink.Tls(ca_file=pki.file("ca.pem"), cert_file=pki.file("mes.pem"), key_file=pki.file("mes.key"))
        with nclink.Client(url, "mes", tls=tls) as c:
            assert c.connect(timeout=5, register=False) == "not_sent"
            assert c.link_state == "connected"
            assert c.get(DEV, "status")
            assert c.stats()["transport"]["refused"] is False
    finally:
        sim.stop()
        broker.stop()


def test_refused_client_certificates_are_clear_exceptions(workdir: str, pki: Pki) -> None:
    broker, url = tls_broker(workdir, pki, require_certificate=True)
    try:
        ca = pki.file("ca.pem")
        cases = {
            # the client library refuses to present an expired certificate
            "expired": (nclink.Tls(ca_file=ca, cert_file=pki.file("mes-expired.pem"), key_file=pki.file("mes.key")),
                        "expired"),
            # the broker requires one and gets none: it ends the handshake
            "none": (nclink.Tls(ca_file=ca), "the broker refused our certificate"),
            # a client key that is not the certificate's
            "wrong key": (nclink.Tls(ca_file=ca, cert_file=pki.file("mes.pem"), key_file=pki.file("server.key")),
                          "cannot load the client key"),
        }
        for what, (tls, expect) in cases.items():
            started = time.monotonic()
            with nclink.Client(url, "mes", tls=tls, reconnect_max=0.5) as c:
                with pytest.raises(nclink.Error) as raised:
                    c.connect(timeout=5, register=False)
            took = time.monotonic() - started
            message = raised.value.message
            assert url in message, what
            assert expect in message, (what, message)
            # Refused: the broker or the client said no, nothing to wait for.
            assert isinstance(raised.value, nclink.PermissionDenied), (what, raised.value)
            assert took < 3, (what, took)
            print(f"{what}: {type(raised.value).__name__} after {took:.2f} s: {message}")
        # The broker's certificate from a CA the client does not trust.
        with nclink.Client(url, "mes", tls=nclink.Tls(ca_file=pki.file("other-ca.pem"), cert_file=pki.file("mes.pem"),
                                                      key_file=pki.file("mes.key"))) as c:
            with pytest.raises(nclink.PermissionDenied) as refused:
                c.connect(timeout=5, register=False)
        assert "the broker's certificate did not verify" in refused.value.message
    finally:
        broker.stop()
