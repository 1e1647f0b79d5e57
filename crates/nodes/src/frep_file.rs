//! The frep_file node: a field read from a program file, fidget's `.vm`
//! SSA text or a HyperFun `.hf` program, or from an OpenVDB `.vdb` volume.
//! A 2D `.vm` program (no `var-z`) is a prism along z: polygonise's bounds
//! give its height.

use geode_op::{
    CookContext, CookError, FnOperator, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, PortType, Registry, Value,
};

const FREP_FILE_FILE: P = P::new(
    "file",
    "File",
    T::File,
    D::Str(""),
    "A fidget `.vm` program (negative inside in fidget; geode flips it to positive inside), a HyperFun `.hf` program or an OpenVDB `.vdb` file.",
);

const FREP_FILE_OBJECT: P = P::new(
    "object",
    "Object",
    T::String,
    D::Str(""),
    "For a HyperFun program: the object to read (empty: the last one defined). Its parameter array `a` is all zeros.",
);

const FREP_FILE_GRID: P = P::new(
    "grid",
    "Grid",
    T::String,
    D::Str(""),
    "For a `.vdb` file: the float grid to read (empty: the first).",
);

const FREP_FILE_ISO: P = P::new(
    "iso",
    "Isovalue",
    T::Float,
    D::Float(0.5),
    "For a `.vdb` grid that is not a level set (a fog volume): the value where its surface lies; the field is the value less this, inside where it is larger. A level set's surface is at 0.",
);

static FREP_FILE: NodeSpec = NodeSpec::new(
    "frep_file",
    "FRep File",
    "frep",
    "Reads a field from a fidget `.vm` program, a HyperFun `.hf` program (its language, compiled to a field: arrays, `if`, `while` with conditions known before meshing, the set operations and the FRep library) or a float grid of an OpenVDB `.vdb` file (Houdini's, Blender's, OpenVDB's: any compression, half floats, tiles). A `.vm` program without `var-z` is a 2D shape, extruded along z (the meshing bounds give its height). A level set reads as its negated distance (positive inside, as every geode field); other grids read as their values less the isovalue (a fog volume: inside where its density passes it), trilinear between voxel centres. The voxel transform may scale and translate; rotated or sheared grids are refused.",
    &[],
    &[FREP_FILE_FILE, FREP_FILE_OBJECT, FREP_FILE_GRID, FREP_FILE_ISO],
)
.output(PortType::Field);

fn cook_frep_file(
    ctx: &CookContext,
    _inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let path = p.string(&FREP_FILE_FILE)?;
    if path.is_empty() {
        return Err(ctx.param_error(&FREP_FILE_FILE, "names no file to read"));
    }
    let extension = path.to_lowercase();
    if extension.ends_with(".vdb") {
        return read_vdb(
            ctx,
            path,
            p.string(&FREP_FILE_GRID)?,
            p.float(&FREP_FILE_ISO)?,
        );
    }
    let hyperfun = extension.ends_with(".hf");
    if !hyperfun && !extension.ends_with(".vm") {
        return Err(ctx.param_error(
            &FREP_FILE_FILE,
            format!(
                "{path}: expected a fidget .vm or a HyperFun .hf program, or an OpenVDB .vdb file"
            ),
        ));
    }
    let text = crate::util::text_file(ctx, &FREP_FILE_FILE, path)?;
    ctx.check()?;
    let field = if hyperfun {
        let object = p.string(&FREP_FILE_OBJECT)?;
        let object = (!object.is_empty()).then_some(object);
        geode_frep::parse_hf(&text, object, &[]).map_err(|e| {
            ctx.param_error(&FREP_FILE_FILE, format!("{path}, {e}"))
                .with_source(e)
        })?
    } else {
        geode_frep::vm::parse_vm(&text).map_err(|e| {
            ctx.param_error(&FREP_FILE_FILE, format!("{path}, {e}"))
                .with_source(e)
        })?
    };
    Ok(Value::Field(field))
}

/// A float grid of a `.vdb` file as a field.
fn read_vdb(ctx: &CookContext, path: &str, grid: &str, iso: f64) -> Result<Value, CookError> {
    use geode_io::vdb::VdbError;
    use geode_io::{IoError, Position};
    ctx.readable_file(&FREP_FILE_FILE, path)?;
    let bytes = ctx.read_file(&FREP_FILE_FILE, path)?;
    let cancel = || ctx.cancel.is_cancelled();
    let volumes = geode_io::vdb::read_vdb(&bytes, ctx.env.memory_budget, &cancel).map_err(|e| {
        let path = std::path::PathBuf::from(path);
        let e = match e {
            VdbError::Malformed { offset, message } => IoError::Parse {
                path,
                pos: Some(Position::Byte(offset)),
                message,
            },
            VdbError::TooLarge { .. } => IoError::TooLarge {
                path,
                message: e.to_string(),
            },
            VdbError::Cancelled => IoError::Cancelled { path },
        };
        crate::file::io_error(ctx, &FREP_FILE_FILE, e)
    })?;
    let names: Vec<String> = volumes.iter().map(|v| format!("{:?}", v.name)).collect();
    let volume = if grid.is_empty() {
        volumes.into_iter().next()
    } else {
        volumes.into_iter().find(|v| v.name == grid)
    };
    let Some(volume) = volume else {
        return Err(ctx.param_error(
            &FREP_FILE_GRID,
            format!(
                "{path} has no float grid named {grid:?} (it has {})",
                names.join(", ")
            ),
        ));
    };
    warn_of_values(ctx, &volume, iso);
    Ok(Value::Field(geode_frep::Field::volume(
        geode_frep::VolumeField::with_iso(volume, iso),
    )))
}

/// Warnings for what reads unlike its file: a grid that is not a level
/// set, one without active voxels, voxels that are not numbers.
fn warn_of_values(ctx: &CookContext, volume: &geode_geo::volume::SparseVolume, iso: f64) {
    if volume.class != geode_geo::volume::VolumeClass::LevelSet {
        ctx.warn(format!(
            "grid {:?} is not a level set: its surface is where its values pass the isovalue {iso}, and its values are not distances",
            volume.name
        ));
    }
    if volume.active_voxel_count() == 0 {
        ctx.warn(format!("grid {:?} has no active voxels", volume.name));
    }
    let bad = volume
        .leaves()
        .iter()
        .flat_map(|l| l.values.iter())
        .chain(volume.tiles().iter().map(|t| &t.value))
        .filter(|v| !v.is_finite())
        .count();
    if bad > 0 {
        ctx.warn(format!(
            "grid {:?} holds {bad} voxels or tiles that are NaN or infinite: the field is not a number near them",
            volume.name
        ));
    }
}

fn key_frep_file(ctx: &geode_op::KeyContext, p: &Params) -> Result<Option<u128>, CookError> {
    // The program's text is part of the key: editing the file recooks.
    Ok(ctx.file_hash(p.string(&FREP_FILE_FILE)?))
}

pub fn register(r: &mut Registry) {
    r.add(FnOperator {
        spec: &FREP_FILE,
        cook: cook_frep_file,
        key_extra: Some(key_frep_file),
    });
}
