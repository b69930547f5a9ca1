"""nclink: NC-Link (GB/T 41970-2022) applications in Python.

    import nclink
    with nclink.connect("tcp://127.0.0.1:1883", "mes-01") as client:
        print(client.value("nclink-sim-mill-01", "x_position"))

See docs/python.md for the quick start and the API reference.
"""

from ._errors import (ArgumentsNimiety, BadAttribute, BadKey, BadSyntax, Error, FilterArgumentsMismatch, FilterType,
                      InsufficientDynamicSampling, InsufficientEvent, InsufficientMethod, KeysOfArguments,
                      MemoryConfigured, MethodActionType, NodeNotExists, NoIndex, NoKey, NotSetable, OutOfRange,
                      ParameterMissing, PermissionDenied, Timeout, TriggerType, Unavailable, UnsupportedGetAttributes,
                      UnsupportedGetKeys, UnsupportedGetLength, UnsupportedTerminalId, ValueTypeError, error_class)
from ._types import (Device, Event, MethodResult, MethodRun, MethodStatus, QueryResult, SetResult, StateChange,
                     VersionChange)
from ._model import Model, Node
from ._client import (Client, EventRegistration, Row, SampleBatch, SampleStream, SamplingChannel, Subscription, Tls,
                      connect)
from ._frames import dataframe
from . import _nclink

__version__ = _nclink.sdk_version

__all__ = [
    "Client", "connect", "Tls", "Model", "Node", "SampleBatch", "SampleStream", "SamplingChannel", "Subscription",
    "EventRegistration", "Row", "dataframe",
    "QueryResult", "SetResult", "MethodStatus", "MethodResult", "MethodRun", "Event", "Device", "StateChange",
    "VersionChange",
    "Error", "error_class", "OutOfRange", "ParameterMissing", "Unavailable", "Timeout", "PermissionDenied",
    "NotSetable", "NodeNotExists", "NoIndex", "NoKey", "MemoryConfigured", "ValueTypeError", "UnsupportedGetLength",
    "UnsupportedGetAttributes", "UnsupportedGetKeys", "ArgumentsNimiety", "BadKey", "BadAttribute", "BadSyntax",
    "KeysOfArguments", "UnsupportedTerminalId", "InsufficientDynamicSampling", "InsufficientEvent",
    "InsufficientMethod", "MethodActionType", "FilterType", "TriggerType", "FilterArgumentsMismatch",
]
