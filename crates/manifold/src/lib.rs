//! manifold's exact, robust mesh booleans (the C++ library vendored in
//! vendor/manifold, built by build.rs with a small C shim) behind a safe
//! face: a [`Solid`] from positions and triangles, each triangle carrying a
//! face number; [`boolean`] of two solids; the result's [`Mesh`], where
//! every triangle names the input face it lies in.
//!
//! It knows meshes only: nothing of geode's geometry, nodes or graphs.

use std::ffi::CStr;
use std::ptr::NonNull;

use thiserror::Error;

mod ffi {
    #[repr(C)]
    pub struct GmSolid {
        _opaque: [u8; 0],
    }
    #[repr(C)]
    pub struct GmMesh {
        _opaque: [u8; 0],
    }
    extern "C" {
        pub fn gm_last_error() -> *const std::ffi::c_char;
        pub fn gm_solid_new(
            positions: *const f32,
            npoints: u64,
            tris: *const u32,
            ntris: u64,
            face_ids: *const u32,
            source: u32,
            threads: u32,
            out: *mut *mut GmSolid,
        ) -> i32;
        pub fn gm_solid_free(solid: *mut GmSolid);
        pub fn gm_boolean(
            a: *const GmSolid,
            b: *const GmSolid,
            op: i32,
            threads: u32,
            out: *mut *mut GmSolid,
        ) -> i32;
        pub fn gm_union_pieces(solid: *const GmSolid, threads: u32, out: *mut *mut GmSolid) -> i32;
        pub fn gm_mesh_of(solid: *const GmSolid, threads: u32, out: *mut *mut GmMesh) -> i32;
        pub fn gm_parallel() -> i32;
        pub fn gm_mesh_sizes(mesh: *const GmMesh, npoints: *mut u64, ntris: *mut u64);
        pub fn gm_mesh_copy(
            mesh: *const GmMesh,
            positions: *mut f32,
            tris: *mut u32,
            face_ids: *mut u32,
        );
        pub fn gm_mesh_free(mesh: *mut GmMesh);
    }
}

/// What manifold refused, or why it stopped.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum ManifoldError {
    /// Every edge must join exactly two triangles, in opposite directions.
    #[error("the mesh is not a closed manifold (an edge without exactly one opposite)")]
    NotManifold,
    #[error("a point's position is not finite")]
    NonFinite,
    #[error("a triangle names a point that does not exist")]
    PointOutOfRange,
    #[error("the result would be too large for manifold's 32-bit indices")]
    TooLarge,
    #[error("{0} face numbers for {1} triangles")]
    FaceCount(usize, usize),
    #[error("out of memory")]
    OutOfMemory,
    /// Anything else manifold reported (its status or its exception's text).
    #[error("{0}")]
    Other(String),
}

impl ManifoldError {
    fn from_status(status: i32) -> ManifoldError {
        // SAFETY: the shim's last error is a NUL-terminated thread-local
        // string, valid until the next shim call on this thread.
        let text = || {
            unsafe { CStr::from_ptr(ffi::gm_last_error()) }
                .to_string_lossy()
                .into_owned()
        };
        // manifold's Error values plus one (see shim/shim.cpp).
        match status {
            2 => ManifoldError::NonFinite,
            3 => ManifoldError::NotManifold,
            4 => ManifoldError::PointOutOfRange,
            13 => ManifoldError::TooLarge,
            100 => ManifoldError::OutOfMemory,
            101 | 102 => ManifoldError::Other(text()),
            s => ManifoldError::Other(format!("manifold status {}", s - 1)),
        }
    }
}

fn check(status: i32) -> Result<(), ManifoldError> {
    if status == 0 {
        Ok(())
    } else {
        Err(ManifoldError::from_status(status))
    }
}

/// Whether manifold was built on TBB, its parallel backend (build.rs uses
/// it where its headers are installed). Built serially, every call runs on
/// its caller's thread whatever `threads` it is given.
pub fn parallel() -> bool {
    // SAFETY: a constant of the build.
    unsafe { ffi::gm_parallel() != 0 }
}

/// `threads` for the shim: at least one (0 would mean all of TBB's).
fn thread_count(threads: usize) -> u32 {
    threads.clamp(1, u32::MAX as usize) as u32
}

/// A closed manifold solid, owned by manifold.
pub struct Solid(NonNull<ffi::GmSolid>);

