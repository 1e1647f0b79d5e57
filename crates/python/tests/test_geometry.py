"""Geometry as numpy: every attribute type of every class round-trips Python -> geode -> numpy, numeric columns are read without copying, and geometry made in Python cooks inside a network."""

import numpy as np
import pytest

import geode
from conftest import oracle

rng = np.random.default_rng(7)

# A quad and a triangle sharing an edge, and an open polyline: 6 points, 9 vertices, 3 prims.
POINTS = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0.5, 0], [3, 3, 3]], dtype=np.float32)
QUAD_TRI = [[0, 1, 2, 3], [1, 4, 2]]
LINE = [[3, 5]]


def base() -> geode.Geometry:
    return geode.Geometry.from_arrays(POINTS, polygons=QUAD_TRI, polylines=LINE)


def values(type_: str, n: int):
    """n values of an attribute type, as Python hands them in."""
    shapes = {"float": (n,), "vector2": (n, 2), "vector3": (n, 3), "vector4": (n, 4), "quaternion": (n, 4), "matrix3": (n, 3, 3), "matrix4": (n, 4, 4)}
    if type_ in shapes:
        return rng.standard_normal(shapes[type_]).astype(np.float32)
    if type_ == "int":
        return rng.integers(-1000, 1000, n).astype(np.int32)
    if type_ == "string":
        return np.array([f"piece_{i % 3}" for i in range(n)], dtype=object)
    if type_ == "int array":
        return [list(range(i)) for i in range(n)]
    if type_ == "float array":
        return [[0.5 * j for j in range(i + 1)] for i in range(n)]
    if type_ == "string array":
        return [[f"tag{j}" for j in range(i % 3)] for i in range(n)]
    if type_ == "vector3 array":
        return [rng.standard_normal((i, 3)).astype(np.float32) for i in range(n)]
    raise AssertionError(type_)


TYPES = ["float", "int", "vector2", "vector3", "vector4", "quaternion", "matrix3", "matrix4", "string", "int array", "float array", "vector3 array", "string array"]
COUNTS = {"point": 6, "vertex": 9, "prim": 3}
INFERRED = {"float", "int", "vector2", "vector3", "vector4", "matrix3", "matrix4", "string"}


def same(a, b):
    if isinstance(b, list) or (isinstance(b, np.ndarray) and b.dtype == object):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            if isinstance(y, str) or (isinstance(y, list) and (not y or isinstance(y[0], str))):
                assert list(x) == list(y) if isinstance(y, list) else x == y
            else:
                np.testing.assert_array_equal(np.asarray(x, dtype=np.float32).reshape(-1), np.asarray(y, dtype=np.float32).reshape(-1))
    else:
        np.testing.assert_array_equal(a, b)


def through_a_network(geo: geode.Geometry) -> geode.Geometry:
    """Feeds geo into a network (python_input -> null) and cooks it back out."""
    net = geode.Network()
    src = net.create_node("python_input", "src", params={"geometry": geo})
    out = net.create_node("null", "out").set_input(0, src)
    return net.cook(out)


@pytest.mark.parametrize("cls", ["point", "vertex", "prim"])
@pytest.mark.parametrize("type_", TYPES)
def test_every_attribute_type_of_every_class_round_trips(cls, type_):
    v = values(type_, COUNTS[cls])
    named = None if type_ in INFERRED else type_
    geo = base().set_attrib(cls, "a", v, type=named)
    back = through_a_network(geo)
    assert back.content_hash == geo.content_hash
    table = {"point": back.points, "vertex": back.vertices, "prim": back.prims}[cls]
    assert table.type("a")[0] == type_
    same(table["a"], v)


@pytest.mark.parametrize("type_", TYPES)
def test_every_attribute_type_round_trips_as_a_detail_value(type_):
    v = values(type_, 1)[0]
    geo = base().set_attrib("detail", "d", v, type=None if type_ in INFERRED else type_)
    back = through_a_network(geo)
    assert back.detail.type("d")[0] == type_
    same([back.detail["d"]], [v])


