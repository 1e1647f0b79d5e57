"""geode.Network, Node and Parm: a node network built and edited as Houdini's ``hou`` does it, then cooked."""

from __future__ import annotations

import math
import numbers
import os
from typing import Any, Iterable, Optional, Sequence, Union

from . import _geode
from ._display import network_svg
from ._errors import error, invalid, not_found
from ._geode import EditError
from .geometry import Geometry

PathLike = Union[str, "os.PathLike[str]"]


def _wrap(value: Any) -> Any:
    if isinstance(value, _geode.Geometry) and not isinstance(value, Geometry):
        return Geometry(value)
    if isinstance(value, dict):
        return {k: _wrap(v) for k, v in value.items()}
    return value


class Network:
    """A node network: its nodes, wires, parameters and keys, as a network file holds them.

    Every edit goes through geode's own edit functions (those the studio
    uses), so what Python builds is what the file would say. A refused edit
    raises ``EditError``; a parameter value the node cannot take raises
    ``LoadError`` and leaves the old value.
    """

    def __init__(self, _native: Optional[_geode.Network] = None):
        self._net = _native if _native is not None else _geode.Network()

    # --- files -------------------------------------------------------------

    @classmethod
    def load(cls, path: PathLike, strict: bool = True) -> "Network":
        """Reads a network file. With ``strict`` any load problem raises ``LoadError``."""
        return cls(_geode.Network.load(os.fspath(path), strict))

    @classmethod
    def from_json(cls, text: str, strict: bool = True) -> "Network":
        return cls(_geode.Network.from_json(text, strict))

    def copy(self) -> "Network":
        """Another network with this one's nodes, file (so ``$HIP``) and
        ``python_input`` geometry, edited apart from it: one per thread when
        a wedge edits parameters."""
        return Network(self._net.copy())

    def to_json(self) -> str:
        """The document in canonical form (as ``geode fmt`` writes it)."""
        return self._net.to_json()

    def save(self, path: Optional[PathLike] = None) -> None:
        """Writes the network atomically to ``path`` (or to where it came from)."""
        self._net.save(None if path is None else os.fspath(path))

    @property
    def path(self) -> Optional[str]:
        p = self._net.path
        return None if p is None else os.fspath(p)

    # --- nodes -------------------------------------------------------------

    def create_node(self, type: str, name: Optional[str] = None, params: Optional[dict[str, Any]] = None) -> "Node":
        """Adds a node of ``type`` at the top level (named after its type when ``name`` is None)."""
        return Node(self, self._net._create("/", type, name, params))

    def node(self, path: str) -> "Node":
        """The node at ``path`` (``/box`` or ``box``; ``/loop/inner`` inside a
        subnet or block); ``NotFoundError`` (a ``KeyError``) when there is none."""
        path = path if path.startswith("/") else "/" + path
        try:
            self._net._node_info(path)
        except KeyError:
            names = ", ".join(self._net._children(path.rsplit("/", 1)[0] or "/")) if path.count("/") == 1 else ""
            raise not_found("node", path, None, f"no such node{f' (nodes: {names})' if names else ''}") from None
        return Node(self, path)

    @property
    def nodes(self) -> list["Node"]:
        """The top-level nodes."""
        return [Node(self, "/" + n) for n in self._net._children("/")]

    @property
    def output(self) -> Optional["Node"]:
        """The node whose result is the network's: the one set here (a Node,
        a name), else the one with the display flag, as the file says it.
        Setting None leaves it to the display flag."""
        path = self._net._effective_output()
        return None if path is None else Node(self, path)

    @output.setter
    def output(self, node: Union["Node", str, None]) -> None:
        _set_output(self, "/", node)

    def problems(self) -> list[dict[str, Any]]:
        """Every load problem: dicts of ``kind``, ``path``, ``param`` and ``message``."""
        return self._net.problems()

    # --- cooking -----------------------------------------------------------

    def cook(self, node: Union["Node", str, None] = None, frame: float = 1.0) -> Any:
        """Cooks ``node`` (the output when None) at ``frame`` and returns its Geometry.

        A bundle comes back as ``{name: Geometry}``. Results are cached in
        memory (and in ``GEODE_CACHE_DIR`` when set); the GIL is released
        while cooking, so threads can cook frames side by side; Ctrl-C
        cancels the cook and raises ``KeyboardInterrupt``.
        """
        target = _own(self, node).path if isinstance(node, Node) else node
        return _wrap(self._net.cook(target, _frame(frame)))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Network) and self._net == other._net

    __hash__ = None  # type: ignore[assignment]

    def _repr_svg_(self) -> str:
        return network_svg(self.to_json())

    def __repr__(self) -> str:
        names = self._net._children("/")
        return f"<geode.Network {len(names)} nodes{' from ' + self.path if self.path else ''}>"


