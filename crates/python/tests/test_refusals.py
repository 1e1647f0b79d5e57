"""What a second new user tried: data geode cannot take as given is refused with a geode error naming it, never truncated, wrapped or replaced; a refused batch of edits changes nothing."""

import os
import subprocess
import sys

import numpy as np
import pytest

import geode

P = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=np.float32)
FA = geode.Geometry.from_arrays


@pytest.mark.parametrize(
    "call",
    [
        lambda: FA(P, polygons=np.array([[0, 1, 2**32 + 1]], np.int64)),  # would wrap to 1
        lambda: FA(P, polygons=np.zeros((1, 3, 1), int)),  # not a list of primitives
        lambda: FA(P, point_attribs={"P": np.zeros((4, 3))}),  # would replace points=
        lambda: FA(P.astype(complex)),  # would drop the imaginary part
        lambda: FA([["a", "b", "c"]]),
        lambda: FA(P).set_attrib("point", "w", [[1, 2], ["x"], [], []], type="float array"),
        lambda: FA(P).set_group("point", "g", np.array([0.0, 1.0, 0.5, 1.0])),  # 0.5 is no flag
        lambda: FA(P).set_attrib("point", "my attr", np.zeros(4, np.float32)),
        lambda: FA(P).set_group("point", "1top", [True] * 4),
        lambda: FA(P).set_attrib("point", "name", [1, 2, 3, 4], type="string"),
    ],
)
def test_data_geode_cannot_take_as_given_is_refused(call):
    with pytest.raises(geode.InvalidValueError) as e:
        call()
    assert e.value.kind == "value" and e.value.message


def test_text_and_flat_arrays_come_in_as_a_user_means_them():
    g = FA(P, point_attribs={"name": np.array([b"a", b"b", b"c", b"d"])})
    assert list(g.points["name"]) == ["a", "b", "c", "d"]
    flat = geode.Geometry.from_prims(P.tolist(), np.array([0, 1, 2, 3], np.int64), [4], [True])
    assert flat.prim_types == ["polygon"] and list(flat.prim_points) == [0, 1, 2, 3]
    assert list(FA(P).set_group("point", "g", [0, 1, 1, 0]).point_groups["g"]) == [False, True, True, False]


def test_a_quaternion_is_turned_by_a_transform_whatever_its_name():
    g = FA(P).set_attrib("point", "spin", np.tile(np.float32([0, 0, 0, 1]), (4, 1)), type="quaternion")
    assert g.points.type("spin") == ("quaternion", "quaternion")
    net = geode.Network()
    src = net.create_node("python_input", "src", params={"geometry": g})
    t = net.create_node("transform", "t", params={"rotate": [0, 90, 0]}).set_input(0, src)
    half = np.sqrt(0.5)
    np.testing.assert_allclose(net.cook(t).points["spin"][0], [0, half, 0, half], atol=1e-6)
    with pytest.raises(geode.InvalidValueError, match="cannot be a transform"):
        FA(P).set_attrib("point", "m", np.zeros((4, 3, 3), np.float32), type_info="transform")


def test_a_refused_parameter_edit_leaves_everything_as_it_was():
    net = geode.Network()
    b = net.create_node("box", "b")
    with pytest.raises(geode.LoadError):
        b.set_params({"size": [2, 2, 2], "divisions": "x"})
    assert b.parm("size").raw is None  # all or nothing
    with pytest.raises(geode.InvalidValueError) as e:
        b.parm("size").set([float("nan"), 1, 1])
    assert (e.value.path, e.value.param) == ("/b", "size")
    n = net.create_node("normals", "n")
    with pytest.raises(geode.InvalidValueError):
        n.parm("cusp_angle").set_expression("$F", component=2)
    with pytest.raises(geode.EditError, match="cannot be animated"):
        n.parm("class").set_expression("$F")
    with pytest.raises(geode.EditError, match="cannot be animated"):
        n.parm("class").set_keys([(1, 0), (2, 1)])
    with pytest.raises(geode.InvalidValueError):
        b.parm("size").set_key(1, "point")
    with pytest.raises(geode.InvalidValueError):
        net.cook(b, frame=float("nan"))
    with pytest.raises(geode.InvalidValueError):
        b.set_input(-1, None)


def test_files_are_refused_as_the_file_node_refuses_them(tmp_path):
    obj = tmp_path / "big.obj"
    net = geode.Network()
    net.cook(net.create_node("grid", "g", params={"rows": 300, "columns": 300})).save(obj)
    script = (
        "import geode\n"
        "try:\n"
        f"    geode.Geometry.load({str(obj)!r})\n"
        "except geode.FileError as e:\n"
        "    print(e.kind)\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", script],
        env=dict(os.environ, GEODE_MEMORY_MB="1"),
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    assert out.strip() == "resource"
    with pytest.raises(geode.FileError) as e:
        net.save("/proc/geode-test.json")
    assert "no file can be made in /proc" in e.value.message
