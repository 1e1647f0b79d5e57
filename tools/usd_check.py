"""Opens .usda files with usd-core (Pixar's USD) and checks them.

Usage: usd_check.py FILE [EXPECT_JSON]...
Each FILE may be followed by a JSON object of expectations:
{"points": N, "faces": N, "curves": N, "instances": N}. Prints one JSON line per
file and exits 1 on any composition error or unmet expectation.
"""
import json
import sys

from pxr import Tf, Usd, UsdGeom


def check(path, expect):
    errors = []
    stage = Usd.Stage.Open(path)
    if stage is None:
        return {"file": path, "ok": False, "errors": ["could not open"]}
    for err in stage.GetCompositionErrors():
        errors.append(str(err))
    counts = {"points": 0, "faces": 0, "curves": 0, "instances": 0}
    # Instance proxies are visited so nested instances count; geometry is
    # counted once, where it is authored (not once per instance).
    for prim in stage.Traverse(Usd.TraverseInstanceProxies()):
        if prim.IsInstance():
            counts["instances"] += 1
        if prim.IsInstanceProxy():
            continue
        if prim.IsA(UsdGeom.Mesh):
            mesh = UsdGeom.Mesh(prim)
            pts = mesh.GetPointsAttr().Get() or []
            fvc = mesh.GetFaceVertexCountsAttr().Get() or []
            fvi = mesh.GetFaceVertexIndicesAttr().Get() or []
            counts["points"] += len(pts)
            counts["faces"] += len(fvc)
            if sum(fvc) != len(fvi):
                errors.append(f"{prim.GetPath()}: counts sum {sum(fvc)} != {len(fvi)} indices")
            if fvi and max(fvi) >= len(pts):
                errors.append(f"{prim.GetPath()}: index {max(fvi)} out of range")
            for pv in UsdGeom.PrimvarsAPI(prim).GetPrimvarsWithAuthoredValues():
                # ValueMightBeTimeVarying etc. are fine; check element counts.
                vals = pv.Get()
                interp = pv.GetInterpolation()
                n = len(vals) if vals is not None else 0
                want = {"vertex": len(pts), "faceVarying": len(fvi), "uniform": len(fvc), "constant": 1}.get(interp)
                if want is not None and n != want:
                    errors.append(f"{prim.GetPath()} {pv.GetName()}: {n} values for {interp} (want {want})")
        if prim.IsA(UsdGeom.BasisCurves):
            counts["curves"] += len(UsdGeom.BasisCurves(prim).GetCurveVertexCountsAttr().Get() or [])
    for k, v in expect.items():
        if counts.get(k) != v:
            errors.append(f"expected {k}={v}, found {counts.get(k)}")
    return {"file": path, "ok": not errors, "errors": errors, "counts": counts}


def main(argv):
    ok = True
    i = 0
    while i < len(argv):
        path = argv[i]
        expect = {}
        if i + 1 < len(argv) and argv[i + 1].startswith("{"):
            expect = json.loads(argv[i + 1])
            i += 1
        i += 1
        try:
            result = check(path, expect)
        except Tf.ErrorException as e:
            result = {"file": path, "ok": False, "errors": [str(e)]}
        print(json.dumps(result))
        ok = ok and result["ok"]
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
