"""A device's model (Probe/Query, 8.2.7) as objects with ids and paths.

``Client.probe()`` gives the model as received (plain dicts and lists);
``Client.model()`` wraps it in a ``Model``: every node (device, component,
data item, config, sample channel, method) as a ``Node`` with its ``id``,
``type``, ``name`` and ``path`` (the ids from the root down, joined by "/"),
found by id or path.
"""

from __future__ import annotations

from typing import Any, Dict, Iterator, List, Optional, Tuple

#: Node kinds: how the model names a node's role (docs/model.md).
KINDS = ("root", "device", "component", "item", "config", "channel", "method")


class Node:
    """One node of the model: ``id``, ``type``, ``name``, ``kind``, ``path``, ``raw`` (its dict)."""

    __slots__ = ("raw", "kind", "path", "parent", "children")

    def __init__(self, raw: Dict[str, Any], kind: str, path: str, parent: Optional["Node"]) -> None:
        self.raw = raw
        self.kind = kind
        self.path = path
        self.parent = parent
        self.children: List[Node] = []

    @property
    def id(self) -> str:
        return str(self.raw.get("id", ""))

    @property
    def type(self) -> str:
        return str(self.raw.get("type", ""))

    @property
    def name(self) -> str:
        return str(self.raw.get("name", ""))

    def get(self, key: str, default: Any = None) -> Any:
        """A key of the node's dict (e.g. "units", "datatype", "settable")."""
        return self.raw.get(key, default)

    def __getitem__(self, key: str) -> Any:
        return self.raw[key]

    def walk(self) -> Iterator["Node"]:
        """This node and every node below it, depth first."""
        yield self
        for child in self.children:
            yield from child.walk()

    def __repr__(self) -> str:
        return f"<Node {self.kind} {self.path} type={self.type}>"


class Model:
    """A probed model: ``raw`` (the dict), ``root``, lookups by id and path."""

    def __init__(self, raw: Dict[str, Any]) -> None:
        if not isinstance(raw, dict):
            raise TypeError("a model is a JSON object (dict)")
        self.raw = raw
        self.root = self._build(raw, "root", None)
        self._by_id: Dict[str, Node] = {}
        self._by_path: Dict[str, Node] = {}
        for node in self.root.walk():
            self._by_path[node.path] = node
            # A data item may also be listed under a channel (ids); the first
            # node with an id (the item itself, depth first) wins.
            self._by_id.setdefault(node.id, node)

    @staticmethod
    def _kind(raw: Dict[str, Any], key: str) -> str:
        if raw.get("type") == "SAMPLE_CHANNEL":
            return "channel"
        if raw.get("type") == "METHOD":
            return "method"
        return {"devices": "device", "components": "component", "dataItems": "item", "configs": "config"}.get(key, "item")

    def _build(self, raw: Dict[str, Any], kind: str, parent: Optional[Node]) -> Node:
        path = raw.get("id", "") if parent is None or parent.kind == "root" else f"{parent.path}/{raw.get('id', '')}"
        node = Node(raw, kind, str(path), parent)
        for key in ("configs", "dataItems", "components", "devices"):
            children = raw.get(key)
            if not isinstance(children, list):
                continue
            for child in children:
                if isinstance(child, dict):
                    node.children.append(self._build(child, self._kind(child, key), node))
        return node

    @property
    def version(self) -> str:
        return str(self.raw.get("version", ""))

    def find(self, id: str) -> Node:
        """The node with this id (KeyError when there is none)."""
        return self._by_id[id]

    def at(self, path: str) -> Node:
        """The node at this path, e.g. "mill/axis_x/x_position"."""
        return self._by_path[path]

    def __contains__(self, id: object) -> bool:
        return id in self._by_id

    def nodes(self, kind: Optional[str] = None) -> List[Node]:
        """Every node, or those of one kind ("device", "item", "channel", ...)."""
        return [n for n in self.root.walk() if kind is None or n.kind == kind]

    @property
    def devices(self) -> List[Node]:
        return self.nodes("device")

    @property
    def items(self) -> List[Node]:
        return self.nodes("item")

    @property
    def channels(self) -> List[Node]:
        return self.nodes("channel")

    @property
    def methods(self) -> List[Node]:
        return self.nodes("method")

    def channel_layouts(self) -> Dict[str, Tuple[float, List[str]]]:
        """{channel id: (sampleInterval in ms, [point ids])}: what gives each sample row its time."""
        out: Dict[str, Tuple[float, List[str]]] = {}
        for channel in self.channels:
            ids = [str(e.get("id", "")) if isinstance(e, dict) else str(e) for e in channel.get("ids", []) or []]
            interval = channel.get("sampleInterval", 0)
            out[channel.id] = (float(interval) if isinstance(interval, (int, float)) else 0.0, ids)
        return out

    def __repr__(self) -> str:
        return f"<Model {self.root.id} version={self.version} nodes={len(self._by_path)}>"
