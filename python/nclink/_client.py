"""nclink.Client: an NC-Link application (GB/T 41970-2022) in Python.

A thin layer over the C++ client (nclink::Client, through the extension
module nclink._nclink): it shapes arguments, turns answers into dataclasses
and errors into exceptions, and adds iterators, asyncio and pandas helpers.

Threads (docs/python.md, "Threads"): blocking calls wait with the GIL
released and end with KeyboardInterrupt on Ctrl-C. Every callback (samples,
state, events, method status, link state, and the completions behind the
``a...`` coroutines) runs on the client's own dispatch thread, one at a time,
holding the GIL while it runs. A callback must not make a blocking call of
the same client (it raises nclink.Unavailable; use the ``a...`` form or a
queue); keep callbacks short, they delay every other one.
"""

from __future__ import annotations

import asyncio
import atexit
import os
import queue
import threading
import time
import uuid
import weakref
from dataclasses import dataclass
from typing import (Any, AsyncIterator, Callable, Dict, Iterable, Iterator, List, Mapping, NamedTuple, Optional,
                    Sequence, Tuple, Union)

from . import _errors, _nclink
from ._model import Model
from ._types import Device, Event, MethodResult, MethodRun, MethodStatus, QueryResult, SetResult, StateChange, VersionChange

SampleBatch = _nclink.SampleBatch

#: A Query item: an id, or (id, params) with params such as {"operation": "get_length"}, {"keys": [...]}.
QueryItems = Union[str, Mapping[str, Optional[Dict[str, Any]]], Sequence[Union[str, Tuple[str, Optional[Dict[str, Any]]]]]]
#: Set items: {id: value} (each sent as {"value": value}), or [(id, params)] for list and dict operations.
SetItems = Union[Mapping[str, Any], Sequence[Tuple[str, Dict[str, Any]]]]

_MISSING: Any = object()


@dataclass(frozen=True)
class Tls:
    """TLS for ssl:// broker URLs (the broker's CA, and a client certificate for mutual TLS)."""

    ca_file: str = ""
    cert_file: str = ""
    key_file: str = ""
    key_password: str = ""
    verify_server: bool = True


class Row(NamedTuple):
    """One sample row: its channel, its time (seconds since the epoch) and {point id: value}."""

    channel: str
    time: float
    values: Dict[str, Any]


def _query_items(items: QueryItems) -> List[Tuple[str, Optional[Dict[str, Any]]]]:
    if isinstance(items, str):
        return [(items, None)]
    if isinstance(items, Mapping):
        return [(str(k), v) for k, v in items.items()]
    out: List[Tuple[str, Optional[Dict[str, Any]]]] = []
    for item in items:
        if isinstance(item, str):
            out.append((item, None))
        elif isinstance(item, (tuple, list)) and len(item) == 2 and isinstance(item[0], str):
            out.append((item[0], item[1]))
        else:
            raise TypeError(f"a query item is an id or (id, params), not {item!r}")
    return out


def _set_items(items: SetItems) -> List[Tuple[str, Dict[str, Any]]]:
    if isinstance(items, Mapping):
        return [(str(k), {"value": v}) for k, v in items.items()]
    out: List[Tuple[str, Dict[str, Any]]] = []
    for item in items:
        if isinstance(item, (tuple, list)) and len(item) == 2 and isinstance(item[0], str) and isinstance(item[1], dict):
            out.append((item[0], item[1]))
        else:
            raise TypeError(f"a set item is (id, params dict), not {item!r}")
    return out


def _bridge(loop: asyncio.AbstractEventLoop) -> Tuple["asyncio.Future[Any]", Callable[[Any, Any], None]]:
    """A future of `loop` and the done(value, error) callback that settles it from any thread."""
    future: asyncio.Future[Any] = loop.create_future()

    def settle(value: Any, error: Optional[BaseException]) -> None:
        if future.done():  # cancelled by the awaiting task: the answer is dropped
            return
        if error is not None:
            future.set_exception(error)
        else:
            future.set_result(value)

    def done(value: Any, error: Any) -> None:
        try:
            loop.call_soon_threadsafe(settle, value, error)
        except RuntimeError:  # the loop is closed: nobody waits any more
            pass

    return future, done