def test_numeric_columns_are_read_only_views_of_the_geometrys_memory():
    net = geode.Network()
    grid = net.create_node("grid", "g", params={"rows": 200, "columns": 300})
    geo = net.cook(grid)
    P = geo.points["P"]
    assert P.shape == (geo.num_points, 3) and geo.num_points > 60000 and P.dtype == np.float32
    assert P.base is geo  # the array keeps the geometry alive, and nothing else
    again = geo.points["P"]
    assert again.__array_interface__["data"][0] == P.__array_interface__["data"][0]
    assert not P.flags.writeable and not P.flags.owndata
    with pytest.raises(ValueError):
        P[0, 0] = 1.0
    # A cache hit hands back the very same memory.
    assert net.cook(grid).points["P"].__array_interface__["data"][0] == P.__array_interface__["data"][0]
    # The view outlives every Python name for the geometry.
    first = P[0].copy()
    del geo, again
    import gc

    gc.collect()
    np.testing.assert_array_equal(P[0], first)
    off, pts = net.cook(grid).prim_offsets, net.cook(grid).prim_points
    assert off.dtype == np.uint32 and off[0] == 0 and off[-1] == len(pts)


def test_writes_make_a_new_geometry_and_leave_the_old_unchanged():
    geo = base()
    P = geo.points["P"]
    moved = geo.set_attrib("point", "P", P + np.float32(1))
    np.testing.assert_array_equal(geo.points["P"], POINTS)
    np.testing.assert_array_equal(moved.points["P"], POINTS + 1)
    assert moved.content_hash != geo.content_hash
    assert moved.points.type("P") == ("vector3", "position")
    with pytest.raises(ValueError, match="needs 6 values"):
        geo.set_attrib("point", "w", np.zeros(5, dtype=np.float32))
    with pytest.raises(ValueError, match="type="):
        geo.set_attrib("point", "w", np.zeros((6, 5), dtype=np.float32))
    assert "w" not in geo.points
    assert "Cd" not in geo.remove_attrib("point", "Cd").points if "Cd" in geo.points else True


def test_connectivity_and_groups_read_as_arrays():
    geo = base()
    np.testing.assert_array_equal(geo.prim_offsets, [0, 4, 7, 9])
    np.testing.assert_array_equal(geo.prim_points, [0, 1, 2, 3, 1, 4, 2, 3, 5])
    assert geo.prim_types == ["polygon", "polygon", "polyline"]
    assert [list(p) for p in geo.prim_point_lists()] == [[0, 1, 2, 3], [1, 4, 2], [3, 5]]
    mask = np.array([True, False, True, False, False, True])
    g = geo.set_group("point", "picked", mask).set_group("prim", "faces", [True, True, False])
    back = through_a_network(g)
    np.testing.assert_array_equal(back.point_groups["picked"], mask)
    np.testing.assert_array_equal(back.prim_groups["faces"], [True, True, False])
    # A group drives a node: delete the picked points, as Houdini's Blast would.
    net = geode.Network()
    src = net.create_node("python_input", "src", params={"geometry": g})
    blast = net.create_node("delete", "d", params={"group": "picked", "class": "point"}).set_input(0, src)
    assert net.cook(blast).num_points == 3


def test_python_geometry_cooks_downstream_and_is_keyed_by_its_content():
    net = geode.Network()
    src = net.create_node("python_input", "src", params={"geometry": base()})
    up = net.create_node("transform", "up", params={"translate": [0, 2, 0]}).set_input(0, src)
    np.testing.assert_array_equal(net.cook(up).points["P"], POINTS + np.float32([0, 2, 0]))
    other = base().set_attrib("point", "P", POINTS * 2)
    src.parm("geometry").set(other)
    np.testing.assert_array_equal(net.cook(up).points["P"], POINTS * 2 + np.float32([0, 2, 0]))
    assert src.parm("geometry").raw == other.content_hash
    # The file names the geometry by hash; a network naming one this process
    # does not hold says so (a hash no cook has seen, so no cache answers).
    text = net.to_json().replace(other.content_hash, "0123456789abcdef0123456789abcdef")
    loose = geode.Network.from_json(text)
    with pytest.raises(geode.CookError) as e:
        loose.cook("up")
    assert (e.value.kind, e.value.path, e.value.param) == ("parameter", "/src", "geometry")
    assert "held by this process" in e.value.message


def test_to_trimesh_is_watertight_with_the_analytic_volume():
    trimesh = oracle("trimesh")
    net = geode.Network()
    box = net.create_node("box", "b", params={"size": [1, 2, 3]})
    mesh = net.cook(box).to_trimesh()
    assert isinstance(mesh, trimesh.Trimesh)
    assert mesh.is_watertight
    assert abs(mesh.volume) == pytest.approx(6.0)


