// geode's C face onto manifold (vendor/manifold): solids from raw arrays,
// booleans, meshes read back with each triangle's source face. Every C++
// exception stops here and becomes a status code, so none crosses into Rust.

#include <manifold/manifold.h>

#if MANIFOLD_PAR == 1
#include <tbb/task_arena.h>
#endif

#include <cstdint>
#include <cstring>
#include <exception>
#include <new>
#include <string>
#include <utility>

using manifold::Manifold;
using manifold::MeshGL;

namespace {

// Status codes: 0 is success, 1..=64 are manifold's Error values plus one,
// these are the shim's own.
constexpr int kOutOfMemory = 100;
constexpr int kException = 101;
constexpr int kBadArgument = 102;

thread_local std::string last_error;

int status_of(Manifold::Error e) { return e == Manifold::Error::NoError ? 0 : static_cast<int>(e) + 1; }

// `f` on at most `threads` of TBB's threads (all of them for 0) when
// manifold is built parallel: each call is given its caller's share, so a
// cook on one thread stays on one, and the same inputs give the same
// result on any count (manifold sorts what its threads find).
template <typename F>
int in_arena(uint32_t threads, F&& f) {
#if MANIFOLD_PAR == 1
  if (threads > 0) {
    tbb::task_arena arena(static_cast<int>(threads));
    return arena.execute(f);
  }
#else
  (void)threads;
#endif
  return f();
}

template <typename F>
int guarded(uint32_t threads, F&& f) {
  try {
    last_error.clear();
    return in_arena(threads, f);
  } catch (const std::bad_alloc&) {
    last_error = "out of memory";
    return kOutOfMemory;
  } catch (const std::exception& e) {
    last_error = e.what();
    return kException;
  } catch (...) {
    last_error = "unknown C++ exception";
    return kException;
  }
}

}  // namespace

struct GmSolid {
  Manifold solid;
};

struct GmMesh {
  MeshGL mesh;
};

namespace {

// `solid` evaluated (its status read forces manifold's lazy work) and
// handed to the caller in `out`, or its error status.
int hand_out(Manifold solid, GmSolid** out) {
  int status = status_of(solid.Status());
  if (status != 0) return status;
  *out = new GmSolid{std::move(solid)};
  return 0;
}

}  // namespace

extern "C" {

const char* gm_last_error() { return last_error.c_str(); }

// Whether manifold was built on TBB (its parallel backend).
int gm_parallel() { return MANIFOLD_PAR == 1; }

// A solid from `npoints` positions (x, y, z floats) and `ntris` triangles of
// point indices, each triangle's face number in `face_ids`. `source` is the
// solid's original ID: a result's triangles are sorted by it, so giving it
// here (rather than letting manifold draw the next ID from its global
// counter) keeps the output's order independent of which solid another
// thread happened to build first.
int gm_solid_new(const float* positions, uint64_t npoints, const uint32_t* tris, uint64_t ntris,
                 const uint32_t* face_ids, uint32_t source, uint32_t threads, GmSolid** out) {
  return guarded(threads, [&]() -> int {
    *out = nullptr;
    if ((npoints > 0 && positions == nullptr) || (ntris > 0 && (tris == nullptr || face_ids == nullptr))) {
      last_error = "null array";
      return kBadArgument;
    }
    MeshGL mesh;
    mesh.numProp = 3;
    mesh.vertProperties.assign(positions, positions + 3 * npoints);
    mesh.triVerts.assign(tris, tris + 3 * ntris);
    mesh.faceID.assign(face_ids, face_ids + ntris);
    mesh.runIndex = {0, static_cast<uint32_t>(3 * ntris)};
    mesh.runOriginalID = {source};
    return hand_out(Manifold(mesh), out);
  });
}

void gm_solid_free(GmSolid* solid) { delete solid; }

// The boolean `op` (0 union, 1 subtract, 2 intersect) of `a` and `b`,
// evaluated before it returns.
int gm_boolean(const GmSolid* a, const GmSolid* b, int op, uint32_t threads, GmSolid** out) {
  return guarded(threads, [&]() -> int {
    *out = nullptr;
    if (a == nullptr || b == nullptr || op < 0 || op > 2) {
      last_error = "bad boolean arguments";
      return kBadArgument;
    }
    const manifold::OpType ops[] = {manifold::OpType::Add, manifold::OpType::Subtract,
                                    manifold::OpType::Intersect};
    return hand_out(a->solid.Boolean(b->solid, ops[op]), out);
  });
}

// `solid`'s connected pieces unioned: where closed pieces overlap (each
// closed, together one valid mesh), the overlap goes and one boundary is
// left.
int gm_union_pieces(const GmSolid* solid, uint32_t threads, GmSolid** out) {
  return guarded(threads, [&]() -> int {
    *out = nullptr;
    if (solid == nullptr) {
      last_error = "null solid";
      return kBadArgument;
    }
    return hand_out(Manifold::BatchBoolean(solid->solid.Decompose(), manifold::OpType::Add), out);
  });
}

// The solid's triangle mesh; its sizes by `gm_mesh_sizes`, its arrays by
// `gm_mesh_copy`.
int gm_mesh_of(const GmSolid* solid, uint32_t threads, GmMesh** out) {
  return guarded(threads, [&]() -> int {
    *out = nullptr;
    if (solid == nullptr) {
      last_error = "null solid";
      return kBadArgument;
    }
    *out = new GmMesh{solid->solid.GetMeshGL()};
    return 0;
  });
}

void gm_mesh_sizes(const GmMesh* mesh, uint64_t* npoints, uint64_t* ntris) {
  *npoints = mesh->mesh.NumVert();
  *ntris = mesh->mesh.NumTri();
}

// Copies the positions (3 floats a point), triangles (3 indices each) and
// each triangle's source face number into arrays of the sizes given.
void gm_mesh_copy(const GmMesh* mesh, float* positions, uint32_t* tris, uint32_t* face_ids) {
  const MeshGL& m = mesh->mesh;
  const uint64_t n = m.NumVert();
  for (uint64_t v = 0; v < n; ++v) {
    for (int k = 0; k < 3; ++k) positions[3 * v + k] = m.vertProperties[v * m.numProp + k];
  }
  std::memcpy(tris, m.triVerts.data(), m.triVerts.size() * sizeof(uint32_t));
  if (m.faceID.size() == m.NumTri()) {
    std::memcpy(face_ids, m.faceID.data(), m.faceID.size() * sizeof(uint32_t));
  } else {
    std::memset(face_ids, 0xff, m.NumTri() * sizeof(uint32_t));
  }
}

void gm_mesh_free(GmMesh* mesh) { delete mesh; }

}  // extern "C"
