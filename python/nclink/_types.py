"""The values nclink hands to Python: answers, events, notifications.

Plain frozen dataclasses; the C++ binding builds them with positional
arguments in the order the fields are declared here.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Optional

from . import _errors


class _ItemAnswer:
    """What a Query and a Set item answer share: its NG as an exception."""

    _operation = ""
    _set_item = False
    id: str
    ok: bool
    code: int
    reason: Optional[str]
    private_info: Any

    def error(self) -> Optional[_errors.Error]:
        """The item's NG as an exception (None when OK; a Set's 301 gives NotSetable)."""
        if self.ok:
            return None
        message = f"{self._operation} of {self.id}"
        if isinstance(self.private_info, dict) and "message" in self.private_info:
            message += f": {self.private_info['message']}"
        return _errors.from_code(self.code, self.reason, message, set_item=self._set_item)

    def raise_for_error(self) -> None:
        err = self.error()
        if err is not None:
            raise err


@dataclass(frozen=True)
class QueryResult(_ItemAnswer):
    """One item of a Query answer (8.2.12): ``values`` (always a list) when ``ok``, else ``code``/``reason``."""

    _operation = "query"

    id: str
    ok: bool
    values: Optional[list[Any]]
    code: int
    reason: Optional[str]
    params: Any
    private_info: Any


@dataclass(frozen=True)
class SetResult(_ItemAnswer):
    """One item of a Set answer (8.2.14)."""

    _operation = "set"
    _set_item = True

    id: str
    ok: bool
    code: int
    reason: Optional[str]
    params: Any
    private_info: Any


@dataclass(frozen=True)
class MethodStatus:
    """A Method/Status (8.2.23): ``status`` waiting/executing/stopped/sleep, ``progress`` percent."""

    call_id: Optional[str]
    dev: str
    method: str
    status: str
    progress: Optional[float]


@dataclass(frozen=True)
class MethodResult:
    """A Method/Result (8.2.24): ``result`` finished/canceled/error, ``value`` the method's return."""

    call_id: Optional[str]
    dev: str
    method: str
    result: str
    ok: bool
    code: int
    reason: Optional[str]
    value: Any
    private_info: Any

    def error(self) -> Optional[_errors.Error]:
        """A refused or failed call as an exception (None when finished or canceled)."""
        if self.ok and self.result != "error":
            return None
        code = self.code if self.code else _errors.Unavailable.CODE
        return _errors.from_code(code, self.reason, f"method {self.method} at {self.dev}: {self.result}")


@dataclass(frozen=True)
class Event:
    """An Event DTU (8.2.31): ``item`` changed to ``value`` at ``time_ms`` (ms since the epoch)."""

    event_id: str
    dev: str
    app: str
    time_ms: int
    item: str
    value: Any
    old_value: Any
    key: Optional[str]
    index: Optional[int]
    private_info: Any

    @property
    def time(self) -> float:
        """Seconds since the epoch, like time.time()."""
        return self.time_ms / 1000.0


@dataclass(frozen=True)
class Device:
    """An entry of the agent's device list (Discovery, 8.2.4)."""

    guid: str
    status: str
    last_alive: str


@dataclass(frozen=True)
class StateChange:
    """A Notify/State (8.2.16): ``state`` online/offline of terminal ``tid``."""

    tid: str
    state: str


@dataclass(frozen=True)
class VersionChange:
    """A Probe/Version (8.2.5): the adapter announces its model version."""

    dev: str
    version: str


@dataclass(frozen=True)
class MethodRun:
    """A method run of any application at a device (``kind`` status or result)."""

    kind: str
    dev: str
    app: str
    status: Optional[MethodStatus]
    result: Optional[MethodResult]