@pytest.mark.parametrize("ext", [".obj", ".stl", ".ply", ".glb", ".usda", ".geo", ".bgeo"])
def test_save_writes_every_format_geode_writes(tmp_path, ext):
    net = geode.Network()
    box = net.create_node("box", "b", params={"size": [1, 2, 3]})
    geo = net.cook(box)
    path = tmp_path / f"box{ext}"
    geo.save(path)
    assert path.stat().st_size > 0
    if ext == ".usda":
        # geode writes USD but does not read it: Pixar's usd-core reads it back.
        oracle("pxr")
        from pxr import Usd, UsdGeom

        stage = Usd.Stage.Open(str(path))
        meshes = [p for p in stage.Traverse() if p.IsA(UsdGeom.Mesh)]
        P = np.array(UsdGeom.Mesh(meshes[0]).GetPointsAttr().Get(), dtype=np.float32)
    else:
        P = geode.Geometry.load(path).points["P"]
    lo, hi = P.min(axis=0), P.max(axis=0)
    np.testing.assert_allclose(hi - lo, [1, 2, 3], atol=1e-6)
    with pytest.raises(geode.FileError):
        geo.save(tmp_path / "box.nope")


def test_a_geometry_and_a_network_draw_themselves_for_jupyter():
    Image = oracle("PIL.Image")
    import io

    net = geode.Network()
    s = net.create_node("sphere", "s", params={"radius": 1, "rows": 48, "columns": 96})
    net.output = s
    png = net.cook()._repr_png_()
    image = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)
    assert image.shape == (320, 320, 3)
    background = image[0, 0]
    np.testing.assert_array_equal(background, [43, 43, 43])
    covered = np.any(image != background, axis=2)
    # A unit sphere fills 0.45 of the half-width: a disc of pi * 144^2 pixels.
    assert covered.mean() == pytest.approx(np.pi * 144**2 / 320**2, rel=0.03)
    assert covered[160, 160] and image[160, 160].sum() > 3 * 120  # lit, not background
    # Polylines are drawn too, and a point cloud as points.
    curve = geode.Geometry.from_arrays([[0, 0, 0], [1, 1, 1], [2, 0, 2]], polylines=[[0, 1, 2]])
    lines = np.asarray(Image.open(io.BytesIO(curve.png(64))).convert("RGB"))
    assert lines.shape == (64, 64, 3) and (lines != lines[0, 0]).any()
    cloud = geode.Geometry.from_arrays(np.random.default_rng(3).random((500, 3)))
    assert (np.asarray(Image.open(io.BytesIO(cloud.png(64))).convert("RGB")) != 43).any()
    with pytest.raises(ValueError):
        cloud.png(5)
    graph = net._repr_svg_()
    assert graph.startswith("<svg") and ">s<" in graph and ">sphere<" in graph


def test_attributes_from_python_carry_the_tags_transforms_read():
    n = len(POINTS)
    up = np.tile(np.float32([0, 1, 0]), (n, 1))
    geo = base().set_attrib("point", "N", up).set_attrib("point", "v", up).set_attrib("point", "rest", up)
    geo = geo.set_attrib("point", "tint", up, type_info="color")
    assert geo.points.type("N") == ("vector3", "normal")
    assert geo.points.type("v") == ("vector3", "vector")
    assert geo.points.type("rest") == ("vector3", "none")
    assert geo.points.type("tint") == ("vector3", "color")
    # Replacing an attribute keeps its tag; a tag the type cannot carry is refused.
    assert geo.set_attrib("point", "tint", up * 2).points.type("tint") == ("vector3", "color")
    with pytest.raises(geode.InvalidValueError, match="cannot be a normal"):
        geo.set_attrib("point", "w", np.zeros(n, dtype=np.float32), type_info="normal")
    # Rotated 90 degrees about X, as Houdini's Transform does: a normal and a
    # vector turn (Y to Z), a colour and an untagged vector do not.
    net = geode.Network()
    src = net.create_node("python_input", "src", params={"geometry": geo})
    turn = net.create_node("transform", "t", params={"rotate": [90, 0, 0]}).set_input(0, src)
    out = net.cook(turn)
    np.testing.assert_allclose(out.points["N"], np.tile([0, 0, 1], (n, 1)), atol=1e-6)
    np.testing.assert_allclose(out.points["v"], np.tile([0, 0, 1], (n, 1)), atol=1e-6)
    np.testing.assert_allclose(out.points["rest"], up)
    np.testing.assert_allclose(out.points["tint"], up)