def _frame(frame: Any) -> float:
    """A frame number; strings and the like are refused, not parsed."""
    if isinstance(frame, bool) or not isinstance(frame, numbers.Real):
        raise TypeError(f"a frame is a number, not {type(frame).__name__}")
    if not math.isfinite(frame):
        raise invalid(f"a frame is a finite number, not {frame}")
    return float(frame)


def _own(network: Network, node: "Node") -> "Node":
    """``node``, refused when it belongs to another network (its name would
    find a different node here)."""
    if node.network is not network:
        raise error(EditError, "edit", node.path, None, "is a node of another network")
    return node


def _set_output(network: Network, parent: str, node: Union["Node", str, None]) -> None:
    """Names ``parent``'s output node (moving the display flag to it where one
    is set, as Houdini's display flag is the output); None leaves it to the flag."""
    if node is None:
        network._net._set_output(parent, None)
        return
    if isinstance(node, Node):
        name = _own(network, node).name
    elif isinstance(node, str):
        name = node.rsplit("/", 1)[-1]
    else:
        raise TypeError(f"an output is a Node, a node's name or None, not {type(node).__name__}")
    network._net._set_output(parent, name)
    # Where a display flag is in use it follows the output, so the two never
    # disagree; a network without one (a file that names its output) keeps none.
    base = parent.rstrip("/")
    if any(network._net._node_info(f"{base}/{n}")["display"] for n in network._net._children(parent)):
        network._net._set_flag(f"{base}/{name}", "display", True)


def _flag(name: str, doc: str) -> property:
    """A node flag as a property that reads and writes the document."""

    def get(node: "Node") -> bool:
        return bool(node._net._node_info(node.path)[name])

    def set(node: "Node", on: bool) -> None:
        node._net._set_flag(node.path, name, bool(on))

    return property(get, set, doc=doc)


