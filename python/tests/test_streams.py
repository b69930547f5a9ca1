"""Sample channels, dynamic sampling, events, methods; threads and Ctrl-C."""

from __future__ import annotations

import os
import queue
import signal
import sys
import threading
import time
from typing import Any, List

import pytest

import nclink
from conftest import DEV, Broker, Sim, wait_until



def test_sample_callback_rows_with_times_none_lost(sim: Sim, client: nclink.Client) -> None:
    batches: "queue.SimpleQueue[nclink.SampleBatch]" = queue.SimpleQueue()
    threads: List[int] = []

    def on_batch(batch: nclink.SampleBatch) -> None:
        threads.append(threading.get_ident())
        batches.put(batch)

    with client.on_samples(DEV, on_batch, "ch_fast"):
        got = [batches.get(timeout=15) for _ in range(4)]
    assert all(b.channel == "ch_fast" and b.dev == DEV and b.interval_ms == 1.0 for b in got)
    assert got[0].ids[:3] == ["x_position", "y_position", "z_position"]
    rows = [row for b in got for row in b.rows]
    assert len(rows) == sum(len(b) for b in got) >= 4
    assert all(len(row) == 1 + len(got[0].ids) for row in rows)
    # consecutive rows 1 ms apart across batches: no row lost or repeated
    times = [round(row[0] * 1000) for row in rows]
    assert times == list(range(times[0], times[0] + len(times)))
    assert abs(rows[0][0] - time.time()) < 60
    assert got[0].columns["x_position"] == [row[1] for row in got[0].rows]
    assert got[0].raw()["id"] == "ch_fast"
    # callbacks run on the client's dispatch thread, not on this one
    assert threading.get_ident() not in threads and len(set(threads)) == 1


def test_sample_iterator_and_rows(sim: Sim, client: nclink.Client) -> None:
    with client.samples(DEV, "ch_slow", timeout=5) as stream:
        batch = next(iter(stream))
        assert batch.channel == "ch_slow" and batch.interval_ms == 100.0
        row = next(stream.rows())
        assert row.channel == "ch_slow" and "status" in row.values and row.time > 0
        assert row.values["status"] in ("running", "free", "holding")
    # closed: iteration ends
    assert list(stream) == [] or all(isinstance(b, nclink.SampleBatch) for b in stream)


def test_sample_iterator_timeout_is_an_exception(sim: Sim, client: nclink.Client) -> None:
    with client.samples(DEV, "no_such_channel", timeout=0.3) as stream:
        with pytest.raises(nclink.Timeout):
            next(stream)


def test_dataframe(sim: Sim, client: nclink.Client) -> None:
    pd = pytest.importorskip("pandas", reason="pandas is not installed (Debian: apt-get install python3-pandas); "
                                              "nclink.dataframe is left untested")
    with client.samples(DEV, "ch_fast", timeout=5) as stream:
        batches = stream.collect(rows=250)
    frame = nclink.dataframe(batches)
    assert isinstance(frame, pd.DataFrame)
    assert len(frame) == sum(len(b) for b in batches) >= 250
    assert list(frame.columns[:2]) == ["channel", "x_position"]
    assert str(frame.index.tz) == "UTC" and frame.index.is_monotonic_increasing
    assert (frame.index[1] - frame.index[0]) == pd.Timedelta(milliseconds=1)


def test_dataframe_without_pandas_says_what_to_install(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "pandas", None)  # type: ignore[misc]
    with pytest.raises(ImportError, match="python3-pandas"):
        nclink.dataframe([])


def lease_sim(broker: Broker, workdir: str) -> Sim:
    return Sim(broker, workdir, config={"application_lease_ms": 1500})


def test_dynamic_sampling_lease_kept_alive(broker: Broker, workdir: str) -> None:
    sim = lease_sim(broker, workdir)
    try:
        rows: List[Any] = []
        kept = nclink.Client(broker.url, keepalive=0.3)
        kept.connect(register=False)
        lapsed = nclink.Client(broker.url, keepalive=0)  # no keep-alive: the adapter lets it go
        lapsed.connect(register=False)
        lapsed_rows: List[Any] = []
        with kept, lapsed:
            channel = kept.sample(DEV, ["x_position", "spindle_speed"], 10, 100, lambda b: rows.extend(b.rows))
            other = lapsed.sample(DEV, ["x_position"], 10, 100, lambda b: lapsed_rows.extend(b.rows))
            assert channel.id.startswith("dyn") and other.id != channel.id
            # The adapter releases the lapsed channel a lease (1.5 s) after
            # its last sign of life; a loaded machine may take longer, so
            # wait for its rows to stop (a second without one) rather than a
            # fixed time. Without the lease they never stop.
            def lapsed_stopped() -> bool:
                before = len(lapsed_rows)
                time.sleep(1.0)
                return len(lapsed_rows) == before

            time.sleep(1.5)
            assert wait_until(lapsed_stopped, timeout=30), "the channel without keep-alive was not released"
            count = len(rows)
            assert wait_until(lambda: len(rows) > count), "the kept channel stopped: its lease ran out"
            assert all(len(r) == 3 for r in rows)
            steps = {round((b[0] - a[0]) * 1000) for a, b in zip(rows, rows[1:])}
            assert 10 in steps
            channel.close()
    finally:
        sim.stop()