def test_arrays_geode_cannot_take_as_they_are_are_refused_not_reinterpreted():
    for bad in (np.arange(12.0).reshape(3, 4), np.zeros((3, 2)), np.zeros(9)):
        with pytest.raises(geode.InvalidValueError, match=r"\(n, 3\)") as e:
            geode.Geometry.from_arrays(bad)
        assert isinstance(e.value, ValueError) and e.value.kind == "value"
    with pytest.raises(geode.InvalidValueError, match="integers"):
        geode.Geometry.from_arrays(POINTS, polygons=[[0, 1, 2.7]])
    with pytest.raises(geode.InvalidValueError, match="0 or more"):
        geode.Geometry.from_arrays(POINTS, polygons=[[0, 1, -2]])
    with pytest.raises(geode.GeodeError, match="out of range|6 points"):
        geode.Geometry.from_arrays(POINTS, polygons=[[0, 1, 60]])
    with pytest.raises(geode.InvalidValueError, match="32-bit"):
        base().set_attrib("point", "id", np.array([2**40] * 6))
    with pytest.raises(geode.InvalidValueError, match="whole numbers"):
        base().set_attrib("point", "ids", [[1.5]] * 6, type="int array")
    with pytest.raises(geode.InvalidValueError, match="not an attribute type"):
        base().set_attrib("point", "id", [1] * 6, type="intarray")
    # Every spelling of a class the reading side takes, the writing side takes too.
    assert "w" in base().set_attrib("primitive", "w", np.zeros(3, dtype=np.float32)).prims
    with pytest.raises(geode.NotFoundError) as e:
        base().points["nope"]
    assert e.value.kind == "attribute" and "nope" in str(e.value)


def test_the_picture_is_the_same_on_any_thread_count():
    import hashlib
    import os
    import subprocess
    import sys

    # Enough primitives for several workers' runs, which must merge to the
    # same picture: two interpenetrating coloured spheres (depth ties where
    # they meet).
    script = (
        "import geode, hashlib\n"
        "net = geode.Network()\n"
        "a = net.create_node('sphere', 'a', params={'rows': 120, 'columns': 240})\n"
        "b = net.create_node('transform', 'b', params={'translate': [0.5, 0, 0]}).set_input(0, a)\n"
        "m = net.create_node('merge', 'm').set_inputs([a, b])\n"
        "c = net.create_node('wrangle', 'c', params={'snippet': '@Cd = set(rand(@ptnum), 0.5, rand(@ptnum + 7));'}).set_input(0, m)\n"
        "print(hashlib.sha256(net.cook(c).png(256)).hexdigest())\n"
    )
    digests = {
        threads: subprocess.run(
            [sys.executable, "-c", script],
            env=dict(os.environ, RAYON_NUM_THREADS=str(threads)),
            capture_output=True,
            text=True,
            check=True,
        ).stdout
        for threads in (1, 2, 3)
    }
    assert len(set(digests.values())) == 1, digests


def test_the_picture_looks_down_on_the_geometry_as_houdini_does():
    Image = oracle("PIL.Image")
    import io

    net = geode.Network()
    g = net.cook(net.create_node("box", "b"))
    P, off, pts = g.points["P"], g.prim_offsets, g.prim_points
    heights = [P[pts[off[i] : off[i + 1]]].mean(axis=0)[1] for i in range(g.num_prims)]
    # The top face red, the bottom blue, the sides grey.
    cd = [[1, 0, 0] if h > 0.4 else [0, 0, 1] if h < -0.4 else [0.5, 0.5, 0.5] for h in heights]
    image = np.asarray(Image.open(io.BytesIO(g.set_attrib("prim", "Cd", np.float32(cd)).png(128))).convert("RGB")).astype(int)
    red = (image[:, :, 0] > image[:, :, 2] + 30).sum()
    blue = (image[:, :, 2] > image[:, :, 0] + 30).sum()
    assert red > 500 and blue == 0, (red, blue)