// SAFETY: a manifold solid is immutable once built (its evaluation is
// finished before `Solid::new` and `boolean` return), and manifold reads
// shared solids from several threads itself.
unsafe impl Send for Solid {}
// SAFETY: as above; no method takes `&mut`.
unsafe impl Sync for Solid {}

impl Drop for Solid {
    fn drop(&mut self) {
        // SAFETY: the pointer came from the shim and is freed once, here.
        unsafe { ffi::gm_solid_free(self.0.as_ptr()) }
    }
}

/// A triangle mesh: positions, triangles over them and, per triangle, the
/// face number of the input triangle it lies in (`u32::MAX` if manifold
/// lost it).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub positions: Vec<[f32; 3]>,
    pub triangles: Vec<[u32; 3]>,
    pub faces: Vec<u32>,
}

impl Solid {
    /// The solid bounded by `triangles` (counter-clockwise seen from
    /// outside), `faces[t]` the number triangle `t` will be known by in a
    /// boolean's result. A result lists its triangles by their solids'
    /// `source` numbers, lowest first, whatever order the solids were
    /// built in (so give each solid of a boolean its own number). It is
    /// built on at most `threads` threads (see [`parallel`]).
    pub fn new(
        positions: &[[f32; 3]],
        triangles: &[[u32; 3]],
        faces: &[u32],
        source: u32,
        threads: usize,
    ) -> Result<Solid, ManifoldError> {
        if faces.len() != triangles.len() {
            return Err(ManifoldError::FaceCount(faces.len(), triangles.len()));
        }
        if triangles
            .iter()
            .flatten()
            .any(|&p| p as usize >= positions.len())
        {
            return Err(ManifoldError::PointOutOfRange);
        }
        let mut out = std::ptr::null_mut();
        // SAFETY: the arrays are the lengths passed; the shim copies them.
        let status = unsafe {
            ffi::gm_solid_new(
                positions.as_ptr().cast(),
                positions.len() as u64,
                triangles.as_ptr().cast(),
                triangles.len() as u64,
                faces.as_ptr(),
                source,
                thread_count(threads),
                &mut out,
            )
        };
        check(status)?;
        NonNull::new(out)
            .map(Solid)
            .ok_or_else(|| ManifoldError::Other("no solid".into()))
    }

    /// The solid's triangles, each with the face number it came from, on
    /// at most `threads` threads.
    pub fn mesh(&self, threads: usize) -> Result<Mesh, ManifoldError> {
        let mut raw = std::ptr::null_mut();
        // SAFETY: self.0 is a live solid.
        check(unsafe { ffi::gm_mesh_of(self.0.as_ptr(), thread_count(threads), &mut raw) })?;
        let raw = NonNull::new(raw).ok_or_else(|| ManifoldError::Other("no mesh".into()))?;
        let (mut npoints, mut ntris) = (0u64, 0u64);
        // SAFETY: raw is a live mesh; the arrays are allocated to the sizes
        // it reports before it writes them; it is freed once.
        unsafe {
            ffi::gm_mesh_sizes(raw.as_ptr(), &mut npoints, &mut ntris);
            let mut mesh = Mesh {
                positions: vec![[0.0; 3]; npoints as usize],
                triangles: vec![[0; 3]; ntris as usize],
                faces: vec![0; ntris as usize],
            };
            ffi::gm_mesh_copy(
                raw.as_ptr(),
                mesh.positions.as_mut_ptr().cast(),
                mesh.triangles.as_mut_ptr().cast(),
                mesh.faces.as_mut_ptr(),
            );
            ffi::gm_mesh_free(raw.as_ptr());
            Ok(mesh)
        }
    }
}

/// What a boolean keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    Union,
    Subtract,
    Intersect,
}

/// The boolean `op` of `a` and `b`, evaluated on at most `threads` threads
/// before it returns (manifold itself cannot be interrupted inside one
/// boolean).
pub fn boolean(a: &Solid, b: &Solid, op: Op, threads: usize) -> Result<Solid, ManifoldError> {
    let code = match op {
        Op::Union => 0,
        Op::Subtract => 1,
        Op::Intersect => 2,
    };
    let mut out = std::ptr::null_mut();
    // SAFETY: a and b are live solids.
    check(unsafe {
        ffi::gm_boolean(
            a.0.as_ptr(),
            b.0.as_ptr(),
            code,
            thread_count(threads),
            &mut out,
        )
    })?;
    NonNull::new(out)
        .map(Solid)
        .ok_or_else(|| ManifoldError::Other("no solid".into()))
}