def test_dynamic_sampling_iterator_and_refusal(sim: Sim, client: nclink.Client) -> None:
    with client.sample(DEV, ["x_position"], 10, 100, stream_timeout=5) as channel:
        batch = next(iter(channel))
        assert batch.channel == channel.id and batch.ids == ["x_position"]
    with pytest.raises(nclink.NodeNotExists):
        client.sample(DEV, ["nope"], 10, 100, lambda b: None)
    with pytest.raises(ValueError):
        client.sample(DEV, ["x_position"], 0, 100, lambda b: None)


def test_events_registered_and_watched(sim: Sim, client: nclink.Client) -> None:
    mine: "queue.SimpleQueue[nclink.Event]" = queue.SimpleQueue()
    watched: "queue.SimpleQueue[nclink.Event]" = queue.SimpleQueue()
    client.put(DEV, "feed_override", 100)
    client.on_events(DEV, watched.put)
    with client.register_event(DEV, "feed_override", mine.put, filters=[{"type": "range", "from": 40, "to": 60}]) as reg:
        assert reg.id
        client.put(DEV, "feed_override", 50)
        event = mine.get(timeout=15)
        assert event.item == "feed_override" and event.value == 50 and event.event_id == reg.id
        assert abs(event.time - time.time()) < 60
        seen = watched.get(timeout=15)
        assert seen.app == client.client_id and seen.value == 50
    with pytest.raises(nclink.Error) as raised:
        client.register_event(DEV, "feed_override", mine.put, trigger="sometimes")
    assert raised.value.code == 420
    with pytest.raises(nclink.NodeNotExists):
        client.register_event(DEV, "nope", mine.put)


def method_sim(broker: Broker, workdir: str) -> Sim:
    programs = os.path.join(workdir, "programs")
    os.makedirs(programs)
    return Sim(broker, workdir, config={"driver": {"config": {"program_dir": programs, "transfer_rate": 8192}},
                                        "methods": {"status_period_ms": 100}})


