"""Networks built from Python: equal to the same network loaded from its file, edited with keys, spare parameters, subnets and blocks, saved atomically."""

import json

import pytest

import geode


def build_shatter() -> geode.Network:
    """examples/shatter_for_each.json, built node by node as a script would."""
    net = geode.Network()
    ball = net.create_node("sphere", "ball", params={"radius": 1, "rows": 32, "columns": 64})
    line = net.create_node("curve_line", "line", params={"points": 3})
    pts = net.create_node("wrangle", "slab_points", params={"snippet": "@P = set(@ptnum * 0.7 - 0.7, 0, 0);"})
    pts.set_input(0, line)
    slab = net.create_node("box", "slab")
    slab.parm("size").set([0.3, 3, 3])
    slabs = net.create_node("copy_to_points", "slabs", params={"pack": False}).set_inputs([slab, pts])
    shattered = net.create_node("boolean", "shattered", params={"operation": "shatter"})
    shattered.set_inputs([ball, slabs])
    moved = net.create_node("for_each", "moved")
    moved.set_input(0, shattered)
    # A new block passes its piece through a `null` named output, as in the studio.
    assert [n.name for n in moved.children] == ["output"]
    moved.node("output").destroy()
    volume = moved.create_node("measure", "volume", params={"measure": "volume", "accumulate": "total"})
    volume.set_input(0, "@0")
    push = moved.create_node("wrangle", "push")
    push.set_inputs([volume, "@meta"])
    push.parm("snippet").set(
        'vector c = getbbox_center(0);\nf@piece_volume = detail(0, "volume");\n'
        'i@piece = detail(1, "iteration");\n@P += normalize(c) * f@piece_volume * 3;'
    )
    moved.output = push
    net.output = moved
    return net


def test_a_network_built_in_python_equals_the_same_network_loaded_from_json(examples):
    built = build_shatter()
    loaded = geode.Network.load(examples / "shatter_for_each.json")
    assert built == loaded
    assert json.loads(built.to_json()) == json.loads(loaded.to_json())
    a, b = built.cook(), loaded.cook()
    assert a.content_hash == b.content_hash
    assert a.num_prims > 0
    # The for_each moved pieces apart: the result is not the shattered ball.
    assert a.content_hash != built.cook("shattered").content_hash


def test_nodes_are_found_by_path_and_know_their_wires():
    net = build_shatter()
    push = net.node("/moved/push")
    assert push.type == "wrangle"
    assert push.parent == net.node("moved")
    assert push.inputs == [net.node("/moved/volume"), "@meta"]
    assert [n.name for n in net.node("moved").children] == ["push", "volume"]
    assert net.output == net.node("moved")
    with pytest.raises(KeyError):
        net.node("/nope")
    with pytest.raises(geode.NotFoundError) as e:
        net.node("nope")
    assert (e.value.kind, e.value.path) == ("node", "/nope")
    assert "ball" in e.value.message  # the nodes that are there
    with pytest.raises(geode.NotFoundError) as e:
        push.parm("snipet")
    assert (e.value.kind, e.value.path, e.value.param) == ("parameter", "/moved/push", "snipet")
    assert "snippet" in e.value.message
    assert isinstance(e.value, geode.GeodeError) and isinstance(e.value, KeyError)
    with pytest.raises(geode.NotFoundError, match="no point attribute `Cd`"):
        net.cook().points["Cd"]


