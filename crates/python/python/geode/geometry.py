"""geode.Geometry: a cooked or Python-made geometry, its attributes as numpy arrays."""

from __future__ import annotations

from collections.abc import Iterator, Mapping
import os
from typing import Any, Optional, Union

import numpy as np

from . import _geode
from ._errors import invalid

_CLASS_NAMES = {
    "point": "point", "points": "point",
    "vertex": "vertex", "vertices": "vertex",
    "prim": "prim", "prims": "prim", "primitive": "prim", "primitives": "prim",
    "detail": "detail", "global": "detail",
}

# Element shape and dtype of each attribute type, for inferring a type from an array.
_FLOAT_SHAPES = {
    (): "float",
    (2,): "vector2",
    (3,): "vector3",
    (4,): "vector4",
    (3, 3): "matrix3",
    (4, 4): "matrix4",
}
_FLOAT_TYPES = {"float", "vector2", "vector3", "vector4", "quaternion", "matrix3", "matrix4"}
_ARRAY_TYPES = {"int array", "float array", "vector3 array", "string array"}


class Attributes(Mapping[str, Any]):
    """The attributes of one class (``geo.points``, ``geo.vertices``, ``geo.prims``) by name.

    Numeric attributes come back as read-only numpy arrays that share the
    geometry's memory (float32, or int32 for ``int``; vectors as (n, k),
    matrices as (n, k, k) in Houdini's row-vector layout). Strings come back
    as object arrays of ``str``, array attributes as object arrays of arrays.
    """

    def __init__(self, geo: "Geometry", cls: str):
        self._geo = geo
        self._cls = cls

    def __getitem__(self, name: str) -> np.ndarray:
        values = self._geo.attrib(self._cls, name)
        if isinstance(values, list):
            out = np.empty(len(values), dtype=object)
            for i, v in enumerate(values):
                out[i] = v
            return out
        return values

    def __iter__(self) -> Iterator[str]:
        return iter(self._geo.attrib_names(self._cls))

    def __len__(self) -> int:
        return len(self._geo.attrib_names(self._cls))

    def __contains__(self, name: object) -> bool:
        return name in self._geo.attrib_names(self._cls)

    def type(self, name: str) -> tuple[str, str]:
        """``(type, type_info)`` of an attribute, e.g. ``("vector3", "position")``."""
        return self._geo.attrib_type(self._cls, name)

    def __repr__(self) -> str:
        return f"<{self._cls} attributes: {', '.join(self) or 'none'}>"


class DetailAttributes(Attributes):
    """Detail (global) attributes: each is one value, not an array of them."""

    def __getitem__(self, name: str) -> Any:
        values = super().__getitem__(name)
        return values[0]


