//! `geode convert`: between geometry formats, and to and from OpenVDB
//! level sets as Houdini's Convert VDB and VDB from Polygons do: a `.vdb`
//! grid meshed at its own voxel size, a closed mesh sampled into a level
//! set. Both run the nodes a network would (`frep_file`, `polygonise`,
//! `frep_from_mesh`, `frep_write`), so they read, check and fail alike.

use crate::exit::{tagged, Exit};
use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Context, Result};
use geode_graph::{CookOptions, Document, Engine, Network};
use geode_op::{CancelToken, CookEnv, Value};
use serde_json::json;

/// What `geode convert` was asked.
#[derive(clap::Args)]
pub struct ConvertArgs {
    /// Input file (.obj, .stl, .ply, .gltf, .glb, .geo, .bgeo, .vdb).
    pub input: PathBuf,
    /// Output file (.obj, .stl, .ply, .glb, .usda, .geo, .bgeo, .vdb).
    pub output: PathBuf,
    /// Voxel edge of a .vdb written from a mesh, in model units (default: the longest side of its box / 256).
    #[arg(long, allow_negative_numbers = true)]
    pub voxel_size: Option<f64>,
    /// Voxels either side of the surface that hold distances in a .vdb written from a mesh.
    #[arg(long, default_value_t = 3.0, allow_negative_numbers = true)]
    pub half_width: f64,
    /// The float grid of a .vdb input to mesh (default: the first).
    #[arg(long, default_value = "")]
    pub grid: String,
    /// Adaptive output of a meshed .vdb grid: triangles merge while within this distance of its surface (model units; 0 keeps one cell a voxel).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub tolerance: f64,
}

/// Voxels along the longest side of a mesh's box, when no voxel size is given.
const DEFAULT_VOXELS: f64 = 256.0;

/// Points closer than this part of the box's longest side are one before
/// a mesh becomes a field.
const WELD: f64 = 1e-6;

/// The deepest octree meshing a grid (polygonise's own limit).
const DEEPEST: u32 = 12;

fn is_vdb(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("vdb"))
}

pub fn convert(args: &ConvertArgs) -> Result<()> {
    match (is_vdb(&args.input), is_vdb(&args.output)) {
        (false, false) => geometry_to_geometry(&args.input, &args.output),
        (true, false) => vdb_to_mesh(args),
        (false, true) => mesh_to_vdb(args),
        (true, true) => Err(tagged(
            Exit::Usage,
            anyhow!(
                "{} and {} are both .vdb files: convert one of them to or from a mesh",
                args.input.display(),
                args.output.display()
            ),
        )),
    }
}

fn geometry_to_geometry(input: &Path, output: &Path) -> Result<()> {
    let bar = crate::progress::Bar::new();
    let g = crate::read_geometry(input, &bar)?;
    geode_io::write(&g, output, &bar)?;
    eprintln!(
        "wrote {} ({} points, {} primitives)",
        output.display(),
        g.num_points(),
        g.num_prims()
    );
    Ok(())
}

/// A `.vdb` grid meshed over its active voxels, one cell a voxel (up to
/// 2^12 cells a side), closed where the band reaches the box.
fn vdb_to_mesh(args: &ConvertArgs) -> Result<()> {
    let bytes =
        geode_op::FileAccess::anywhere()
            .read(&args.input, geode_op::budget_from_env(), &|| false)?;
    let volumes = geode_io::vdb::read_vdb(&bytes, geode_op::budget_from_env(), &|| false)
        .with_context(|| args.input.display().to_string())?;
    let names: Vec<String> = volumes.iter().map(|v| format!("{:?}", v.name)).collect();
    let volume = volumes
        .iter()
        .find(|v| args.grid.is_empty() || v.name == args.grid)
        .ok_or_else(|| {
            tagged(
                Exit::Usage,
                anyhow!(
                    "{}: no float grid named {:?} (it has {})",
                    args.input.display(),
                    args.grid,
                    names.join(", ")
                ),
            )
        })?;
    let (lo, hi) = volume.active_bounds().ok_or_else(|| {
        anyhow!(
            "{}: grid {:?} has no active voxels",
            args.input.display(),
            volume.name
        )
    })?;
    let voxel = volume
        .transform
        .scale
        .iter()
        .fold(f64::INFINITY, |m, s| m.min(*s));
    // A voxel of margin: the surface never touches the box's side.
    let (min, max) = (
        volume.transform.to_world(lo).map(|x| x - voxel),
        volume.transform.to_world(hi).map(|x| x + voxel),
    );
    let longest = (0..3).map(|k| max[k] - min[k]).fold(0.0, f64::max);
    let depth = ((longest / voxel).log2().ceil() as u32).clamp(1, DEEPEST);
    let doc = json!({
        "geode": "network", "version": 1, "output": "mesh",
        "nodes": {
            "grid": {"type": "frep_file", "params": {"file": absolute(&args.input)?, "grid": volume.name}},
            "mesh": {"type": "polygonise", "inputs": ["grid"],
                     "params": {"min": min, "max": max, "depth": depth, "tolerance": args.tolerance}},
        }
    });
    let g = match cook(&doc, "/mesh", &args.input, false)? {
        Value::Geometry(g) => g,
        _ => bail!("polygonise gave no geometry"),
    };
    let bar = crate::progress::Bar::new();
    let g = geode_nodes::for_file(&g, &args.output)?;
    geode_io::write(&g, &args.output, &bar)?;
    eprintln!(
        "wrote {} ({} points, {} triangles; grid {:?} meshed at depth {depth}, {} cells a side)",
        args.output.display(),
        g.num_points(),
        g.num_prims(),
        volume.name,
        1u64 << depth
    );
    Ok(())
}