def test_keyframes_are_channels_the_cook_evaluates_at_each_frame():
    net = geode.Network()
    box = net.create_node("box", "b")
    xf = net.create_node("transform", "t").set_input(0, box)
    xf.parm("translate").set_keys([(1, [0, 0, 0]), (25, [2, 4, 0])])
    xf.parm("uniform_scale").set_keys([{"frame": 1, "value": 1}, {"frame": 11, "value": 3, "interp": "linear"}])
    net.output = xf
    # Linear keys: halfway between frames 1 and 25 is frame 13.
    assert xf.parm("translate").eval(13) == pytest.approx((1.0, 2.0, 0.0))
    assert xf.parm("uniform_scale").eval(6) == pytest.approx(2.0)
    raw = xf.parm("translate").raw
    assert raw[0]["keys"] == [{"frame": 1.0, "value": 0.0}, {"frame": 25.0, "value": 2.0}]
    # The same keys written as a file give the same cook.
    text = {
        "geode": "network",
        "version": 1,
        "output": "t",
        "nodes": {
            "b": {"type": "box"},
            "t": {
                "type": "transform",
                "inputs": ["b"],
                "params": {
                    "translate": [
                        {"keys": [{"frame": 1, "value": 0}, {"frame": 25, "value": 2}]},
                        {"keys": [{"frame": 1, "value": 0}, {"frame": 25, "value": 4}]},
                        {"keys": [{"frame": 1, "value": 0}, {"frame": 25, "value": 0}]},
                    ],
                    "uniform_scale": {"keys": [{"frame": 1, "value": 1}, {"frame": 11, "value": 3, "interp": "linear"}]},
                },
            },
        },
    }
    from_file = geode.Network.from_json(json.dumps(text))
    for frame in (1, 6, 13, 30):
        assert net.cook(frame=frame).content_hash == from_file.cook(frame=frame).content_hash
    P = net.cook(frame=13).points["P"]
    # The unit box scaled by 3 (frame 13 is past the scale's last key) and moved by (1, 2, 0).
    assert P.min(axis=0) == pytest.approx([1 - 1.5, 2 - 1.5, -1.5])
    # One key at a time, as the studio's timeline does.
    xf.parm("translate").set_key(40, 10.0, component=0)
    assert xf.parm("translate").eval(40)[0] == pytest.approx(10.0)
    xf.parm("translate").delete_key(40, component=0)
    assert xf.parm("translate").eval(40)[0] == pytest.approx(2.0)


def test_spare_parameters_of_a_block_are_read_by_the_wrangles_inside():
    # As geode's own block test: a loop of 2 iterations lifting by ch("../lift").
    net = geode.Network()
    grid = net.create_node("grid", "g", params={"rows": 2, "columns": 2})
    loop = net.create_node("loop", "l", params={"iterations": 2}).set_input(0, grid)
    lift = loop.add_spare("lift", "float")
    lift.set_keys([(1, 0.25), (5, 1.0)])
    step = loop.create_node("wrangle", "step", params={"snippet": '@P.y += ch("../lift");'})
    step.set_input(0, "@0")
    loop.output = step
    g = net.cook(loop)
    assert g.points["P"][0][1] == pytest.approx(0.5)
    assert g.points["P"][:, 1] == pytest.approx([0.5] * g.num_points)
    assert net.cook(loop, frame=5).points["P"][0][1] == pytest.approx(2.0)
    loop.remove_spare("lift")
    with pytest.raises(geode.CookError) as e:
        net.cook(loop)
    assert (e.value.path, e.value.param) == ("/l/step", "snippet")
    assert "no parameter '../lift'" in e.value.message


def test_a_subnet_cooks_its_inner_output_and_flags_and_renames_hold():
    net = geode.Network()
    box = net.create_node("box", "b")
    sub = net.create_node("subnet", "s").set_input(0, box)
    sub.node("output").destroy()
    inner = sub.create_node("transform", "up", params={"translate": [0, 5, 0]})
    inner.set_input(0, "@0")
    sub.output = inner
    net.output = sub
    assert net.cook().points["P"][:, 1].min() == pytest.approx(4.5)
    inner.bypass = True
    assert inner.bypass
    assert net.cook().points["P"][:, 1].min() == pytest.approx(-0.5)
    inner.bypass = False
    inner.rename("raise_it")
    assert inner.path == "/s/raise_it"
    assert sub.output == inner
    assert net.cook().points["P"][:, 1].min() == pytest.approx(4.5)
    inner.destroy()
    assert sub.children == []