class Geometry(_geode.Geometry):
    """A geometry: points, vertices, primitives and their attributes.

    Immutable: ``set_attrib`` and the like return a new geometry, so arrays
    read from one never change under you.
    """

    # --- reading -----------------------------------------------------------

    @property
    def points(self) -> Attributes:
        return Attributes(self, "point")

    @property
    def vertices(self) -> Attributes:
        return Attributes(self, "vertex")

    @property
    def prims(self) -> Attributes:
        return Attributes(self, "prim")

    @property
    def detail(self) -> DetailAttributes:
        return DetailAttributes(self, "detail")

    @property
    def point_groups(self) -> dict[str, np.ndarray]:
        """Point groups as boolean arrays, one flag per point."""
        return self.groups("point")

    @property
    def prim_groups(self) -> dict[str, np.ndarray]:
        """Primitive groups as boolean arrays, one flag per primitive."""
        return self.groups("prim")

    def prim_point_lists(self) -> list[np.ndarray]:
        """Each primitive's point indices (a view of ``prim_points`` per primitive)."""
        off, pts = self.prim_offsets, self.prim_points
        return [pts[off[i] : off[i + 1]] for i in range(len(off) - 1)]

    # --- making ------------------------------------------------------------

    @classmethod
    def from_arrays(
        cls,
        points: Any,
        polygons: Optional[Any] = None,
        polylines: Optional[Any] = None,
        point_attribs: Optional[dict[str, Any]] = None,
        vertex_attribs: Optional[dict[str, Any]] = None,
        prim_attribs: Optional[dict[str, Any]] = None,
        detail_attribs: Optional[dict[str, Any]] = None,
    ) -> "Geometry":
        """A geometry from positions (n, 3), polygons and polylines.

        ``polygons`` and ``polylines`` are each either an (m, k) integer array
        (m primitives of k points) or a sequence of point-index sequences.
        Polygons come first, then polylines. Attributes are given per class as
        ``{name: values}`` (see ``set_attrib`` for how types are inferred).
        """
        P = _positions(points)
        counts: list[np.ndarray] = []
        flat: list[np.ndarray] = []
        closed: list[np.ndarray] = []
        for prims, is_closed in ((polygons, True), (polylines, False)):
            if prims is None:
                continue
            n, f = _flatten(prims)
            counts.append(n)
            flat.append(f)
            closed.append(np.full(len(n), is_closed))
        native = _geode.Geometry.from_prims(
            P, _concat(flat, np.uint32), _concat(counts, np.uint32), _concat(closed, np.bool_)
        )
        geo = cls(native)
        if point_attribs and "P" in point_attribs:
            raise invalid("P comes from points=; point_attribs cannot give it too")
        for klass, attribs in (("point", point_attribs), ("vertex", vertex_attribs), ("prim", prim_attribs), ("detail", detail_attribs)):
            for name, values in (attribs or {}).items():
                geo = geo.set_attrib(klass, name, values)
        return geo

    @classmethod
    def from_prims(cls, points: Any, vertex_points: Any, counts: Any, closed: Any) -> "Geometry":
        """Polygons and polylines from flat arrays: positions (n, 3), the point
        of every vertex, a vertex count per primitive, and whether each is closed."""
        return cls(
            _geode.Geometry.from_prims(
                _positions(points),
                _indices(vertex_points, 1).astype(np.uint32),
                _indices(counts, 1).astype(np.uint32),
                np.ascontiguousarray(np.asarray(closed, dtype=np.bool_)),
            )
        )

    @classmethod
    def load(cls, path: Union[str, "os.PathLike[str]"]) -> "Geometry":
        """Reads a geometry file (.obj .stl .ply .gltf .glb .geo .bgeo; geode writes .usda but does not read it)."""
        return cls(_geode.Geometry.load(path))

    def set_attrib(
        self, cls: str, name: str, values: Any, type: Optional[str] = None, type_info: Optional[str] = None
    ) -> "Geometry":
        """A new geometry with attribute ``name`` of class ``cls`` (point,
        vertex, prim, detail) set to ``values``.

        The type is inferred unless given: integers make ``int``; floats of
        element shape (), (2,), (3,), (4,), (3, 3), (4, 4) make ``float``,
        ``vector2``, ``vector3``, ``vector4``, ``matrix3``, ``matrix4``;
        strings make ``string``. ``quaternion`` and the array types
        (``int array``, ``float array``, ``vector3 array``, ``string array``)
        must be named. A detail attribute takes one value.

        ``type_info`` tells transforms what the values are (``position``,
        ``vector``, ``normal``, ``color``, ``quaternion``, ``texcoord``,
        ``transform``, ``none``). Unless given, the attribute keeps the tag
        of the one it replaces, else takes Houdini's for its name (``N`` a
        normal, ``v`` a vector, ``Cd`` a colour, ``orient`` a quaternion).
        """
        cls = _class(cls)
        if type is not None and type not in _FLOAT_TYPES | _ARRAY_TYPES | {"int", "string"}:
            raise invalid(f"{type!r} is not an attribute type ({', '.join(sorted(_FLOAT_TYPES | _ARRAY_TYPES | {'int', 'string'}))})")
        if type in _ARRAY_TYPES:
            return self._set_array(cls, name, values, type, type_info)
        if cls == "detail":
            values = [values]
        arr = np.asarray(values)
        if type is None:
            type = _infer_type(arr, cls, name)
        what = f"{cls} attribute {name!r}"
        if type == "string":
            return Geometry(self.with_attrib(cls, name, type, [_text(v, what) for v in arr.reshape(-1)], type_info))
        if type == "int":
            return Geometry(self.with_attrib(cls, name, type, _int32(arr, what), type_info))
        return Geometry(self.with_attrib(cls, name, type, _floats(arr, what), type_info))

    def _set_array(self, cls: str, name: str, values: Any, type: str, type_info: Optional[str]) -> "Geometry":
        rows = [values] if cls == "detail" else list(values)
        what = f"{cls} attribute {name!r}"
        if type == "string array":
            return Geometry(self.with_attrib(cls, name, type, [[_text(x, what) for x in r] for r in rows], type_info))
        flat = [_floats(r, what, np.float64).reshape(-1).tolist() for r in rows]
        return Geometry(self.with_attrib(cls, name, type, flat, type_info))

    def remove_attrib(self, cls: str, name: str) -> "Geometry":
        return Geometry(self.without_attrib(_class(cls), name))

    def set_group(self, cls: str, name: str, mask: Any) -> "Geometry":
        """A new geometry with point or prim group ``name`` from a boolean mask
        (booleans, or numbers that are all 0 or 1)."""
        flags = np.asarray(mask)
        if flags.dtype != np.bool_ and flags.size and not np.isin(flags, (0, 1)).all():
            raise invalid(f"group {name!r}: a mask holds booleans (or 0 and 1), not {flags.dtype} values like {flags.flat[0]!r}")
        return Geometry(self.with_group(_class(cls), name, np.ascontiguousarray(flags, dtype=np.bool_)))

    # --- handing on --------------------------------------------------------

    def to_trimesh(self) -> Any:
        """A ``trimesh.Trimesh`` of the polygons (triangulated as geode does)."""
        try:
            import trimesh
        except ImportError as e:
            raise ImportError("to_trimesh needs trimesh: pip install trimesh") from e
        return trimesh.Trimesh(
            vertices=np.array(self.points["P"], dtype=np.float64),
            faces=np.array(self.triangles(), dtype=np.int64),
            process=False,
        )

    def _repr_png_(self) -> bytes:
        return self.png()

    def __repr__(self) -> str:
        return (
            f"<geode.Geometry {self.num_points} points, {self.num_prims} prims, "
            f"hash {self.content_hash[:8]}>"
        )