def g_code(workdir: str, size: int = 24 * 1024) -> str:
    path = os.path.join(workdir, "O1234.nc")
    with open(path, "w") as f:
        line = "G01 X10 Y10 F100\n"
        f.write(line * (size // len(line)))
    return path


def test_method_call_with_progress_and_control(broker: Broker, workdir: str) -> None:
    sim = method_sim(broker, workdir)
    try:
        with nclink.Client(broker.url, timeout=3) as c:
            c.connect(register=False)
            statuses: List[nclink.MethodStatus] = []
            runs: List[nclink.MethodRun] = []
            c.on_method_runs(DEV, runs.append)
            done = c.call(DEV, "program_transfer", {"source": g_code(workdir, 24 * 1024)}, on_status=statuses.append,
                          timeout=30)  # a 3 s transfer: the result comes at its end
            assert done.result == "finished" and done.method == "program_transfer"
            progress = [s.progress for s in statuses if s.progress is not None]
            assert progress == sorted(progress) and progress[-1] > progress[0]
            assert all(s.call_id == done.call_id for s in statuses)
            assert wait_until(lambda: any(r.kind == "result" and r.app == c.client_id for r in runs))
            # stop (pause) a running call, then cancel it
            statuses.clear()
            result: List[Any] = []

            def call() -> None:
                try:
                    result.append(c.call(DEV, "program_transfer", {"source": g_code(workdir)},
                                         on_status=statuses.append))
                except Exception as e:
                    result.append(e)
            caller = threading.Thread(target=call)
            caller.start()
            assert wait_until(lambda: any(s.status == "executing" for s in statuses))
            c.control(DEV, "program_transfer", "stop")
            assert wait_until(lambda: any(s.status == "stopped" for s in statuses))
            c.control(DEV, "program_transfer", "cancel")
            caller.join(30)
            assert not caller.is_alive()
            assert isinstance(result[0], nclink.MethodResult), result[0]
            assert result[0].result == "canceled"
            # cancel, through asyncio this time
            import asyncio

            async def cancel() -> nclink.MethodResult:
                task = asyncio.ensure_future(c.acall(DEV, "program_transfer", {"source": g_code(workdir)}))
                await asyncio.sleep(0.5)
                await c.acontrol(DEV, "program_transfer", "cancel")
                return await task
            assert asyncio.run(cancel()).result == "canceled"
            with pytest.raises(nclink.NodeNotExists):
                c.call(DEV, "no_such_method")
            with pytest.raises(nclink.MethodActionType):
                c.control(DEV, "program_transfer", "jump")
    finally:
        sim.stop()


def test_ctrl_c_interrupts_a_blocking_call(sim: Sim, client: nclink.Client) -> None:
    threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
    started = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        client.get("no-such-device", "status", timeout=30)
    # Interrupted, not timed out: well before the call's own 30 s.
    assert time.monotonic() - started < 20
    assert client.get(DEV, "status")  # the client goes on


def test_blocking_call_from_a_callback_raises_instead_of_hanging(sim: Sim, client: nclink.Client) -> None:
    errors: "queue.SimpleQueue[BaseException]" = queue.SimpleQueue()

    def on_batch(batch: nclink.SampleBatch) -> None:
        try:
            client.get(DEV, "status")
        except nclink.Error as e:
            errors.put(e)

    with client.on_samples(DEV, on_batch, "ch_fast"):
        err = errors.get(timeout=15)
    assert isinstance(err, nclink.Unavailable) and "callback" in err.message


def test_callback_exception_is_reported_and_delivery_goes_on(sim: Sim, client: nclink.Client,
                                                             monkeypatch: pytest.MonkeyPatch) -> None:
    reported: List[Any] = []
    monkeypatch.setattr(sys, "unraisablehook", reported.append)
    calls: List[int] = []

    def on_batch(batch: nclink.SampleBatch) -> None:
        calls.append(len(batch))
        raise RuntimeError("a bug in the application")

    with client.on_samples(DEV, on_batch, "ch_fast"):
        assert wait_until(lambda: len(calls) >= 3)
    assert reported and isinstance(reported[0].exc_value, RuntimeError)


def test_adapter_restart_mid_subscription(sim: Sim, client: nclink.Client) -> None:
    batches: List[nclink.SampleBatch] = []
    dynamic: List[nclink.SampleBatch] = []
    states: List[str] = []
    client.on_state(DEV, lambda s: states.append(s.state))
    client.on_samples(DEV, batches.append, "ch_slow")
    channel = client.sample(DEV, ["x_position"], 10, 100, dynamic.append)
    assert wait_until(lambda: len(batches) >= 1 and len(dynamic) >= 1)
    sim.restart()
    restarted_at = time.time() * 1000
    assert wait_until(lambda: any(b.begin_time_ms > restarted_at for b in batches), 15)
    # the dynamic channel is registered again by the client, under the same id for close()
    assert wait_until(lambda: any(b.begin_time_ms > restarted_at for b in dynamic), 15)
    assert "offline" in states and states[-1] == "online"
    channel.close()


def test_broker_restart_mid_subscription(sim: Sim, broker: Broker) -> None:
    links: List[str] = []
    batches: List[nclink.SampleBatch] = []
    with nclink.Client(broker.url, on_link_state=links.append, reconnect_max=0.5) as c:
        c.connect(register=False)
        c.on_samples(DEV, batches.append, "ch_slow")
        assert wait_until(lambda: len(batches) >= 1)
        broker.stop()
        assert wait_until(lambda: c.link_state != "connected")
        with pytest.raises(nclink.Timeout):
            c.get(DEV, "status", timeout=0.3)  # queued while down, times out, never sent
        broker.start()
        assert wait_until(lambda: c.link_state == "connected", 15)
        back = time.time() * 1000
        assert wait_until(lambda: any(b.begin_time_ms > back for b in batches), 20)
        assert "disconnected" in links and links[-1] == "connected"


def test_asyncio(sim: Sim, client: nclink.Client) -> None:
    import asyncio

    async def main() -> None:
        results = await asyncio.gather(client.aget(DEV, "x_position"), client.aquery(DEV, ["status", "nope"]),
                                       client.aprobe(DEV))
        assert len(results[0]) == 1 and results[1][1].code == 401 and results[2]["type"] == "NC_LINK_ROOT"
        await client.aset(DEV, {"feed_override": 60})
        assert await client.aget(DEV, "feed_override") == [60]
        with pytest.raises(nclink.NotSetable):
            await client.aset(DEV, {"spindle_speed": 1})
        with pytest.raises(nclink.Timeout):
            await client.aget("no-such-device", "status", timeout=0.2)
        stream = await client.asamples(DEV, "ch_fast", timeout=5)
        n = 0
        async for batch in stream:
            n += len(batch)
            if n >= 200:
                stream.close()
        assert n >= 200
        channel = await client.asample(DEV, ["x_position"], 10, 100, stream_timeout=5)
        assert channel.stream is not None
        async for batch in channel.stream:
            assert batch.ids == ["x_position"]
            break
        channel.close()
        model = await client.amodel(DEV)
        assert model.find("x_position").path == "mill/axis_x/x_position"

    asyncio.run(main())
