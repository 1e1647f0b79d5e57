// Reference Catmull-Clark refinement by OpenSubdiv (Debian libosd-dev), for
// geode's tests: reads a mesh description on stdin, refines it uniformly
// with Far::TopologyRefiner and Far::PrimvarRefiner, and prints the
// positions of every level and the limit positions and normals of the last.
//
// Input (whitespace separated):
//   boundary B crease C levels L        (B: 0 none, 1 edge only, 2 edge and
//                                        corner; C: 0 uniform, 1 Chaikin)
//   verts N      then N lines "x y z"
//   faces F      then F lines "n i0 ... i(n-1)"
//   creases K    then K lines "a b sharpness"
//   corners M    then M lines "v sharpness"
//   holes H      then H face indices
//   [fvar M V     optional: a 2-D face-varying channel with linear interpolation
//                 M (0 none, 1 corners only, 2 corners plus1, 3 corners plus2,
//                 4 boundaries, 5 all), V lines "u v", then one value index per
//                 face corner in face order]
// Output: "level k n" then n lines "x y z", for k = 1..L; then "limit n"
// and n lines; then "normal n" and n unit normals (du x dv); with fvar,
// "fvar k n" and the n face corners' values of level k, in face order, then
// "fvarlimit n" and the last level's corners' values at the limit.
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

using namespace OpenSubdiv;

struct Vertex {
    double p[3];
    void Clear(void * = 0) { p[0] = p[1] = p[2] = 0.0; }
    void AddWithWeight(Vertex const & src, float weight) {
        for (int k = 0; k < 3; ++k) p[k] += weight * src.p[k];
    }
};

struct FVar {
    double uv[2];
    void Clear(void * = 0) { uv[0] = uv[1] = 0.0; }
    void AddWithWeight(FVar const & src, float weight) {
        uv[0] += weight * src.uv[0];
        uv[1] += weight * src.uv[1];
    }
};

static bool expect(std::istream & in, char const * word) {
    std::string w;
    if (!(in >> w) || w != word) {
        std::fprintf(stderr, "expected `%s`, found `%s`\n", word, w.c_str());
        return false;
    }
    return true;
}

