"""Every failure reaches Python as an exception of its kind, carrying kind, node path, parameter and message."""

import json

import pytest

import geode


def test_an_unknown_node_type_is_an_edit_error_that_names_a_near_type():
    net = geode.Network()
    with pytest.raises(geode.EditError) as e:
        net.create_node("bxo", "b")
    assert e.value.kind == "edit"
    assert "bxo" in e.value.message and "box" in e.value.message
    assert isinstance(e.value, geode.GeodeError)


def test_a_value_a_parameter_cannot_take_is_refused_and_the_old_one_kept():
    net = geode.Network()
    box = net.create_node("box", "b", params={"size": [1, 2, 3]})
    with pytest.raises(geode.LoadError) as e:
        box.parm("size").set("not a vector")
    err = e.value
    assert (err.kind, err.path, err.param) == ("parameter", "/b", "size")
    assert "vector3" in err.message
    assert err.errors == [{"kind": "parameter", "path": "/b", "param": "size", "message": err.message}]
    assert box.parm("size").raw == [1, 2, 3]
    # A bad value given at creation undoes the whole creation.
    with pytest.raises(geode.LoadError):
        net.create_node("sphere", "s", params={"radius": [1, 2]})
    assert [n.name for n in net.nodes] == ["b"]
    with pytest.raises(ValueError, match="finite"):
        box.parm("size").set([float("nan"), 1, 1])


def test_an_unknown_parameter_a_cycle_and_a_wrong_port_are_edit_errors():
    net = geode.Network()
    a = net.create_node("box", "a")
    t = net.create_node("transform", "t").set_input(0, a)
    u = net.create_node("transform", "u").set_input(0, t)
    with pytest.raises(geode.EditError) as e:
        net.create_node("box", "b", params={"sizee": 1})
    assert e.value.path == "/b" and "sizee" in e.value.message
    assert [n.name for n in net.nodes] == ["a", "t", "u"]
    with pytest.raises(geode.EditError) as e:
        t.set_input(0, u)
    assert e.value.path == "/t" and "cycle" in e.value.message
    with pytest.raises(geode.EditError) as e:
        a.set_input(0, t)
    assert "has no input 1" in e.value.message
    f = net.create_node("frep_sphere", "f")
    with pytest.raises(geode.EditError) as e:
        t.set_input(0, f)
    assert e.value.path == "/t" and "field" in e.value.message


def test_a_failed_cook_is_a_cook_error_of_its_kind(tmp_path):
    net = geode.Network()
    f = net.create_node("file", "in", params={"file": str(tmp_path / "missing.obj")})
    with pytest.raises(geode.CookError) as e:
        net.cook(f)
    assert (e.value.kind, e.value.path, e.value.param) == ("io", "/in", "file")
    assert "missing.obj" in str(e.value)
    w = net.create_node("wrangle", "w", params={"snippet": "@P.y += ;"})
    w.set_input(0, net.create_node("grid", "g"))
    with pytest.raises(geode.GeodeError) as e:
        net.cook(w)
    assert e.value.path == "/w" and e.value.param == "snippet"
    with pytest.raises(geode.GeodeError) as e:
        net.cook()
    assert "output" in e.value.message
    with pytest.raises(geode.GeodeError) as e:
        net.cook("nothere")
    assert e.value.path == "/nothere"


def test_a_broken_file_is_a_load_error_naming_line_node_and_parameter(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"geode": "network", "version": 1, "nodes": {"b": {"type": "box", "params": {"size": 1e999}}}}')
    with pytest.raises(geode.LoadError) as e:
        geode.Network.load(bad)
    assert (e.value.path, e.value.param) == ("/b", "size")
    assert "line 1" in e.value.message
    with pytest.raises(geode.FileError) as e:
        geode.Network.load(tmp_path / "none.json")
    assert e.value.kind == "io"
    doc = {"geode": "network", "version": 1, "nodes": {"b": {"type": "box", "params": {"size": "x"}}, "c": {"type": "nope"}}}
    with pytest.raises(geode.LoadError) as e:
        geode.Network.from_json(json.dumps(doc))
    assert {(x["path"], x["param"]) for x in e.value.errors} == {("/b", "size"), ("/c", None)}
    loose = geode.Network.from_json(json.dumps(doc), strict=False)
    assert len(loose.problems()) == 2


def test_parameter_values_too_deep_or_of_no_json_kind_are_refused():
    net = geode.Network()
    b = net.create_node("box", "b")
    deep: list = []
    for _ in range(100):
        deep = [deep]
    with pytest.raises(ValueError, match="deeper"):
        b.parm("size").set(deep)
    with pytest.raises(ValueError):
        b.parm("size").set(object())


def test_mistakes_found_by_a_new_user_are_errors_that_say_what_to_fix(tmp_path):
    net = geode.Network()
    box = net.create_node("box", "b")
    t = net.create_node("transform", "t").set_input(0, box)
    # An unknown parameter given at creation names it and the nearest one.
    with pytest.raises(geode.EditError) as e:
        net.create_node("box", "c", params={"sise": [1, 1, 1]})
    assert (e.value.path, e.value.param) == ("/c", "sise")
    assert "did you mean `size`?" in e.value.message
    # A node of another network is not wired by its name into this one.
    other = geode.Network()
    with pytest.raises(geode.EditError, match="another network"):
        t.set_input(0, other.create_node("box", "b"))
    with pytest.raises(TypeError):
        t.set_input(0, 3)
    # Spare parameters: removing one that is not there says so, and never
    # drops a parameter of the node's own.
    w = net.create_node("wrangle", "w", params={"snippet": "@P.y += 1;"})
    for name in ("nope", "snippet"):
        with pytest.raises(geode.EditError) as e:
            w.remove_spare(name)
        assert (e.value.path, e.value.param) == ("/w", name)
    assert w.parm("snippet").raw == "@P.y += 1;"
    # Keys need numbers; a menu parameter has none to key.
    with pytest.raises(geode.GeodeError) as e:
        net.create_node("normals", "n").parm("class").set_keys([(1, "point")])
    assert e.value.param == "class"
    with pytest.raises(geode.InvalidValueError):
        t.parm("translate").set_expression("$F", component=3)
    with pytest.raises(TypeError):
        net.cook(t, frame="12")
    with pytest.raises(geode.NotFoundError) as e:
        net.cook("nope")
    assert (e.value.kind, e.value.path) == ("node", "/nope") and isinstance(e.value, KeyError)
    # A save into a folder that is not there names the folder, not a temporary file.
    with pytest.raises(geode.FileError) as e:
        net.cook(box).save(tmp_path / "missing" / "box.obj")
    assert "missing" in e.value.message and "does not exist" in e.value.message
    assert ".geode-tmp" not in str(e.value)
    assert str(e.value).count(str(tmp_path / "missing" / "box.obj")) == 1


def test_a_file_over_the_memory_budget_is_refused_before_it_is_read(tmp_path):
    import subprocess
    import sys

    net = geode.Network()
    grid = net.create_node("grid", "g", params={"rows": 600, "columns": 600})
    path = tmp_path / "big.bgeo"
    net.cook(grid).save(path)
    script = (
        "import geode, sys\n"
        "try:\n"
        f"    geode.Geometry.load({str(path)!r})\n"
        "except geode.FileError as e:\n"
        "    print(e.kind, e.message)\n"
    )
    env = dict(__import__("os").environ, GEODE_MEMORY_MB="1")
    out = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, check=True).stdout
    assert out.startswith("resource "), out
    assert "GEODE_MEMORY_MB" in out or "budget" in out, out
    assert geode.Geometry.load(path).num_points == net.cook(grid).num_points
