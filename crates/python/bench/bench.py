"""Benchmarks of geode's Python package: reading P of a 10M-point cook as numpy, and building a 100-node network.

Run from the repository root after `maturin develop --release -m crates/python/Cargo.toml`:
    tools/.venv/bin/python crates/python/bench/bench.py
Prints the median and the spread of each over its repetitions.
"""

import math
import statistics
import sys
import time

import geode


def timed(f, repeat):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return times


def report(name, times, goal=None):
    med = statistics.median(times)
    line = f"{name:<44} median {med * 1e3:9.4f} ms  min {min(times) * 1e3:9.4f}  max {max(times) * 1e3:9.4f}  ({len(times)} runs)"
    if goal is not None:
        line += f"  goal < {goal * 1e3:g} ms: {'met' if med < goal else 'MISSED'}"
    print(line)
    return med


def build_chain(n=100):
    net = geode.Network()
    prev = net.create_node("box", "n0", params={"size": [1, 2, 1]})
    for i in range(1, n):
        node = net.create_node("transform", f"n{i}", params={"translate": [0.1 * i, 0, 0], "rotate": [0, i, 0]})
        node.set_input(0, prev)
        prev = node
    net.output = prev
    return net


def main():
    points = int(sys.argv[1]) if len(sys.argv) > 1 else 10_000_000
    side = math.isqrt(points - 1) + 1
    net = geode.Network()
    grid = net.create_node("grid", "g", params={"rows": side - 1, "columns": side - 1})
    geo = net.cook(grid)
    print(f"grid of {geo.num_points:,} points")
    report("points['P'] as numpy (zero-copy)", timed(lambda: geo.points["P"], 200), goal=1e-3)
    report("points['P'] copied by numpy (for contrast)", timed(lambda: geo.points["P"].copy(), 10))
    report("cook of the cached grid (cache hit)", timed(lambda: net.cook(grid), 50))
    build_chain()
    report("100-node network built from Python", timed(build_chain, 30), goal=10e-3)
    chain = build_chain()
    report("to_json of the 100-node network", timed(chain.to_json, 30))

    ball = geode.Network()
    sphere = ball.create_node("sphere", "s", params={"rows": 500, "columns": 1000})
    mesh = ball.cook(sphere)
    report(f"Jupyter's PNG of a {mesh.num_prims:,}-polygon sphere", timed(mesh.png, 5))

    # Numpy into a network: Geometry.from_arrays copies the points once;
    # a python_input hands the same geometry to its cook (no copy), keyed
    # by its content hash (hashed once per geometry, then cached).
    import numpy as np

    P = np.random.default_rng(1).random((points, 3), dtype=np.float32)
    report(f"Geometry.from_arrays of {points:,} points", timed(lambda: geode.Geometry.from_arrays(P), 5))
    fed = geode.Network()
    src = fed.create_node("python_input", "src")
    out = fed.create_node("null", "out").set_input(0, src)

    def feed_and_cook():
        g = geode.Geometry.from_arrays(P)
        t = time.perf_counter()
        src.parm("geometry").set(g)
        fed.cook(out)
        return time.perf_counter() - t

    feed_and_cook()
    report(f"python_input of {points:,} points set and cooked (hash included)", [feed_and_cook() for _ in range(5)])


if __name__ == "__main__":
    main()
