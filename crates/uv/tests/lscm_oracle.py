"""LSCM reference for geode-uv's tests: libigl's igl.lscm (PyPI libigl).

Reads from standard input a header line "vertices triangles pins", then
one "x y z" line per vertex, one "i j k" line per triangle and one
"vertex u v" line per pin; prints one "u v" line per vertex (17
significant digits). Exits with status 3 and a message naming what is
missing when numpy or igl cannot be imported.
"""

import sys

try:
    import numpy as np
    import igl
except ImportError as missing:  # the Rust test says SKIPPED (or fails on CI)
    print(f"missing: {missing}", file=sys.stderr)
    sys.exit(3)


def main():
    lines = sys.stdin.read().split("\n")
    nv, nf, nb = (int(x) for x in lines[0].split())
    rows = [line.split() for line in lines[1 : 1 + nv + nf + nb]]
    v = np.array(rows[:nv], dtype=np.float64)
    f = np.array(rows[nv : nv + nf], dtype=np.int64)
    pins = np.array(rows[nv + nf :], dtype=np.float64)
    b = pins[:, 0].astype(np.int64)
    bc = np.ascontiguousarray(pins[:, 1:3])
    result = igl.lscm(v, f, b, bc)
    # libigl 2.6 returns (uv, Q); older bindings returned uv or (ok, uv).
    if isinstance(result, tuple):
        uv = next(r for r in result if isinstance(r, np.ndarray) and r.ndim == 2)
    else:
        uv = result
    out = "\n".join(f"{u:.17g} {w:.17g}" for u, w in uv)
    sys.stdout.write(out + "\n")


main()
