"""geode from Python: build node networks, cook them, and read the geometry as numpy arrays.

    import geode
    net = geode.Network()
    box = net.create_node("box", "b", params={"size": [1, 2, 1]})
    net.output = box
    geo = net.cook(frame=1)
    P = geo.points["P"]          # (n, 3) float32, read-only, no copy

See docs/python.md in the repository for the guide.
"""

from __future__ import annotations

from ._geode import (
    CookError,
    EditError,
    FileError,
    GeodeError,
    InvalidValueError,
    LoadError,
    NotFoundError,
    __version__,
    node_type,
    node_types,
)
from .geometry import Geometry
from .network import Network, Node, Parm

__all__ = [
    "CookError",
    "EditError",
    "FileError",
    "GeodeError",
    "Geometry",
    "InvalidValueError",
    "LoadError",
    "Network",
    "Node",
    "NotFoundError",
    "Parm",
    "__version__",
    "node_type",
    "node_types",
]