def test_save_writes_the_document_atomically_and_load_reads_it_back(tmp_path):
    net = build_shatter()
    path = tmp_path / "shatter.json"
    net.save(path)
    assert path.read_text() == net.to_json()
    assert net.path == str(path)
    again = geode.Network.load(path)
    assert again == net
    # Saving again goes to the same file, and leaves no temporary file beside it.
    net.node("ball").parm("radius").set(2)
    net.save()
    assert geode.Network.load(path).node("ball").parm("radius").raw == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == ["shatter.json"]


def test_a_copy_keeps_hip_and_geometry_and_edits_apart(tmp_path):
    import numpy as np

    folder = tmp_path / "shot"
    folder.mkdir()
    geode.Geometry.from_arrays(np.eye(3, dtype=np.float32), polygons=[[0, 1, 2]]).save(folder / "tri.bgeo")
    net = geode.Network()
    f = net.create_node("file", "in", params={"file": "$HIP/tri.bgeo"})
    net.output = f
    net.save(folder / "shot.json")
    copy = net.copy()
    assert copy == net and copy.path == net.path
    assert copy.cook().num_points == 3  # $HIP is still the shot's folder
    copy.node("in").parm("file").set("$HIP/other.bgeo")
    assert net.node("in").parm("file").raw == "$HIP/tri.bgeo"
    # Python geometry goes with a copy, and with a network read back from
    # its file while the geometry lives, before any cook could cache it.
    fresh = geode.Geometry.from_arrays(np.random.default_rng(11).random((4, 3)), polygons=[[0, 1, 2, 3]])
    fed = geode.Network()
    fed.output = fed.create_node("python_input", "src", params={"geometry": fresh})
    assert fed.copy().cook().content_hash == fresh.content_hash
    assert geode.Network.from_json(fed.to_json()).cook().content_hash == fresh.content_hash


def test_the_output_is_the_named_node_else_the_display_flag():
    net = geode.Network()
    a = net.create_node("box", "a")
    b = net.create_node("sphere", "b")
    assert net.output is None
    b.display = True
    assert net.output == b
    # Naming the output moves the display flag to it, as the two are one in Houdini.
    net.output = a
    assert net.output == a and a.display and not b.display and net.cook().num_points == 8
    net.output = None
    assert net.output == a  # the display flag still says so
    b.display = True
    assert net.output == b and net.cook().num_points == net.cook(b).num_points
    other = geode.Network()
    with pytest.raises(geode.EditError, match="another network"):
        net.output = other.create_node("box", "a")
    with pytest.raises(geode.EditError, match="another network"):
        net.cook(other.node("a"))
    with pytest.raises(TypeError):
        net.output = 5


def test_parameters_and_node_types_describe_themselves_as_the_studio_reads_them():
    box = geode.node_type("box")
    assert box["category"] and box["output"] == "geometry"
    size = next(p for p in box["params"] if p["name"] == "size")
    assert (size["type"], size["default"], size["min"]) == ("vec3", [1.0, 1.0, 1.0], 0.0)
    net = geode.Network()
    normals = net.create_node("normals", "n")
    menu = normals.parm("class").template
    assert menu["type"] == "menu" and menu["default"] in menu["items"]
    # The template says what the parameter takes; a value outside it is refused.
    with pytest.raises(geode.LoadError) as e:
        normals.parm("class").set("edge")
    assert e.value.param == "class" and all(item in e.value.message for item in menu["items"])
    w = net.create_node("wrangle", "w")
    w.add_spare("amp", "float")
    assert w.parm("amp").template["spare"] is True
    assert [name for name, _, _ in geode.node_types()] == sorted(name for name, _, _ in geode.node_types())
    with pytest.raises(geode.NotFoundError, match="did you mean box"):
        geode.node_type("bxo")
