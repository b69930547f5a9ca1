"""Table-19 errors (GB/T 41970-2022) as Python exceptions.

Every failure of a request is an ``nclink.Error`` carrying the numeric
``code``, the table-19 ``reason`` and a ``message`` for people; each code has
its own subclass, so ``except nclink.Timeout`` catches exactly 203. Codes a
vendor defines (below 0) and codes table 19 does not know are plain
``nclink.Error``.
"""

from __future__ import annotations

from typing import Dict, Optional, Type


class Error(Exception):
    """Base of every nclink error: ``code`` (int), ``reason`` (str), ``message`` (str)."""

    #: The table-19 code of the class (0 for the base class: any code).
    CODE = 0

    def __init__(self, code: int, reason: str, message: str = "") -> None:
        self.code = code
        self.reason = reason
        self.message = message
        super().__init__(f"{code} {reason}: {message}" if message else f"{code} {reason}")


class OutOfRange(Error):
    CODE = 101


class ParameterMissing(Error):
    CODE = 102


class Unavailable(Error):
    """202: the device is unreachable (DEV_UNREACHABLE), or the client is not running."""

    CODE = 202


class Timeout(Error, TimeoutError):
    """203: nobody answered in time (also a builtin TimeoutError)."""

    CODE = 203


class PermissionDenied(Error):
    CODE = 301


class NotSetable(PermissionDenied):
    """301 on an item of a Set: the adapter refused to write it (the item is not setable)."""


class NodeNotExists(Error):
    CODE = 401


class NoIndex(Error):
    CODE = 402


class NoKey(Error):
    CODE = 403


class MemoryConfigured(Error):
    CODE = 404


class ValueTypeError(Error):
    CODE = 405


class UnsupportedGetLength(Error):
    CODE = 406


class UnsupportedGetAttributes(Error):
    CODE = 407


class UnsupportedGetKeys(Error):
    CODE = 408


class ArgumentsNimiety(Error):
    CODE = 409


class BadKey(Error):
    """410 key error."""

    CODE = 410


class BadAttribute(Error):
    """411 Attribute error."""

    CODE = 411


class BadSyntax(Error):
    """412 syntax error (also: a malformed model or DTU)."""

    CODE = 412


class KeysOfArguments(Error):
    CODE = 413


class UnsupportedTerminalId(Error):
    CODE = 414


class InsufficientDynamicSampling(Error):
    CODE = 415


class InsufficientEvent(Error):
    CODE = 416


class InsufficientMethod(Error):
    CODE = 417


class MethodActionType(Error):
    CODE = 418


class FilterType(Error):
    CODE = 419


class TriggerType(Error):
    CODE = 420


class FilterArgumentsMismatch(Error):
    CODE = 421


_BY_CODE: Dict[int, Type[Error]] = {
    cls.CODE: cls
    for cls in (OutOfRange, ParameterMissing, Unavailable, Timeout, PermissionDenied, NodeNotExists, NoIndex,
                NoKey, MemoryConfigured, ValueTypeError, UnsupportedGetLength, UnsupportedGetAttributes,
                UnsupportedGetKeys, ArgumentsNimiety, BadKey, BadAttribute, BadSyntax, KeysOfArguments,
                UnsupportedTerminalId, InsufficientDynamicSampling, InsufficientEvent, InsufficientMethod,
                MethodActionType, FilterType, TriggerType, FilterArgumentsMismatch)
}


def error_class(code: int) -> Type[Error]:
    """The exception class of a code (nclink.Error for codes table 19 does not define)."""
    return _BY_CODE.get(code, Error)


def from_code(code: int, reason: Optional[str] = None, message: str = "", *, set_item: bool = False) -> Error:
    """The exception for ``code``; ``set_item``: a refused item of a Set (301 gives NotSetable)."""
    cls = error_class(code)
    if set_item and code == PermissionDenied.CODE:
        cls = NotSetable
    if not reason:
        from . import _nclink

        reason = _nclink.reason(code) if code >= 0 else "vendor error"
    return cls(code, reason, message)