class Node:
    """A node of a network, by path. It stays valid while the node exists."""

    def __init__(self, network: Network, path: str):
        self.network = network
        self.path = path

    @property
    def _net(self) -> _geode.Network:
        return self.network._net

    @property
    def name(self) -> str:
        return self.path.rsplit("/", 1)[-1]

    @property
    def type(self) -> str:
        return str(self._net._node_info(self.path)["type"])

    @property
    def parent(self) -> Optional["Node"]:
        """The subnet or block holding this node; None at the top level."""
        head = self.path.rsplit("/", 1)[0]
        return Node(self.network, head) if head else None

    # --- wires -------------------------------------------------------------

    @property
    def inputs(self) -> list[Optional[Union["Node", str]]]:
        """What feeds each input: a Node, ``"@N"``/``"@meta"`` inside a subnet or block, or None."""
        head = self.path.rsplit("/", 1)[0]
        out: list[Optional[Union[Node, str]]] = []
        for name in self._net._node_info(self.path)["inputs"]:
            if name is None or name.startswith("@"):
                out.append(name)
            else:
                out.append(Node(self.network, f"{head}/{name}"))
        return out

    def set_input(self, index: int, source: Union["Node", str, None]) -> "Node":
        """Wires ``source`` (a sibling Node or its name, or ``"@0"``, ``"@meta"``
        inside a subnet or block) into input ``index``; None unwires it."""
        if isinstance(index, bool) or not isinstance(index, int) or index < 0:
            raise invalid(f"an input index is 0 or more, not {index!r}", self.path)
        if isinstance(source, Node):
            if source.network is not self.network:
                raise error(EditError, "edit", self.path, None, f"{source.path} is a node of another network")
            src: Optional[str] = source.path
        elif source is None:
            src = None
        elif not isinstance(source, str):
            raise TypeError(f"an input is a Node, a node's name or path, \"@0\"... or None, not {type(source).__name__}")
        elif source.startswith("@") or source.startswith("/"):
            src = source
        else:
            src = f"{self.path.rsplit('/', 1)[0]}/{source}"
        self._net._connect(self.path, index, src)
        return self

    def set_inputs(self, sources: Sequence[Union["Node", str, None]]) -> "Node":
        for i, s in enumerate(sources):
            self.set_input(i, s)
        return self

    # --- parameters --------------------------------------------------------

    def parm(self, name: str) -> "Parm":
        """The parameter ``name``; ``NotFoundError`` (a ``KeyError``) when the node has none."""
        names = self._net._param_names(self.path)
        if name not in names:
            raise not_found("parameter", self.path, name, f"no such parameter (it has: {', '.join(names)})")
        return Parm(self, name)

    def parms(self) -> list["Parm"]:
        return [Parm(self, n) for n in self._net._param_names(self.path)]

    def set_params(self, values: dict[str, Any]) -> "Node":
        """Sets several parameters: all of them, or (when one is refused) none."""
        parms = [self.parm(k) for k in values]
        before = [p.raw for p in parms]
        try:
            for p, v in zip(parms, values.values()):
                p.set(v)
        except Exception:
            for p, old in zip(parms, before):
                self._net._set_param(self.path, p.name, old)
            raise
        return self

    def add_spare(self, name: str, type: str) -> "Parm":
        """Declares a spare parameter (float, int, toggle, vector2, vector, vector4, string)."""
        self._net._set_spare(self.path, name, type)
        return Parm(self, name)

    def remove_spare(self, name: str) -> None:
        self._net._set_spare(self.path, name, None)

    # --- flags -------------------------------------------------------------

    bypass = _flag("bypass", "Whether the node passes its first input through uncooked.")
    display = _flag("display", "Houdini's display flag: the node the studio shows (and the output when none is named).")
    template = _flag("template", "Houdini's template flag: drawn as a ghost beside what is shown.")

    # --- subnets and blocks ------------------------------------------------

    def create_node(self, type: str, name: Optional[str] = None, params: Optional[dict[str, Any]] = None) -> "Node":
        """Adds a node inside this subnet, for_each, loop or solver."""
        return Node(self.network, self._net._create(self.path, type, name, params))

    @property
    def children(self) -> list["Node"]:
        if not self._net._node_info(self.path)["has_network"]:
            return []
        return [Node(self.network, f"{self.path}/{n}") for n in self._net._children(self.path)]

    def node(self, name: str) -> "Node":
        return self.network.node(f"{self.path}/{name}")

    @property
    def output(self) -> Optional["Node"]:
        """Inside a subnet or block: the node whose result leaves it."""
        name = self._net._output(self.path)
        return None if name is None else Node(self.network, f"{self.path}/{name}")

    @output.setter
    def output(self, node: Union["Node", str, None]) -> None:
        _set_output(self.network, self.path, node)

    # --- the rest ----------------------------------------------------------

    def rename(self, name: str) -> "Node":
        self.path = self._net._rename(self.path, name)
        return self

    def destroy(self) -> None:
        self._net._remove(self.path)

    def cook(self, frame: float = 1.0) -> Any:
        return self.network.cook(self, frame)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Node) and other.network is self.network and other.path == self.path

    def __hash__(self) -> int:
        return hash((id(self.network), self.path))

    def __repr__(self) -> str:
        return f"<geode.Node {self.path} ({self.type})>"