/// A closed mesh as a level set: its exact signed distance (sign by
/// winding number) sampled within the half width of the surface.
fn mesh_to_vdb(args: &ConvertArgs) -> Result<()> {
    let g = crate::read_geometry(&args.input, &crate::progress::Bar::new())?;
    let Some(bounds) = geode_geo::ops::bounds(&g) else {
        bail!("{}: no points to sample", args.input.display());
    };
    let (lo, hi) = (
        bounds.min.as_dvec3().to_array(),
        bounds.max.as_dvec3().to_array(),
    );
    let longest = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    let voxel = match args.voxel_size {
        Some(v) if v > 0.0 && v.is_finite() => v,
        Some(v) => {
            return Err(tagged(
                Exit::Usage,
                anyhow!("--voxel-size {v}: expected a positive number of model units"),
            ))
        }
        None if longest > 0.0 => longest / DEFAULT_VOXELS,
        None => bail!(
            "{}: every point is at one place: nothing to sample",
            args.input.display()
        ),
    };
    // The band reaches `half_width` voxels past the surface, and one more.
    let margin = (args.half_width + 1.0) * voxel;
    let doc = json!({
        "geode": "network", "version": 1, "output": "write",
        "nodes": {
            "part": {"type": "file", "params": {"file": absolute(&args.input)?}},
            // STL repeats every corner per triangle: welded, the mesh is closed.
            "welded": {"type": "fuse", "inputs": ["part"], "params": {"distance": WELD * longest}},
            "solid": {"type": "frep_from_mesh", "inputs": ["welded"]},
            "write": {"type": "frep_write", "inputs": ["solid"], "params": {
                "file": absolute(&args.output)?,
                "min": lo.map(|x| x - margin), "max": hi.map(|x| x + margin),
                "voxel_size": voxel, "half_width": args.half_width}},
        }
    });
    cook(&doc, "/write", &args.input, true)?;
    eprintln!(
        "wrote {} (a level set \"surface\" of {} at voxel size {voxel}, {} voxels either side)",
        args.output.display(),
        args.input.display(),
        args.half_width
    );
    Ok(())
}

fn absolute(path: &Path) -> Result<String> {
    Ok(std::path::absolute(path)?.to_string_lossy().into_owned())
}

/// Cooks `target` of a network built here, its problems reported as the
/// file's (`about`), its warnings printed.
fn cook(doc: &serde_json::Value, target: &str, about: &Path, writes: bool) -> Result<Value> {
    let doc = Document::from_json(&doc.to_string()).map_err(|e| anyhow!("{e}"))?;
    let net = Network::load(&doc, &geode_nodes::registry())
        .map_err(|errors| crate::cook::problems(about, &errors))?;
    let engine = Engine::new(net, crate::disk_cache::cook_cache()?);
    let cancel = CancelToken::new();
    {
        let c = cancel.clone();
        let _ = ctrlc::set_handler(move || c.cancel());
    }
    let opts = CookOptions {
        frame: 1.0,
        cancel: cancel.clone(),
        progress: None,
        env: CookEnv::from_process(),
        writes,
    };
    let result = engine.cook(target, &opts).map_err(|errors| {
        let kind = Exit::of_cook(&errors);
        if kind == Exit::Interrupted {
            return tagged(kind, anyhow!("interrupted: nothing was written"));
        }
        let lines: Vec<String> = errors.iter().map(|e| e.to_string()).collect();
        tagged(kind, anyhow!("{}: {}", about.display(), lines.join("; ")))
    })?;
    for e in &result.events {
        for w in e.warnings.iter() {
            eprintln!("{}: warning: {w}", about.display());
        }
    }
    Ok(result.value)
}
