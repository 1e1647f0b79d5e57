"""Checks meshes with trimesh: prints one JSON line per file with its
watertightness, winding consistency, volume and face count.

Usage: mesh_check.py FILE...
"""
import json
import sys

import trimesh


def main(paths):
    for path in paths:
        mesh = trimesh.load(path, force="mesh", process=True)
        print(json.dumps({
            "file": path,
            "watertight": bool(mesh.is_watertight),
            "winding_consistent": bool(mesh.is_winding_consistent),
            "volume": float(mesh.volume),
            "faces": int(len(mesh.faces)),
        }))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
