"""Opens .usda files with usd-core (Pixar's USD) and checks them.

Usage: usd_check.py FILE [EXPECT_JSON]...
Each FILE may be followed by a JSON object of expectations:
{"points": N, "faces": N, "curves": N, "instances": N, "patches": N}. Prints
one JSON line per file (with each NurbsPatch's point at the centre of its
range, evaluated here by Cox-de Boor with u varying fastest, as RenderMan's
RiNuPatch and USD lay points out, and every primvar's type, role,
interpolation, count and first value as USD reads them) and exits 1 on any
composition error, primvar count that disagrees with its interpolation, or
unmet expectation.
"""
import json
import sys

from pxr import Tf, Usd, UsdGeom


def basis(knots, order, t):
    """Values of every B-spline basis function of `order` at t (Cox-de Boor)."""
    n = len(knots) - order
    hi = knots[n]
    # Degree 0: the span holding t (the last non-empty span at the end).
    N = [0.0] * (len(knots) - 1)
    for i in range(len(knots) - 1):
        if knots[i] <= t < knots[i + 1] or (t == hi and knots[i] < knots[i + 1] == hi):
            N[i] = 1.0
            break
    for k in range(2, order + 1):
        M = [0.0] * (len(knots) - k)
        for i in range(len(M)):
            a = knots[i + k - 1] - knots[i]
            b = knots[i + k] - knots[i + 1]
            if a > 0:
                M[i] += (t - knots[i]) / a * N[i]
            if b > 0:
                M[i] += (knots[i + k] - t) / b * N[i + 1]
        N = M
    return N[:n]


def patch_centre(patch):
    nu, nv = patch.GetUVertexCountAttr().Get(), patch.GetVVertexCountAttr().Get()
    ou, ov = patch.GetUOrderAttr().Get(), patch.GetVOrderAttr().Get()
    ku, kv = list(patch.GetUKnotsAttr().Get()), list(patch.GetVKnotsAttr().Get())
    pts = patch.GetPointsAttr().Get()
    w = patch.GetPointWeightsAttr().Get() or [1.0] * len(pts)
    ru, rv = patch.GetURangeAttr().Get(), patch.GetVRangeAttr().Get()
    bu = basis(ku, ou, 0.5 * (ru[0] + ru[1]))
    bv = basis(kv, ov, 0.5 * (rv[0] + rv[1]))
    acc, wsum = [0.0, 0.0, 0.0], 0.0
    for j in range(nv):
        for i in range(nu):
            k = j * nu + i
            c = bu[i] * bv[j] * w[k]
            wsum += c
            for d in range(3):
                acc[d] += c * pts[k][d]
    return [a / wsum for a in acc]


def plain(v):
    """A USD value as JSON: numbers, lists of numbers (quaternions real part first), strings."""
    if isinstance(v, (int, float, str, bool)):
        return v
    if hasattr(v, "GetReal"):
        return [v.GetReal()] + list(v.GetImaginary())
    try:
        return [plain(x) for x in v]
    except TypeError:
        return str(v)


def check_primvars(prim, sizes, errors, out):
    """Element counts of every primvar against its interpolation; each
    primvar's type, interpolation, count and first value into `out`."""
    for pv in UsdGeom.PrimvarsAPI(prim).GetPrimvarsWithAuthoredValues():
        vals = pv.Get()
        interp = pv.GetInterpolation()
        is_array = pv.GetTypeName().isArray
        n = (len(vals) if vals is not None else 0) if is_array else 1
        want = sizes.get(interp)
        if want is not None and n != want:
            errors.append(f"{prim.GetPath()} {pv.GetName()}: {n} values for {interp} (want {want})")
        first = (vals[0] if n else None) if is_array else vals
        out[f"{prim.GetPath()}.{pv.GetPrimvarName()}"] = {
            "type": str(pv.GetTypeName()),
            "role": str(pv.GetTypeName().role),
            "interpolation": interp,
            "count": n,
            "first": plain(first),
        }


def check(path, expect):
    errors = []
    stage = Usd.Stage.Open(path)
    if stage is None:
        return {"file": path, "ok": False, "errors": ["could not open"]}
    for err in stage.GetCompositionErrors():
        errors.append(str(err))
    counts = {"points": 0, "faces": 0, "curves": 0, "instances": 0, "patches": 0}
    centres = []
    primvars = {}
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
            sizes = {"vertex": len(pts), "faceVarying": len(fvi), "uniform": len(fvc), "constant": 1}
            check_primvars(prim, sizes, errors, primvars)
        if prim.IsA(UsdGeom.NurbsPatch):
            patch = UsdGeom.NurbsPatch(prim)
            counts["patches"] += 1
            nu, nv = patch.GetUVertexCountAttr().Get(), patch.GetVVertexCountAttr().Get()
            pts = patch.GetPointsAttr().Get() or []
            if len(pts) != nu * nv:
                errors.append(f"{prim.GetPath()}: {len(pts)} points for {nu} x {nv}")
            for side, n, order, knots in [
                ("u", nu, patch.GetUOrderAttr().Get(), patch.GetUKnotsAttr().Get()),
                ("v", nv, patch.GetVOrderAttr().Get(), patch.GetVKnotsAttr().Get()),
            ]:
                if len(knots) != n + order:
                    errors.append(f"{prim.GetPath()}: {len(knots)} {side} knots for {n} points of order {order}")
            weights = patch.GetPointWeightsAttr().Get()
            if weights is not None and len(weights) != len(pts):
                errors.append(f"{prim.GetPath()}: {len(weights)} weights for {len(pts)} points")
            if not errors:
                centres.append(patch_centre(patch))
        if prim.IsA(UsdGeom.BasisCurves):
            cvc = UsdGeom.BasisCurves(prim).GetCurveVertexCountsAttr().Get() or []
            counts["curves"] += len(cvc)
            sizes = {"vertex": sum(cvc), "varying": sum(cvc), "uniform": len(cvc), "constant": 1}
            check_primvars(prim, sizes, errors, primvars)
    for k, v in expect.items():
        if counts.get(k) != v:
            errors.append(f"expected {k}={v}, found {counts.get(k)}")
    return {"file": path, "ok": not errors, "errors": errors, "counts": counts, "patch_centres": centres, "primvars": primvars}


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