/// `solid`'s connected pieces unioned (manifold's batch union of its
/// components): where closed pieces overlap, the overlap goes. On at most
/// `threads` threads.
pub fn union_pieces(solid: &Solid, threads: usize) -> Result<Solid, ManifoldError> {
    let mut out = std::ptr::null_mut();
    // SAFETY: solid is live.
    check(unsafe { ffi::gm_union_pieces(solid.0.as_ptr(), thread_count(threads), &mut out) })?;
    NonNull::new(out)
        .map(Solid)
        .ok_or_else(|| ManifoldError::Other("no solid".into()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An axis-aligned cube from `lo` to `lo + size`, faces numbered from
    /// `first`.
    fn cube(lo: [f32; 3], size: f32, first: u32) -> Solid {
        let p: Vec<[f32; 3]> = (0..8)
            .map(|i| {
                let bit = |b: u32| if i & (1 << b) != 0 { size } else { 0.0 };
                [lo[0] + bit(0), lo[1] + bit(1), lo[2] + bit(2)]
            })
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let tris: Vec<[u32; 3]> = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        let faces: Vec<u32> = (first..first + 12).collect();
        Solid::new(&p, &tris, &faces, first, 2).unwrap()
    }

    fn volume(m: &Mesh) -> f64 {
        m.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| m.positions[i as usize].map(f64::from));
                let cross = [
                    a[1] * b[2] - a[2] * b[1],
                    a[2] * b[0] - a[0] * b[2],
                    a[0] * b[1] - a[1] * b[0],
                ];
                (cross[0] * c[0] + cross[1] * c[1] + cross[2] * c[2]) / 6.0
            })
            .sum()
    }

    #[test]
    fn overlapping_cubes_give_the_volumes_of_their_union_difference_and_intersection() {
        let a = cube([0.0; 3], 2.0, 0);
        let b = cube([1.0; 3], 2.0, 100);
        let v = |op| volume(&boolean(&a, &b, op, 2).unwrap().mesh(2).unwrap());
        assert!((v(Op::Union) - 15.0).abs() < 1e-5);
        assert!((v(Op::Subtract) - 7.0).abs() < 1e-5);
        assert!((v(Op::Intersect) - 1.0).abs() < 1e-5);
    }

    #[test]
    fn every_result_triangle_names_an_input_face_of_its_side() {
        let a = cube([0.0; 3], 2.0, 0);
        let b = cube([1.0; 3], 2.0, 100);
        let m = boolean(&a, &b, Op::Union, 2).unwrap().mesh(2).unwrap();
        assert!(m.faces.iter().all(|&f| f < 12 || (100..112).contains(&f)));
        assert!(m.faces.iter().any(|&f| f < 12) && m.faces.iter().any(|&f| f >= 100));
    }

    #[test]
    fn an_open_mesh_is_refused_by_name() {
        let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        assert_eq!(
            Solid::new(&p, &[[0, 1, 2]], &[0], 0, 1).err(),
            Some(ManifoldError::NotManifold)
        );
        assert_eq!(
            Solid::new(&p, &[[0, 1, 2]], &[], 0, 1).err(),
            Some(ManifoldError::FaceCount(0, 1))
        );
        assert_eq!(
            Solid::new(&p, &[[0, 1, 7], [0, 7, 1]], &[0, 1], 0, 1).err(),
            Some(ManifoldError::PointOutOfRange)
        );
    }

    #[test]
    fn a_result_does_not_depend_on_which_solid_was_built_first() {
        // manifold numbers every new solid from a global counter and sorts
        // a result's triangles by those numbers: two identical boxes
        // (every face coplanar with one of the other's) built in either
        // order must give the same mesh.
        let a_first = {
            let a = cube([0.0; 3], 1.0, 0);
            let b = cube([0.0; 3], 1.0, 100);
            boolean(&a, &b, Op::Union, 2).unwrap().mesh(2).unwrap()
        };
        let b_first = {
            let b = cube([0.0; 3], 1.0, 100);
            let a = cube([0.0; 3], 1.0, 0);
            boolean(&a, &b, Op::Union, 2).unwrap().mesh(2).unwrap()
        };
        assert_eq!(a_first, b_first);
    }

    /// A UV sphere of radius `r` at `c`: `rows` bands of `2 rows` segments,
    /// faces numbered from `first`.
    fn sphere(c: [f32; 3], r: f32, rows: u32, first: u32) -> Solid {
        let cols = 2 * rows;
        let mut p = vec![[c[0], c[1], c[2] + r], [c[0], c[1], c[2] - r]];
        for i in 1..rows {
            let theta = std::f32::consts::PI * i as f32 / rows as f32;
            for j in 0..cols {
                let phi = std::f32::consts::TAU * j as f32 / cols as f32;
                let (st, ct) = theta.sin_cos();
                let (sp, cp) = phi.sin_cos();
                p.push([c[0] + r * st * cp, c[1] + r * st * sp, c[2] + r * ct]);
            }
        }
        let at = |i: u32, j: u32| 2 + (i - 1) * cols + j % cols;
        let mut tris = Vec::new();
        for j in 0..cols {
            tris.push([0, at(1, j), at(1, j + 1)]);
            tris.push([1, at(rows - 1, j + 1), at(rows - 1, j)]);
            for i in 1..rows - 1 {
                let (a, b) = (at(i, j), at(i, j + 1));
                let (c, d) = (at(i + 1, j), at(i + 1, j + 1));
                tris.push([a, c, d]);
                tris.push([a, d, b]);
            }
        }
        let faces: Vec<u32> = (first..first + tris.len() as u32).collect();
        Solid::new(&p, &tris, &faces, first, 2).unwrap()
    }

    #[test]
    fn a_result_is_the_same_on_one_thread_as_on_several() {
        // Above manifold's parallel thresholds (1e5 elements): two spheres
        // of 180k triangles. Serially built, this holds trivially; on TBB
        // it checks that manifold orders what its threads find.
        let a = sphere([0.0; 3], 1.0, 300, 0);
        let b = sphere([0.5, 0.3, 0.2], 1.0, 300, 1_000_000);
        for op in [Op::Union, Op::Subtract] {
            let one = boolean(&a, &b, op, 1).unwrap().mesh(1).unwrap();
            let four = boolean(&a, &b, op, 4).unwrap().mesh(4).unwrap();
            assert!(one.triangles.len() > 100_000);
            assert!(one == four, "{op:?} differs between 1 and 4 threads");
        }
    }

    #[test]
    fn built_on_tbb_where_the_test_run_installed_it() {
        // tools/test.sh installs libtbb-dev (tools/debian.sh): the booleans
        // it times must be parallel, unless oracles are skipped.
        let required = std::env::var_os("GEODE_SKIP_ORACLES").is_none_or(|v| v != "1")
            && std::env::var_os("GEODE_MANIFOLD_SERIAL").is_none();
        if required {
            assert!(
                parallel(),
                "manifold was built serially though TBB is required"
            );
        } else if !parallel() {
            eprintln!(
                "skipping: manifold is built serially (no libtbb-dev, or GEODE_MANIFOLD_SERIAL)"
            );
        }
    }

    #[test]
    fn overlapping_pieces_of_one_solid_union() {
        // Two unit cubes overlapping by half, as one mesh: 1.5 in volume
        // once unioned (2 counted twice before).
        let a = cube([0.0; 3], 1.0, 0).mesh(1).unwrap();
        let b = cube([0.5, 0.0, 0.0], 1.0, 100).mesh(1).unwrap();
        let mut positions = a.positions.clone();
        positions.extend(&b.positions);
        let off = a.positions.len() as u32;
        let mut triangles = a.triangles.clone();
        triangles.extend(b.triangles.iter().map(|t| t.map(|i| i + off)));
        let mut faces = a.faces.clone();
        faces.extend(&b.faces);
        let both = Solid::new(&positions, &triangles, &faces, 1, 2).unwrap();
        assert!((volume(&both.mesh(1).unwrap()) - 2.0).abs() < 1e-5);
        let one = union_pieces(&both, 2).unwrap().mesh(2).unwrap();
        assert!((volume(&one) - 1.5).abs() < 1e-5, "{}", volume(&one));
        assert!(one.faces.iter().all(|&f| f < 12 || (100..112).contains(&f)));
    }

    #[test]
    fn disjoint_solids_intersect_in_nothing() {
        let a = cube([0.0; 3], 1.0, 0);
        let b = cube([5.0; 3], 1.0, 12);
        let m = boolean(&a, &b, Op::Intersect, 2).unwrap().mesh(2).unwrap();
        assert!(m.triangles.is_empty());
    }
}