class Parm:
    """A node's parameter: its value as written, evaluated at a frame, and its keys."""

    def __init__(self, node: Node, name: str):
        self.node = node
        self.name = name

    @property
    def _net(self) -> _geode.Network:
        return self.node.network._net

    def set(self, value: Any) -> "Parm":
        """Sets the value as the network file writes it: a number, a vector
        as a sequence, a string, ``{"expr": "$F * 2"}`` for an expression,
        list rows as sequences or dicts, a ``Geometry`` (for
        ``python_input``), or None to revert to the default. A value the
        parameter cannot take raises ``LoadError`` and keeps the old one."""
        if isinstance(value, Node):
            value = value.path  # a node named by a path parameter (object_merge)
        self._net._set_param(self.node.path, self.name, value)
        return self

    @property
    def template(self) -> dict[str, Any]:
        """The parameter's declaration, as Houdini's ``parmTemplate``: ``type``,
        ``label``, ``default``, ``min``, ``max``, ``animatable``, ``help``,
        ``items`` for a menu, ``fields`` for list rows and ramps."""
        return self._net._param_template(self.node.path, self.name)

    def revert(self) -> "Parm":
        return self.set(None)

    @property
    def raw(self) -> Any:
        """The value as the network file writes it; None when it is the default."""
        return self._net._raw_param(self.node.path, self.name)

    def eval(self, frame: float = 1.0) -> Any:
        """The value at ``frame`` as the cook sees it (keys and expressions evaluated)."""
        return self._net._eval_param(self.node.path, self.name, _frame(frame))

    def set_keys(self, keys: Iterable[Any], interp: Optional[str] = None) -> "Parm":
        """Replaces the value by keyframes: ``[(frame, value), ...]`` (a value
        is a sequence for a vector parameter, one channel per component) or
        dicts with ``frame``, ``value`` and optionally ``interp`` (constant,
        linear, bezier, ease), ``slope_in``, ``slope_out``."""
        self._animatable()
        rows = [_key_row(k, interp, self) for k in keys]
        if not rows:
            raise ValueError("set_keys needs at least one key")
        widths = {len(v) if isinstance(v, (list, tuple)) else 0 for _, v, _ in rows}
        if len(widths) != 1:
            raise ValueError("every key must have the same number of components")
        width = widths.pop()
        if width == 0:
            self.set({"keys": [_key_json(f, v, extra) for f, v, extra in rows]})
        else:
            self.set([{"keys": [_key_json(f, v[c], extra) for f, v, extra in rows]} for c in range(width)])
        return self

    def set_expression(self, text: str, component: Optional[int] = None) -> "Parm":
        """Sets an expression (``"$F * 0.1"``, ``'ch("../amp")'``) as the value,
        or as one component's value of a vector parameter."""
        if component is None:
            self._animatable()
            return self.set({"expr": text})
        self._animatable()
        raw = self.raw
        current = raw if isinstance(raw, list) else self.eval()
        if not isinstance(current, (list, tuple)):
            raise invalid(f"component {component} of a parameter that has one: set_expression(text) without it", self.node.path, self.name)
        values = list(current)
        if not 0 <= component < len(values):
            raise invalid(f"component {component} of a parameter of {len(values)}", self.node.path, self.name)
        values[component] = {"expr": text}
        return self.set(values)

    def set_key(self, frame: float, value: float, component: int = 0) -> "Parm":
        """Sets one key of one component (a constant becomes a channel)."""
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise invalid(f"a key's value is a number, not {value!r}", self.node.path, self.name)
        self._net._set_key(self.node.path, self.name, component, _frame(frame), float(value))
        return self

    def delete_key(self, frame: float, component: int = 0) -> "Parm":
        self._net._delete_key(self.node.path, self.name, component, float(frame))
        return self

    def _animatable(self) -> None:
        """Refuses keys and expressions on a parameter that takes neither."""
        if not self.template.get("animatable", True):
            raise error(EditError, "edit", self.node.path, self.name, f"parameter `{self.name}` cannot be animated")

    def __repr__(self) -> str:
        raw = self.raw
        return f"<geode.Parm {self.node.path}/{self.name} = {'(default)' if raw is None else repr(raw)}>"


def _key_row(k: Any, interp: Optional[str], parm: "Parm") -> tuple[float, Any, dict[str, Any]]:
    if isinstance(k, dict):
        extra = {n: k[n] for n in ("interp", "slope_in", "slope_out") if n in k}
        frame, value = k["frame"], k["value"]
    else:
        frame, value = k
        extra = {}
    if interp is not None:
        extra.setdefault("interp", interp)
    if hasattr(value, "tolist"):
        value = value.tolist()
    parts = value if isinstance(value, (list, tuple)) else [value]
    if not all(isinstance(v, numbers.Real) and not isinstance(v, bool) for v in parts):
        raise invalid(f"a key's value is a number (or one per component), not {value!r}", parm.node.path, parm.name)
    return _frame(frame), value, extra


def _key_json(frame: float, value: Any, extra: dict[str, Any]) -> dict[str, Any]:
    return {"frame": frame, "value": float(value), **extra}