class Subscription:
    """A subscription (samples, state, version, method runs, events); ``close()`` ends it."""

    def __init__(self, client: "Client", subscription: int) -> None:
        self._client = client
        self.id = subscription
        self._closed = False

    def close(self) -> None:
        if not self._closed:
            self._closed = True
            self._client._core.unsubscribe(self.id)

    def __enter__(self) -> "Subscription":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


_END: Any = object()


class SampleStream:
    """Sample batches as an iterator (``for batch in stream``) or async iterator (``async for``).

    Batches queue up (unbounded: none is lost) until read. ``timeout``: a read
    that waits longer raises nclink.Timeout (None: wait until closed; Ctrl-C
    works). Iteration ends when the stream is closed.
    """

    def __init__(self, timeout: Optional[float], loop: Optional[asyncio.AbstractEventLoop] = None) -> None:
        self.timeout = timeout
        self._loop = loop
        self._queue: "queue.SimpleQueue[Any]" = queue.SimpleQueue()
        self._aqueue: Optional["asyncio.Queue[Any]"] = asyncio.Queue() if loop is not None else None
        self._closer: Callable[[], None] = lambda: None
        self._closed = False

    # Runs on the dispatch thread.
    def _put(self, item: Any) -> None:
        if self._aqueue is not None and self._loop is not None:
            try:
                self._loop.call_soon_threadsafe(self._aqueue.put_nowait, item)
            except RuntimeError:
                pass
        else:
            self._queue.put(item)

    def get(self, timeout: Optional[float] = _MISSING) -> SampleBatch:
        """The next batch; nclink.Timeout after `timeout` s (default: the stream's), StopIteration once closed."""
        wait = self.timeout if timeout is _MISSING else timeout
        deadline = None if wait is None else time.monotonic() + wait
        while True:
            # Short waits, so the loop sees close() and Ctrl-C promptly.
            step = 0.1 if deadline is None else max(0.0, min(0.1, deadline - time.monotonic()))
            try:
                item = self._queue.get(timeout=step)
            except queue.Empty:
                if self._closed:
                    raise StopIteration from None
                if deadline is not None and time.monotonic() >= deadline:
                    raise _errors.Timeout(_errors.Timeout.CODE, "Timeout", f"no sample within {wait} s") from None
                continue
            if item is _END:
                raise StopIteration
            return item  # type: ignore[no-any-return]

    def __iter__(self) -> Iterator[SampleBatch]:
        return self

    def __next__(self) -> SampleBatch:
        return self.get()

    def __aiter__(self) -> AsyncIterator[SampleBatch]:
        if self._aqueue is None:
            raise TypeError("this stream is synchronous: make it with `await client.asamples(...)` for async for")
        return self

    async def __anext__(self) -> SampleBatch:
        assert self._aqueue is not None
        try:
            item = await asyncio.wait_for(self._aqueue.get(), self.timeout)
        except asyncio.TimeoutError:
            raise _errors.Timeout(_errors.Timeout.CODE, "Timeout", f"no sample within {self.timeout} s") from None
        if item is _END:
            raise StopAsyncIteration
        return item  # type: ignore[no-any-return]

    def rows(self) -> Iterator[Row]:
        """Row by row (slower than batches: one dict per row)."""
        for batch in self:
            ids = batch.ids
            for row in batch.rows:
                yield Row(batch.channel, row[0], dict(zip(ids, row[1:])))

    def collect(self, seconds: Optional[float] = None, rows: Optional[int] = None) -> List[SampleBatch]:
        """Batches read for `seconds`, or until at least `rows` rows came (whichever first)."""
        if seconds is None and rows is None:
            raise ValueError("give seconds, rows or both")
        out: List[SampleBatch] = []
        count = 0
        end = None if seconds is None else time.monotonic() + seconds
        while (rows is None or count < rows) and (end is None or time.monotonic() < end):
            left = None if end is None else max(0.0, end - time.monotonic())
            wait = left if self.timeout is None else (self.timeout if left is None else min(left, self.timeout))
            try:
                batch = self.get(timeout=wait)
            except _errors.Timeout:
                if end is not None and time.monotonic() >= end:
                    break
                raise
            except StopIteration:
                break
            out.append(batch)
            count += len(batch)
        return out

    def close(self) -> None:
        """Ends the subscription; iteration stops after the batches already queued."""
        if not self._closed:
            self._closed = True
            self._closer()
            self._put(_END)

    def __enter__(self) -> "SampleStream":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


