//! Fields as sparse volumes: `frep_volume` samples a field into a
//! narrow-band level set and hands it on as a field (a costly field, a huge
//! mesh's, cached as voxels), and `frep_write` writes that level set as an
//! OpenVDB `.vdb` file (`frep_file` reads one back).

use geode_frep::{Field, SampleError, SampleOptions, SamplePlan, VolumeField};
use geode_geo::volume::SparseVolume;
use geode_op::{
    CookContext, CookError, ErrorKind, NodeSpec, ParamDefault as D, ParamSpec as P, ParamType as T,
    Params, PortType, Registry, Value,
};

use crate::frep::{field_input, FIELD_IN};
use crate::frep_polygonise::{BOUNDS_MAX, BOUNDS_MIN};

const VOXEL_SIZE: P = P::new(
    "voxel_size",
    "Voxel size",
    T::Float,
    D::Float(0.02),
    "Edge of a voxel, in model units; voxel centres sit at its multiples (index 0 at the origin, as Houdini's VDB from Polygons places them).",
)
.range(1e-6, 1e6);
const HALF_WIDTH: P = P::new(
    "half_width",
    "Half width",
    T::Float,
    D::Float(3.0),
    "Voxels on each side of the surface that hold distances (OpenVDB's default is 3); farther voxels hold plus or minus this distance.",
)
.range(1.0, 64.0);
const GRID_NAME: P = P::new(
    "name",
    "Grid name",
    T::String,
    D::Str("surface"),
    "Name of the grid (Houdini and Blender name a level set `surface`).",
);

static VOLUME: NodeSpec = NodeSpec::new(
    "frep_volume",
    "FRep Volume",
    "frep",
    "Samples a field into a narrow-band level set (OpenVDB's kind of volume: signed distances on the voxels within the half width of the surface, the inside filled by tiles) over the box, and gives it back as a field: trilinear between voxel centres, positive inside. Inside and outside come from the field itself, distances from its distance estimate (exact for meshes, primitives and level sets; a field that is not a distance, such as a gyroid, gets the estimate's values). Leaves are whole blocks of 8 voxels, so the band may reach a few voxels past the box. A field that is slow to evaluate (a huge mesh's, a deep blend) costs one sampling, then a lookup per point; offsets within the half width stay exact to the voxels.",
    &[FIELD_IN],
    &[BOUNDS_MIN, BOUNDS_MAX, VOXEL_SIZE, HALF_WIDTH, GRID_NAME],
)
.output(PortType::Field);

const WRITE_FILE: P = P::new(
    "file",
    "File",
    T::File,
    D::Str(""),
    "The `.vdb` file to write (atomically). `$HIP` is the network file's folder, `$F`/`$F4` the frame.",
);
const WRITE_ZIP: P = P::new(
    "compress",
    "Compress",
    T::Toggle,
    D::Toggle(false),
    "Store the voxels zlib-compressed (every OpenVDB reads it). Off by default, as OpenVDB writes level sets: a narrow band's distances barely compress (about 10%) and zlib costs several times the write.",
);

static WRITE: NodeSpec = NodeSpec::new(
    "frep_write",
    "FRep Write VDB",
    "frep",
    "Writes a field as an OpenVDB `.vdb` file: a float grid of level-set class (signed distances, negative inside, as OpenVDB, Houdini and Blender expect), sampled over the box at the voxel size within the half width of the surface, with the voxel transform; passes the field on. A level set read from a `.vdb` file (frep_file) and written at its own voxel size keeps its voxel values, where its voxels sit at multiples of the voxel size (OpenVDB's and Houdini's default). A write is an output, never served from the cache.",
    &[FIELD_IN],
    &[
        WRITE_FILE,
        BOUNDS_MIN,
        BOUNDS_MAX,
        VOXEL_SIZE,
        HALF_WIDTH,
        GRID_NAME,
        WRITE_ZIP,
    ],
)
.writes(&[&WRITE_FILE])
.output(PortType::Field);

/// Samples the node's field over its box, refusing before allocation a
/// band the memory budget cannot hold.
fn sample(ctx: &CookContext, f: &Field, p: &Params) -> Result<SparseVolume, CookError> {
    let options = SampleOptions {
        min: p.vector::<3>(&BOUNDS_MIN)?,
        max: p.vector::<3>(&BOUNDS_MAX)?,
        voxel_size: p.float(&VOXEL_SIZE)?,
        half_width: p.float(&HALF_WIDTH)?,
        memory_budget: ctx.env.memory_budget,
    };
    warn_of_options(ctx, f, &options);
    let cancel = || ctx.cancel.is_cancelled();
    let plan = SamplePlan::new(f, options, &cancel).map_err(|e| sample_error(ctx, e))?;
    ctx.reserve(
        &VOXEL_SIZE,
        plan.bytes() as f64,
        &format!(
            "a narrow band of {} leaves of voxels",
            crate::util::count_text(plan.leaf_count() as f64)
        ),
    )?;
    let volume = plan
        .sample(f, p.string(&GRID_NAME)?, &cancel)
        .map_err(|e| sample_error(ctx, e))?;
    if volume.leaves().is_empty() {
        ctx.warn("the field has no surface in the box: the volume is all inside or all outside");
    }
    Ok(volume)
}

