"""OpenVDB's own reading and writing of `.vdb` files, for geode's VDB tests:
run by Debian's system python3 with python3-openvdb (pyopenvdb).

  vdb_check.py dump FILE GRID LO HI OUT
      Reads grid GRID of FILE with pyopenvdb; writes OUT.json (name, class,
      background, voxel size, index-to-world of three points, active voxel
      count and bounds, metadata) and OUT.bin (float32, the dense values over
      the inclusive index box LO..HI, each "i,j,k", x slowest).
  vdb_check.py sphere OUT RADIUS CX,CY,CZ VOXEL HALF_WIDTH HALF
      Writes OpenVDB's level-set sphere named "surface" to OUT (stored as half
      floats when HALF is 1), and OUT.json/OUT.bin as `dump` does (for the
      grid read back from OUT) over its active bounds grown by two voxels.
"""

import json
import sys

import numpy as np
import pyopenvdb as vdb


def triple(text):
    return tuple(float(v) for v in text.split(","))


def dump(grid, lo, hi, out):
    shape = tuple(int(hi[k] - lo[k] + 1) for k in range(3))
    dense = np.zeros(shape, dtype=np.float32)
    grid.copyToArray(dense, ijk=tuple(int(v) for v in lo))
    dense.tofile(out + ".bin")
    bbox = grid.evalActiveVoxelBoundingBox()
    meta = {}
    for key, value in grid.metadata.items():
        meta[key] = value if isinstance(value, (str, int, float, bool)) else list(value)
    info = {
        "name": grid.name,
        "class": str(grid.gridClass),
        "background": float(grid.background),
        "voxel_size": list(grid.transform.voxelSize()),
        "world": [list(grid.transform.indexToWorld(p)) for p in [(0, 0, 0), (1, 2, 3), (-7, 5, 11)]],
        "active_voxels": int(grid.activeVoxelCount()),
        "active_bounds": [list(bbox[0]), list(bbox[1])],
        "lo": list(lo),
        "hi": list(hi),
        "metadata": meta,
    }
    with open(out + ".json", "w") as f:
        json.dump(info, f)


def main():
    mode = sys.argv[1]
    if mode == "dump":
        _, _, path, name, lo, hi, out = sys.argv
        grid = vdb.read(path, name)
        dump(grid, [int(v) for v in lo.split(",")], [int(v) for v in hi.split(",")], out)
    elif mode == "sphere":
        _, _, out, radius, centre, voxel, half_width, half = sys.argv
        grid = vdb.createLevelSetSphere(
            radius=float(radius),
            center=triple(centre),
            voxelSize=float(voxel),
            halfWidth=float(half_width),
        )
        grid.name = "surface"
        if half == "1":
            grid.saveFloatAsHalf = True
        vdb.write(out, grids=[grid])
        grid = vdb.read(out, "surface")  # as OpenVDB reads its own file
        lo, hi = grid.evalActiveVoxelBoundingBox()
        dump(grid, [v - 2 for v in lo], [v + 2 for v in hi], out)
    else:
        raise SystemExit("unknown mode " + mode)


if __name__ == "__main__":
    main()