def _concat(parts: list[np.ndarray], dtype: Any) -> np.ndarray:
    """The parts end to end as one contiguous array of ``dtype``."""
    if not parts:
        return np.zeros(0, dtype=dtype)
    return np.ascontiguousarray(np.concatenate(parts).astype(dtype))


def _indices(values: Any, ndim: int) -> np.ndarray:
    """Point indices of ``ndim`` dimensions as int64, refusing what is not
    a whole number from 0 to 2**32 - 1."""
    arr = np.asarray(values)
    if arr.ndim != ndim:
        raise invalid(f"a primitive's point indices are a list of numbers; got an array of shape {arr.shape}")
    if arr.size and arr.dtype.kind not in "iu":
        raise invalid(f"point indices must be integers, not {arr.dtype}")
    if arr.size and (arr.min() < 0 or arr.max() > np.iinfo(np.uint32).max):
        raise invalid("point indices must be 0 or more and fit 32 bits")
    return arr.astype(np.int64).reshape(-1)


def _flatten(prims: Any) -> tuple[np.ndarray, np.ndarray]:
    """Vertex counts and flat point indices of uniform (m, k) or ragged primitives."""
    if isinstance(prims, np.ndarray) and prims.dtype != object:
        m, k = prims.shape if prims.ndim == 2 else (0, 0)
        return np.full(m, k, dtype=np.int64), _indices(prims, 2)
    seqs = [_indices(p, 1) for p in prims]
    counts = np.array([len(s) for s in seqs], dtype=np.int64)
    flat = np.concatenate(seqs) if seqs else np.zeros(0, dtype=np.int64)
    return counts, flat


def _positions(points: Any) -> np.ndarray:
    """Positions as a contiguous (n, 3) float32 array; any other shape refused."""
    P = _floats(points, "points")
    if P.size == 0:
        P = P.reshape(0, 3)
    if P.ndim != 2 or P.shape[1] != 3:
        raise invalid(f"points must be an (n, 3) array of positions, not of shape {P.shape}")
    return P


def _floats(values: Any, what: str, dtype: Any = np.float32) -> np.ndarray:
    """Real numbers as a contiguous array of ``dtype``; anything else
    (text, complex numbers, objects) refused rather than converted."""
    try:
        arr = np.asarray(values)
        if arr.dtype.kind == "c":
            raise invalid(f"{what}: complex numbers have no place in geometry")
        if arr.size and arr.dtype.kind not in "biuf":
            raise invalid(f"{what}: numbers expected, not {arr.dtype} values like {arr.flat[0]!r}")
        return np.ascontiguousarray(arr, dtype=dtype)
    except ValueError as e:
        if isinstance(e, _geode.GeodeError):
            raise
        raise invalid(f"{what}: numbers expected ({e})") from None


def _text(value: Any, what: str) -> str:
    """A string attribute's value: text, or bytes as UTF-8."""
    if isinstance(value, (bytes, np.bytes_)):
        try:
            return bytes(value).decode("utf-8")
        except UnicodeDecodeError:
            raise invalid(f"{what}: bytes that are not UTF-8 text") from None
    if isinstance(value, str):
        return value
    raise invalid(f"{what}: text expected, not {type(value).__name__} {value!r}")


def _class(name: str) -> str:
    """An attribute class by any of its names (``prim``, ``primitive``, ``points``...)."""
    cls = _CLASS_NAMES.get(name)
    if cls is None:
        raise invalid(f"{name!r} is not an attribute class (point, vertex, prim, detail)")
    return cls


def _int32(arr: np.ndarray, what: str) -> np.ndarray:
    """Integers as int32, refusing any that int32 cannot hold (rather than wrapping)."""
    if arr.size and arr.dtype.kind in "iu":
        lo, hi = np.iinfo(np.int32).min, np.iinfo(np.int32).max
        if arr.min() < lo or arr.max() > hi:
            raise invalid(f"{what}: integers from {lo} to {hi} only (int attributes are 32-bit)")
    return np.ascontiguousarray(arr, dtype=np.int32)


def _infer_type(arr: np.ndarray, cls: str, name: str) -> str:
    if arr.dtype.kind in "US" or (arr.dtype.kind == "O" and arr.size and isinstance(arr.flat[0], str)):
        return "string"
    if arr.dtype.kind in "iub":
        if arr.ndim == 1:
            return "int"
        arr = arr.astype(np.float32)
    if arr.dtype.kind == "f":
        t = _FLOAT_SHAPES.get(arr.shape[1:])
        if t:
            return t
    raise invalid(
        f"{cls} attribute {name!r}: cannot tell the type of values of dtype {arr.dtype} and shape {arr.shape}; pass type="
    )