int main() {
    std::istream & in = std::cin;
    int boundary = 1, crease = 0, levels = 1;
    if (!expect(in, "boundary") || !(in >> boundary) || !expect(in, "crease") || !(in >> crease) ||
        !expect(in, "levels") || !(in >> levels)) return 2;
    int nv = 0, nf = 0, nc = 0, nk = 0, nh = 0;
    if (!expect(in, "verts") || !(in >> nv)) return 2;
    std::vector<Vertex> coarse(nv);
    for (auto & v : coarse) in >> v.p[0] >> v.p[1] >> v.p[2];
    if (!expect(in, "faces") || !(in >> nf)) return 2;
    std::vector<int> counts(nf), indices;
    for (int f = 0; f < nf; ++f) {
        in >> counts[f];
        for (int k = 0; k < counts[f]; ++k) { int i; in >> i; indices.push_back(i); }
    }
    if (!expect(in, "creases") || !(in >> nc)) return 2;
    std::vector<int> creasePairs(2 * nc);
    std::vector<float> creaseWeights(nc);
    for (int i = 0; i < nc; ++i) in >> creasePairs[2 * i] >> creasePairs[2 * i + 1] >> creaseWeights[i];
    if (!expect(in, "corners") || !(in >> nk)) return 2;
    std::vector<int> cornerVerts(nk);
    std::vector<float> cornerWeights(nk);
    for (int i = 0; i < nk; ++i) in >> cornerVerts[i] >> cornerWeights[i];
    if (!expect(in, "holes") || !(in >> nh)) return 2;
    std::vector<int> holes(nh);
    for (int i = 0; i < nh; ++i) in >> holes[i];
    if (!in) { std::fprintf(stderr, "truncated input\n"); return 2; }
    int fvarMode = -1, fvarCount = 0;
    std::vector<FVar> fvarValues;
    std::vector<int> fvarIndices;
    std::string word;
    if (in >> word) {
        if (word != "fvar" || !(in >> fvarMode >> fvarCount)) { std::fprintf(stderr, "expected `fvar`\n"); return 2; }
        fvarValues.resize(fvarCount);
        for (auto & v : fvarValues) in >> v.uv[0] >> v.uv[1];
        fvarIndices.resize(indices.size());
        for (auto & i : fvarIndices) in >> i;
        if (!in) { std::fprintf(stderr, "truncated fvar\n"); return 2; }
    }

    Sdc::Options options;
    options.SetVtxBoundaryInterpolation(boundary == 0 ? Sdc::Options::VTX_BOUNDARY_NONE
                                        : boundary == 2 ? Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER
                                                        : Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    options.SetCreasingMethod(crease ? Sdc::Options::CREASE_CHAIKIN : Sdc::Options::CREASE_UNIFORM);
    if (fvarMode >= 0) {
        static const Sdc::Options::FVarLinearInterpolation modes[] = {
            Sdc::Options::FVAR_LINEAR_NONE, Sdc::Options::FVAR_LINEAR_CORNERS_ONLY,
            Sdc::Options::FVAR_LINEAR_CORNERS_PLUS1, Sdc::Options::FVAR_LINEAR_CORNERS_PLUS2,
            Sdc::Options::FVAR_LINEAR_BOUNDARIES, Sdc::Options::FVAR_LINEAR_ALL};
        options.SetFVarLinearInterpolation(modes[fvarMode < 0 || fvarMode > 5 ? 5 : fvarMode]);
    }

    Far::TopologyDescriptor desc;
    desc.numVertices = nv;
    desc.numFaces = nf;
    desc.numVertsPerFace = counts.data();
    desc.vertIndicesPerFace = indices.data();
    desc.numCreases = nc;
    desc.creaseVertexIndexPairs = creasePairs.data();
    desc.creaseWeights = creaseWeights.data();
    desc.numCorners = nk;
    desc.cornerVertexIndices = cornerVerts.data();
    desc.cornerWeights = cornerWeights.data();
    desc.numHoles = nh;
    desc.holeIndices = holes.data();
    Far::TopologyDescriptor::FVarChannel channel;
    if (fvarMode >= 0) {
        channel.numValues = fvarCount;
        channel.valueIndices = fvarIndices.data();
        desc.numFVarChannels = 1;
        desc.fvarChannels = &channel;
    }

    typedef Far::TopologyRefinerFactory<Far::TopologyDescriptor> Factory;

    // Timing mode (OSD_REF_TIME=runs): build, refine and interpolate every
    // level (positions, and the face-varying channel when given) `runs`
    // times and print the median milliseconds, nothing else.
    if (char const * runsText = std::getenv("OSD_REF_TIME")) {
        int runs = std::atoi(runsText);
        std::vector<double> times;
        for (int r = 0; r < runs; ++r) {
            auto start = std::chrono::steady_clock::now();
            Far::TopologyRefiner * t = Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, options));
            t->RefineUniform(Far::TopologyRefiner::UniformOptions(levels));
            std::vector<Vertex> buf(t->GetNumVerticesTotal());
            for (int i = 0; i < nv; ++i) buf[i] = coarse[i];
            Far::PrimvarRefiner pr(*t);
            Vertex * s = buf.data();
            for (int level = 1; level <= levels; ++level) {
                Vertex * d = s + t->GetLevel(level - 1).GetNumVertices();
                pr.Interpolate(level, s, d);
                s = d;
            }
            if (fvarMode >= 0) {
                std::vector<FVar> fbuf(t->GetNumFVarValuesTotal(0));
                std::copy(fvarValues.begin(), fvarValues.end(), fbuf.begin());
                FVar * fs = fbuf.data();
                for (int level = 1; level <= levels; ++level) {
                    FVar * fd = fs + t->GetLevel(level - 1).GetNumFVarValues(0);
                    pr.InterpolateFaceVarying(level, fs, fd, 0);
                    fs = fd;
                }
            }
            times.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
            delete t;
        }
        std::sort(times.begin(), times.end());
        std::printf("%.3f\n", times[times.size() / 2]);
        return 0;
    }

    Far::TopologyRefiner * refiner =
        Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, options));
    if (!refiner) { std::fprintf(stderr, "OpenSubdiv rejected the topology\n"); return 3; }
    Far::TopologyRefiner::UniformOptions uniform(levels);
    uniform.fullTopologyInLastLevel = true;  // Limit() needs the last level's edges
    refiner->RefineUniform(uniform);

    std::vector<Vertex> buffer(refiner->GetNumVerticesTotal());
    for (int i = 0; i < nv; ++i) buffer[i] = coarse[i];
    Far::PrimvarRefiner primvar(*refiner);
    Vertex * src = buffer.data();
    for (int level = 1; level <= levels; ++level) {
        Vertex * dst = src + refiner->GetLevel(level - 1).GetNumVertices();
        primvar.Interpolate(level, src, dst);
        src = dst;
        int n = refiner->GetLevel(level).GetNumVertices();
        std::printf("level %d %d\n", level, n);
        for (int i = 0; i < n; ++i) std::printf("%.10g %.10g %.10g\n", src[i].p[0], src[i].p[1], src[i].p[2]);
    }
    int n = refiner->GetLevel(levels).GetNumVertices();
    std::vector<Vertex> limit(n), du(n), dv(n);
    // Far's limit tangents crash on non-manifold vertices: positions only
    // there, and zero normals (which the tests leave out).
    Far::TopologyLevel const & last = refiner->GetLevel(levels);
    bool manifold = true;
    for (int i = 0; i < n; ++i) manifold = manifold && !last.IsVertexNonManifold(i);
    if (manifold) {
        primvar.Limit(src, limit, du, dv);
    } else {
        primvar.Limit(src, limit);
    }
    std::printf("limit %d\n", n);
    for (int i = 0; i < n; ++i) std::printf("%.10g %.10g %.10g\n", limit[i].p[0], limit[i].p[1], limit[i].p[2]);
    // Unit normals from the limit tangents (zero where they are parallel).
    std::printf("normal %d\n", n);
    for (int i = 0; i < n; ++i) {
        double const * a = du[i].p;
        double const * b = dv[i].p;
        double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
        double len = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        if (len > 0) for (int k = 0; k < 3; ++k) c[k] /= len;
        std::printf("%.10g %.10g %.10g\n", c[0], c[1], c[2]);
    }
    if (fvarMode >= 0) {
        std::vector<FVar> fbuf(refiner->GetNumFVarValuesTotal(0));
        std::copy(fvarValues.begin(), fvarValues.end(), fbuf.begin());
        FVar * fsrc = fbuf.data();
        for (int level = 1; level <= levels; ++level) {
            FVar * fdst = fsrc + refiner->GetLevel(level - 1).GetNumFVarValues(0);
            primvar.InterpolateFaceVarying(level, fsrc, fdst, 0);
            fsrc = fdst;
            Far::TopologyLevel const & l = refiner->GetLevel(level);
            int corners = 0;
            for (int f = 0; f < l.GetNumFaces(); ++f) corners += l.GetFaceVertices(f).size();
            std::printf("fvar %d %d\n", level, corners);
            for (int f = 0; f < l.GetNumFaces(); ++f) {
                Far::ConstIndexArray fv = l.GetFaceFVarValues(f, 0);
                for (int k = 0; k < fv.size(); ++k) std::printf("%.10g %.10g\n", fsrc[fv[k]].uv[0], fsrc[fv[k]].uv[1]);
            }
        }
        // The last level's values at the limit, corner by corner.
        Far::TopologyLevel const & last = refiner->GetLevel(levels);
        std::vector<FVar> flimit(last.GetNumFVarValues(0));
        primvar.LimitFaceVarying(fsrc, flimit, 0);
        int corners = 0;
        for (int f = 0; f < last.GetNumFaces(); ++f) corners += last.GetFaceVertices(f).size();
        std::printf("fvarlimit %d\n", corners);
        for (int f = 0; f < last.GetNumFaces(); ++f) {
            Far::ConstIndexArray fv = last.GetFaceFVarValues(f, 0);
            for (int k = 0; k < fv.size(); ++k) std::printf("%.10g %.10g\n", flimit[fv[k]].uv[0], flimit[fv[k]].uv[1]);
        }
    }
    delete refiner;
    return 0;
}
