"""Blender's import of a `.vdb` file as a volume object, for geode's VDB
tests: run as `blender -b --factory-startup --python tools/blender_vdb.py --
FILE`; prints one line `VDB {json}` with the grids Blender lists (name, data
type), whether the first grid's voxels load, its index-to-object matrix and
the object's bounding box."""

import json
import os
import sys

import bpy

path = sys.argv[sys.argv.index("--") + 1]
folder, name = os.path.split(os.path.abspath(path))
bpy.ops.object.volume_import(filepath=path, files=[{"name": name}], directory=folder + "/")
obj = bpy.context.selected_objects[0]
grids = obj.data.grids
grids.load()
first = grids[0] if len(grids) else None
box = [tuple(v) for v in obj.bound_box]
print("VDB " + json.dumps({
    "type": obj.type,
    "error": grids.error_message,
    "grids": [[g.name, g.data_type] for g in grids],
    "loaded": bool(first and first.load()),
    "matrix": [list(r) for r in first.matrix_object] if first else None,
    "min": [min(v[k] for v in box) for k in range(3)],
    "max": [max(v[k] for v in box) for k in range(3)],
}))