/// Warnings for a sampling that cannot show its field: a box narrower than
/// two voxels, or a level set asked for distances beyond its own band
/// (past it, its values are its background, not distances).
fn warn_of_options(ctx: &CookContext, f: &Field, o: &SampleOptions) {
    if (0..3).any(|k| o.max[k] - o.min[k] < 2.0 * o.voxel_size) {
        ctx.warn(format!(
            "the box spans fewer than two voxels of {} along an axis: the volume cannot show the field's shape",
            o.voxel_size
        ));
    }
    let band = o.half_width * o.voxel_size;
    if let Some(own) = level_set_band(f) {
        if own < band {
            ctx.warn(format!(
                "the input level set holds distances only within {own} of its surface: voxels farther than that (up to the half width's {band}) hold {own}, not their distance"
            ));
        }
    }
}

/// How far from its surface a field that is a level set's (read or
/// sampled) holds distances: its background.
pub(crate) fn level_set_band(f: &Field) -> Option<f64> {
    let geode_frep::Node::Dataset(set, _) = f.node() else {
        return None;
    };
    let geode_frep::Dataset::Volume(v) = set.as_ref() else {
        return None;
    };
    (v.volume().class == geode_geo::volume::VolumeClass::LevelSet)
        .then_some(v.volume().background as f64)
}

/// Warns when an offset or shell reaches past the band of the level set
/// it applies to: beyond it the values are the background, and the
/// surface there is lost or everywhere.
pub(crate) fn warn_beyond_band(ctx: &CookContext, f: &Field, reach: f64) {
    if let Some(band) = level_set_band(f) {
        if reach.abs() >= band {
            ctx.warn(format!(
                "{reach} reaches past the band of the level set it applies to ({band}): beyond the band its values are the background, not distances, so the surface there is lost; sample it with a wider half width (frep_volume) first"
            ));
        }
    }
}

fn sample_error(ctx: &CookContext, e: SampleError) -> CookError {
    match e {
        SampleError::Cancelled => CookError::cancelled(ctx.path),
        SampleError::Bounds => ctx.param_error(&BOUNDS_MAX, e.to_string()),
        SampleError::HalfWidth => ctx.param_error(&HALF_WIDTH, e.to_string()),
        SampleError::VoxelSize | SampleError::TooManyVoxels(_) => {
            ctx.param_error(&VOXEL_SIZE, e.to_string())
        }
        SampleError::TooLarge { .. } => {
            CookError::new(ctx.path, ErrorKind::Resource, e.to_string())
                .at_param("voxel_size")
                .with_source(e)
        }
    }
}

fn cook_volume(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let f = field_input(ctx, inputs, 0)?;
    let volume = sample(ctx, f, p)?;
    Ok(Value::Field(Field::volume(VolumeField::new(volume))))
}

fn cook_write(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let f = field_input(ctx, inputs, 0)?;
    let path = p.string(&WRITE_FILE)?;
    if path.is_empty() {
        return Err(ctx.param_error(&WRITE_FILE, "names no file to write"));
    }
    if !path.to_lowercase().ends_with(".vdb") {
        return Err(ctx.param_error(&WRITE_FILE, format!("{path}: expected a .vdb file")));
    }
    let real = ctx.writable_file(&WRITE_FILE, path)?;
    let volume = sample(ctx, f, p)?;
    ctx.check()?;
    let compression = if p.toggle(&WRITE_ZIP)? {
        geode_io::vdb::VdbCompression::Zip
    } else {
        geode_io::vdb::VdbCompression::None
    };
    let bytes = geode_io::vdb::write_vdb(&[&volume], compression);
    geode_io::write_atomic(&real, |w| {
        w.write_all(&bytes)
            .map_err(|e| geode_io::IoError::os(&real, e))
    })
    .map_err(|e| crate::file::io_error(ctx, &WRITE_FILE, e))?;
    Ok(Value::Field(f.clone()))
}

pub fn register(r: &mut Registry) {
    r.node(&VOLUME, cook_volume);
    r.node(&WRITE, cook_write);
}