class SamplingChannel:
    """A dynamic sample channel (Register/Sample, 8.2.17): ``id``, ``dev``, ``close()`` unregisters it.

    Without a callback it is also a SampleStream (``stream``; iterate the channel).
    The client's keep-alive holds the registration past the adapter's lease,
    and registers it again when the adapter restarts (same ``id`` for close()).
    """

    def __init__(self, client: "Client", dev: str, channel: str, stream: Optional[SampleStream]) -> None:
        self._client = client
        self.dev = dev
        self.id = channel
        self.stream = stream
        self._closed = False

    def close(self, timeout: Optional[float] = None) -> None:
        if self._closed:
            return
        self._closed = True
        try:
            self._client._core.unregister_sampling(self.dev, self.id, timeout)
        finally:
            if self.stream is not None:
                self.stream.close()

    def __iter__(self) -> Iterator[SampleBatch]:
        if self.stream is None:
            raise TypeError("this channel hands its batches to its callback")
        return iter(self.stream)

    def __enter__(self) -> "SamplingChannel":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


class EventRegistration:
    """An event registration (Register/Event, 8.2.27): ``id``; ``close()`` unregisters it."""

    def __init__(self, client: "Client", dev: str, event_id: str) -> None:
        self._client = client
        self.dev = dev
        self.id = event_id
        self._closed = False

    def close(self, timeout: Optional[float] = None) -> None:
        if not self._closed:
            self._closed = True
            self._client._core.unregister_event(self.dev, self.id, timeout)

    def __enter__(self) -> "EventRegistration":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


_live_clients: "weakref.WeakSet[Client]" = weakref.WeakSet()


@atexit.register
def _close_all() -> None:
    # Before the interpreter goes away: a dispatch thread must not be left
    # waiting for the GIL of a finalizing interpreter.
    for client in list(_live_clients):
        try:
            client.close()
        except Exception:  # pragma: no cover - best effort at exit
            pass


class Client:
    """An NC-Link application on an MQTT broker.

    ``broker``: "tcp://host:1883" or "ssl://host:8883" (with ``tls``);
    ``client_id``: this application's terminal id (default nclink-py-<pid>-<random>);
    ``timeout``: seconds a request waits by default; ``keepalive``: seconds
    between the liveness Queries that keep this application's event and
    dynamic-channel registrations past the adapter's lease (0 = off);
    ``on_link_state(state)``: "connecting", "connected", "disconnected";
    ``failover``: further brokers, in order ("host:port" with the scheme of
    ``broker``, or URLs): a failed connect attempt, or a connection lost before
    it was stable, moves on to the next one.
    Nothing happens on the network until ``connect()``.
    """

    def __init__(self, broker: str = "tcp://127.0.0.1:1883", client_id: Optional[str] = None, *,
                 username: Optional[str] = None, password: Optional[str] = None, tls: Optional[Tls] = None,
                 timeout: float = 2.0, keepalive: float = 60.0, clean_session: bool = True,
                 connect_timeout: float = 5.0, reconnect_max: float = 10.0, log_level: str = "error",
                 on_link_state: Optional[Callable[[str], None]] = None,
                 max_queued_requests: Optional[int] = None, duplicate_memory: Optional[int] = None,
                 stop_flush_timeout: Optional[float] = None, mqtt_version: Optional[Union[int, str]] = None,
                 mqtt_keepalive: Optional[float] = None, reconnect_min: Optional[float] = None,
                 outbox_max_bytes: Optional[int] = None, outbox_max_in_flight: Optional[int] = None,
                 tcp_nodelay: Optional[bool] = None, last_will: Optional[Tuple[str, str, int, bool]] = None,
                 failover: Optional[Sequence[str]] = None) -> None:
        if client_id is None:
            client_id = f"nclink-py-{os.getpid()}-{uuid.uuid4().hex[:8]}"
        if isinstance(failover, str):
            # A lone URL would be taken for a list of one-letter brokers.
            raise ValueError("failover is a list of broker URLs, e.g. [\"tcp://broker-2:1883\"]")
        tls_dict = None if tls is None else {
            "ca_file": tls.ca_file, "cert_file": tls.cert_file, "key_file": tls.key_file,
            "key_password": tls.key_password, "verify_server": tls.verify_server}
        # The less used options go by name, only when given: the C++ defaults stand otherwise.
        given = {"max_queued_requests": max_queued_requests, "duplicate_memory": duplicate_memory,
                 "stop_flush_timeout": stop_flush_timeout, "mqtt_version": mqtt_version,
                 "mqtt_keepalive": mqtt_keepalive, "reconnect_min": reconnect_min,
                 "outbox_max_bytes": outbox_max_bytes, "outbox_max_in_flight": outbox_max_in_flight,
                 "tcp_nodelay": tcp_nodelay, "last_will": last_will,
                 "failover": None if failover is None else list(failover)}
        advanced = {k: v for k, v in given.items() if v is not None}
        self.broker = broker
        self._timeout = timeout
        self._core = _nclink.Core(broker, client_id, username or "", password or "", tls_dict, timeout, keepalive,
                                  clean_session, connect_timeout, reconnect_max, log_level, on_link_state,
                                  advanced or None)
        self._models: Dict[str, Model] = {}
        self._model_fetched = threading.Condition()
        self._closed = False
        _live_clients.add(self)

    # ---- connection ---------------------------------------------------------------
    def connect(self, timeout: float = 5.0, register: bool = True, register_timeout: Optional[float] = None) -> str:
        """Connects to the broker (nclink.Timeout when it does not answer, nclink.PermissionDenied
        when it refuses the credentials) and registers with the agent (Register/Request, 8.2.1).
        Returns "accepted", "refused", "no_answer" (no agent: normal) or "not_sent" (register=False)."""
        return str(self._core.connect(timeout, register, register_timeout))

    async def aconnect(self, timeout: float = 5.0, register: bool = True,
                       register_timeout: Optional[float] = None) -> str:
        return await asyncio.get_running_loop().run_in_executor(None, self.connect, timeout, register,
                                                                register_timeout)

    def close(self) -> None:
        """Stops the client: pending requests fail with nclink.Unavailable, callbacks end. Idempotent."""
        if not self._closed:
            self._closed = True
            self._core.close()
            _live_clients.discard(self)

    def __enter__(self) -> "Client":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    # ---- requests -----------------------------------------------------------------
    def register(self, timeout: Optional[float] = None) -> str:
        """Register/Request again: "accepted", "refused" or "no_answer" (no agent answered in time)."""
        return str(self._core.register(timeout))

    def discover(self, timeout: Optional[float] = None) -> List[Device]:
        """The adapters this application may reach, as the agent lists them (Discovery, 8.2.3)."""
        return list(self._core.discover(timeout))

    def probe(self, dev: str, timeout: Optional[float] = None) -> Dict[str, Any]:
        """The device's model as received (Probe/Query, 8.2.7): plain dicts and lists."""
        return dict(self._core.probe(dev, timeout))

    def model(self, dev: str, timeout: Optional[float] = None) -> Model:
        """The device's model as a Model (nodes with ids and paths)."""
        model = Model(self.probe(dev, timeout))
        self._models[dev] = model
        return model

    def probe_set(self, dev: str, model: Union[Dict[str, Any], Model], timeout: Optional[float] = None) -> None:
        """Sends a new model (Probe/Set, 8.2.9); a refused one raises (e.g. nclink.BadSyntax)."""
        self._core.probe_set(dev, model.raw if isinstance(model, Model) else model, timeout)
        self._models.pop(dev, None)

    def query(self, dev: str, items: QueryItems, timeout: Optional[float] = None,
              check: bool = False) -> List[QueryResult]:
        """Query (8.2.11): one QueryResult per item, in order. An item is an id or (id, params),
        params giving list and dict operations: {"indexes": [0, 2]}, {"keys": ["P1"]},
        {"operation": "get_length"}, ... ``check``: raise the first item's NG."""
        results: List[QueryResult] = self._core.query(dev, _query_items(items), timeout)
        if check:
            _raise_first(results)
        return results

    def get(self, dev: str, id: str, timeout: Optional[float] = None, **params: Any) -> List[Any]:
        """The values of one item (always a list, as the standard sends them); its NG raises."""
        result = self.query(dev, [(id, params or None)], timeout)[0]
        result.raise_for_error()
        return list(result.values or [])

    def value(self, dev: str, id: str, timeout: Optional[float] = None, **params: Any) -> Any:
        """The first of get()'s values (None when there is none)."""
        values = self.get(dev, id, timeout, **params)
        return values[0] if values else None

    def set(self, dev: str, items: SetItems, timeout: Optional[float] = None, check: bool = True) -> List[SetResult]:
        """Set (8.2.13): {id: value, ...} or [(id, params), ...] (params for list and dict
        operations: {"key": "P1", "value": 3}, {"index": 0, "value": ...}). ``check``
        (default): raise the first refused item (nclink.NotSetable for 301), the
        exception's ``results`` holding every item's result."""
        results: List[SetResult] = self._core.set(dev, _set_items(items), timeout)
        if check:
            _raise_first(results)
        return results

    def put(self, dev: str, id: str, value: Any = _MISSING, timeout: Optional[float] = None, **params: Any) -> None:
        """Sets one item: put(dev, "feed_override", 80), put(dev, "parameters", key="P1", value=3)."""
        if value is not _MISSING:
            params["value"] = value
        self.set(dev, [(id, params)], timeout)

    def call(self, dev: str, method: str, args: Optional[Dict[str, Any]] = None, *,
             on_status: Optional[Callable[[MethodStatus], None]] = None,
             timeout: Optional[float] = None) -> MethodResult:
        """Calls a method (Method/Call, 8.2.22) and waits for its Method/Result. ``on_status`` gets each
        Method/Status (progress) on the dispatch thread. A finished or canceled call returns its
        MethodResult; a refused or failed one raises its code (e.g. nclink.NodeNotExists)."""
        result: MethodResult = self._core.call_method(dev, method, args, on_status, timeout)
        err = result.error()
        if err is not None:
            raise err
        return result

    def control(self, dev: str, method: str, action: str, *, call_id: Optional[str] = None,
                timeout: Optional[float] = None) -> None:
        """Method/Control (8.2.25): action "stop" (pause), "resume" or "cancel" the running calls of
        `method` (``call_id``: only that call, its MethodStatus.call_id)."""
        self._core.control_method(dev, method, action, call_id, timeout)

    def device_state(self, dev: str, timeout: Optional[float] = None) -> str:
        """The device's retained Notify/State (8.2.16): "online" or "offline" (nclink.Timeout when
        none is published)."""
        got: "queue.SimpleQueue[str]" = queue.SimpleQueue()
        sub = self.on_state(dev, lambda change: got.put(change.state))
        try:
            wait = 2.0 if timeout is None else timeout
            end = time.monotonic() + wait
            while True:
                try:
                    return got.get(timeout=max(0.0, min(0.1, end - time.monotonic())))
                except queue.Empty:
                    if time.monotonic() >= end:
                        raise _errors.Timeout(_errors.Timeout.CODE, "Timeout",
                                              f"no Notify/State of {dev} within {wait} s") from None
        finally:
            sub.close()

    # ---- samples --------------------------------------------------------------------
    def _layouts(self, dev: str, model: Optional[Union[Model, Dict[str, Any]]]) -> Dict[str, Tuple[float, List[str]]]:
        if model is None:
            model = self._models.get(dev) or self.model(dev)
        elif not isinstance(model, Model):
            model = Model(model)
        return model.channel_layouts()

    def on_samples(self, dev: str, callback: Callable[[SampleBatch], None], channel: Optional[str] = None, *,
                   model: Optional[Union[Model, Dict[str, Any]]] = None) -> Subscription:
        """Calls callback(batch) for each Sample DTU of the device's model channels (or one channel),
        on the dispatch thread. Row times come from the channels' sampleInterval: the model is
        probed unless given. The subscription outlives adapter restarts and broker outages."""
        layouts = self._layouts(dev, model)
        return Subscription(self, self._core.subscribe_samples(dev, channel, layouts, callback))

    def samples(self, dev: str, channel: Optional[str] = None, *, timeout: Optional[float] = None,
                model: Optional[Union[Model, Dict[str, Any]]] = None) -> SampleStream:
        """A SampleStream of the device's model channels (``for batch in client.samples(dev)``)."""
        stream = SampleStream(timeout)
        sub = self.on_samples(dev, stream._put, channel, model=model)
        stream._closer = sub.close
        return stream

    async def asamples(self, dev: str, channel: Optional[str] = None, *, timeout: Optional[float] = None,
                       model: Optional[Union[Model, Dict[str, Any]]] = None) -> SampleStream:
        """The same for ``async for``."""
        stream = SampleStream(timeout, asyncio.get_running_loop())
        if model is None and dev not in self._models:
            model = Model(await self.aprobe(dev))
            self._models[dev] = model
        sub = self.on_samples(dev, stream._put, channel, model=model)
        stream._closer = sub.close
        return stream

    def sample(self, dev: str, ids: Sequence[str], sample_ms: float, upload_ms: float,
               callback: Optional[Callable[[SampleBatch], None]] = None, *, qos: Optional[int] = None,
               timeout: Optional[float] = None, stream_timeout: Optional[float] = None) -> SamplingChannel:
        """Dynamic sampling (Register/Sample, 8.2.17): `ids` read every `sample_ms`, sent every
        `upload_ms`. Batches go to `callback` (dispatch thread), else iterate the channel.
        Refusals raise (nclink.NodeNotExists 401, nclink.BadAttribute 411 intervals,
        nclink.InsufficientDynamicSampling 415)."""
        stream = None if callback is not None else SampleStream(stream_timeout)
        handler = callback if callback is not None else stream._put  # type: ignore[union-attr]
        channel = str(self._core.register_sampling(dev, list(ids), sample_ms, upload_ms, handler, qos, timeout))
        return SamplingChannel(self, dev, channel, stream)

    async def asample(self, dev: str, ids: Sequence[str], sample_ms: float, upload_ms: float,
                      callback: Optional[Callable[[SampleBatch], None]] = None, *, qos: Optional[int] = None,
                      timeout: Optional[float] = None, stream_timeout: Optional[float] = None) -> SamplingChannel:
        """The same, awaitable; without a callback the channel's stream is for ``async for``."""
        loop = asyncio.get_running_loop()
        stream = None if callback is not None else SampleStream(stream_timeout, loop)
        handler = callback if callback is not None else stream._put  # type: ignore[union-attr]
        future, done = _bridge(loop)
        self._core.register_sampling(dev, list(ids), sample_ms, upload_ms, handler, qos, timeout, done)
        return SamplingChannel(self, dev, str(await future), stream)

    # ---- notifications and events --------------------------------------------------
    def on_state(self, tid: Optional[str], callback: Callable[[StateChange], None]) -> Subscription:
        """Notify/State of a terminal (None: of every terminal); the retained state comes at once."""
        return Subscription(self, self._core.subscribe_state(tid, callback))

    def on_version(self, dev: str, callback: Callable[[VersionChange], None]) -> Subscription:
        """Probe/Version (8.2.5): the adapter announces its model version (at each start)."""
        return Subscription(self, self._core.subscribe_version(dev, callback))

    def on_method_runs(self, dev: str, callback: Callable[[MethodRun], None]) -> Subscription:
        """Method/Status and Method/Result of every application's calls at the device."""
        return Subscription(self, self._core.subscribe_method_runs(dev, callback))

    def on_events(self, dev: str, callback: Callable[[Event], None]) -> Subscription:
        """Event DTUs of every application's registrations at the device (``app`` names it)."""
        return Subscription(self, self._core.subscribe_events(dev, callback))

    def register_event(self, dev: str, id: str, callback: Callable[[Event], None], *, key: Optional[str] = None,
                       index: Optional[int] = None, filters: Sequence[Dict[str, Any]] = (),
                       trigger: str = "always", timeout: Optional[float] = None) -> EventRegistration:
        """Register/Event (8.2.27) on item `id` (``key``/``index`` for a dict/list element);
        ``filters`` e.g. [{"type": "range", "from": 10, "to": 20}], ``trigger`` always/normal/once.
        callback(Event) runs on the dispatch thread."""
        event_id = self._core.register_event(dev, id, key, index, list(filters), trigger, callback, timeout)
        return EventRegistration(self, dev, str(event_id))

    async def aregister_event(self, dev: str, id: str, callback: Callable[[Event], None], *,
                              key: Optional[str] = None, index: Optional[int] = None,
                              filters: Sequence[Dict[str, Any]] = (), trigger: str = "always",
                              timeout: Optional[float] = None) -> EventRegistration:
        future, done = _bridge(asyncio.get_running_loop())
        self._core.register_event(dev, id, key, index, list(filters), trigger, callback, timeout, done)
        return EventRegistration(self, dev, str(await future))

    # ---- model cache ---------------------------------------------------------------
    def _follow(self, dev: str, callback: Optional[Callable[[str, Dict[str, Any]], None]],
                first: Optional[Callable[[Dict[str, Any]], None]] = None) -> None:
        pending = [first]

        def on_model(d: str, model: Dict[str, Any]) -> None:  # the dispatch thread
            with self._model_fetched:
                self._model_fetched.notify_all()
            once = pending[0]
            if once is not None:
                pending[0] = None
                once(model)
            if callback is not None:
                callback(d, model)

        self._core.follow_model(dev, on_model)

    def follow_model(self, dev: str, callback: Optional[Callable[[str, Dict[str, Any]], None]] = None) -> None:
        """Keeps the device's model in the client's cache (8.2.7.3): probes it now, and again whenever
        the adapter announces (Probe/Version, 8.2.5) a version other than the cached one.
        ``callback(dev, model)`` gets every model fetched, on the dispatch thread. Returns at once
        (also from a callback); ``wait_model()``/``afollow_model()`` wait for the model. A second
        call for the same device replaces the callback. Needs connect() first (nclink.Unavailable)."""
        self._follow(dev, callback)

    async def afollow_model(self, dev: str, callback: Optional[Callable[[str, Dict[str, Any]], None]] = None,
                            timeout: Optional[float] = None) -> Dict[str, Any]:
        """follow_model(), then awaits the model it fetches. nclink.Timeout when none comes within
        ``timeout`` (default: the client's request timeout and a second)."""
        future, done = _bridge(asyncio.get_running_loop())
        self._follow(dev, callback, lambda model: done(model, None))
        wait = self._timeout + 1.0 if timeout is None else timeout
        try:
            return dict(await asyncio.wait_for(future, wait))
        except asyncio.TimeoutError:
            raise _errors.Timeout(_errors.Timeout.CODE, "Timeout",
                                  f"no model of {dev} fetched within {wait} s") from None

    def wait_model(self, dev: str, timeout: Optional[float] = None) -> Dict[str, Any]:
        """The cached model of a followed device, waiting until one is fetched (nclink.Timeout after
        ``timeout``, default: the client's request timeout and a second; Ctrl-C works). From a callback
        of this client it raises nclink.Unavailable: the fetch would wait for the very thread."""
        if self._core.in_callback:
            raise _errors.Unavailable(_errors.Unavailable.CODE, "Unavailable",
                                      "wait_model() in a callback of the same client would never end: "
                                      "use follow_model(dev, callback) or afollow_model()")
        wait = self._timeout + 1.0 if timeout is None else timeout
        end = time.monotonic() + wait
        while True:
            model = self.cached_model(dev)
            if model is not None:
                return model
            left = end - time.monotonic()
            if left <= 0:
                raise _errors.Timeout(_errors.Timeout.CODE, "Timeout", f"no model of {dev} fetched within {wait} s")
            with self._model_fetched:
                self._model_fetched.wait(min(left, 0.05))

    def cached_model(self, dev: str) -> Optional[Dict[str, Any]]:
        """The model the cache holds for a followed device (plain dicts), None until one is fetched."""
        model = self._core.cached_model(dev)
        return None if model is None else dict(model)

    def cached_model_version(self, dev: str) -> str:
        """The cached model's device version ("" when none is cached)."""
        return str(self._core.cached_model_version(dev))

    # ---- introspection ---------------------------------------------------------------
    def stats(self) -> Dict[str, Any]:
        """The client's counters (requests, responses, timeouts, samples, events, ..., transport)."""
        return dict(self._core.stats())

    @property
    def client_id(self) -> str:
        return str(self._core.client_id)

    @property
    def link_state(self) -> str:
        """The broker link: "disconnected", "connecting", "connected"."""
        return str(self._core.link_state)

    @property
    def client_state(self) -> str:
        """The application state machine: "initial", "normal", "request", "disconnected"."""
        return str(self._core.state)

    @property
    def pending_requests(self) -> int:
        return int(self._core.pending_requests)

    @property
    def event_registrations(self) -> int:
        """Event registrations of this client whose callbacks are in place (once ones leave after firing)."""
        return int(self._core.event_registrations)

    @property
    def model_reprobes(self) -> int:
        """Models the cache fetched (follow_model(), and each announced version change)."""
        return int(self._core.model_reprobes)

    @property
    def reregistrations(self) -> int:
        """Event registrations and dynamic channels made again after their adapter restarted."""
        return int(self._core.reregistrations)

    # ---- asyncio -----------------------------------------------------------------------
    async def _await(self, method: Callable[..., Any], *args: Any) -> Any:
        future, done = _bridge(asyncio.get_running_loop())
        method(*args, done)
        return await future

    async def aregister(self, timeout: Optional[float] = None) -> str:
        return str(await self._await(self._core.register, timeout))

    async def adiscover(self, timeout: Optional[float] = None) -> List[Device]:
        return list(await self._await(self._core.discover, timeout))

    async def aprobe(self, dev: str, timeout: Optional[float] = None) -> Dict[str, Any]:
        return dict(await self._await(self._core.probe, dev, timeout))

    async def amodel(self, dev: str, timeout: Optional[float] = None) -> Model:
        model = Model(await self.aprobe(dev, timeout))
        self._models[dev] = model
        return model

    async def aprobe_set(self, dev: str, model: Union[Dict[str, Any], Model], timeout: Optional[float] = None) -> None:
        await self._await(self._core.probe_set, dev, model.raw if isinstance(model, Model) else model, timeout)
        self._models.pop(dev, None)

    async def aquery(self, dev: str, items: QueryItems, timeout: Optional[float] = None,
                     check: bool = False) -> List[QueryResult]:
        results: List[QueryResult] = await self._await(self._core.query, dev, _query_items(items), timeout)
        if check:
            _raise_first(results)
        return results

    async def aget(self, dev: str, id: str, timeout: Optional[float] = None, **params: Any) -> List[Any]:
        result = (await self.aquery(dev, [(id, params or None)], timeout))[0]
        result.raise_for_error()
        return list(result.values or [])

    async def aset(self, dev: str, items: SetItems, timeout: Optional[float] = None,
                   check: bool = True) -> List[SetResult]:
        results: List[SetResult] = await self._await(self._core.set, dev, _set_items(items), timeout)
        if check:
            _raise_first(results)
        return results

    async def acall(self, dev: str, method: str, args: Optional[Dict[str, Any]] = None, *,
                    on_status: Optional[Callable[[MethodStatus], None]] = None,
                    timeout: Optional[float] = None) -> MethodResult:
        result: MethodResult = await self._await(self._core.call_method, dev, method, args, on_status, timeout)
        err = result.error()
        if err is not None:
            raise err
        return result

    async def acontrol(self, dev: str, method: str, action: str, *, call_id: Optional[str] = None,
                       timeout: Optional[float] = None) -> None:
        await self._await(self._core.control_method, dev, method, action, call_id, timeout)


def _raise_first(results: Iterable[Union[QueryResult, SetResult]]) -> None:
    listed = list(results)
    for result in listed:
        err = result.error()
        if err is not None:
            err.results = listed  # type: ignore[attr-defined]
            raise err


def connect(broker: str = "tcp://127.0.0.1:1883", client_id: Optional[str] = None, *, timeout: float = 5.0,
            register: bool = True, **options: Any) -> Client:
    """A Client, connected (see Client and Client.connect for the options)."""
    client = Client(broker, client_id, **options)
    try:
        client.connect(timeout, register)
    except BaseException:
        client.close()
        raise
    return client
