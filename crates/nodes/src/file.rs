//! File nodes: read a geometry file (keyed by its content hash) and write one.

use std::path::Path;

use geode_op::{
    geometry_input, CookContext, CookError, ErrorKind, FnOperator, KeyContext, NodeSpec,
    ParamDefault as D, ParamSpec as P, ParamType as T, Params, Registry, Value,
};

use crate::util::{geometry, input};

/// Hands a cook's cancellation and progress to geode-io's readers and writers.
pub(crate) struct CookProgress<'a, 'c> {
    ctx: &'a CookContext<'c>,
    total: std::sync::atomic::AtomicU64,
}

impl<'a, 'c> CookProgress<'a, 'c> {
    pub fn new(ctx: &'a CookContext<'c>) -> Self {
        CookProgress {
            ctx,
            total: 0.into(),
        }
    }
}

impl geode_io::Progress for CookProgress<'_, '_> {
    fn start(&self, _: &str, total: u64) {
        self.total
            .store(total.max(1), std::sync::atomic::Ordering::Relaxed);
    }
    fn set(&self, done: u64) {
        let total = self.total.load(std::sync::atomic::Ordering::Relaxed).max(1);
        self.ctx.progress(done as f32 / total as f32);
    }
    fn cancelled(&self) -> bool {
        self.ctx.cancel.is_cancelled()
    }
    fn memory_budget(&self) -> u64 {
        self.ctx.env.memory_budget
    }
    fn warn(&self, message: &str) {
        self.ctx.warn(message);
    }
}

/// A file error as a cook error of the right kind: cancelled, over the
/// memory budget, or an I/O failure blamed on the file parameter.
pub(crate) fn io_error(ctx: &CookContext, param: &P, e: geode_io::IoError) -> CookError {
    match e {
        geode_io::IoError::Cancelled { .. } => CookError::cancelled(ctx.path),
        geode_io::IoError::TooLarge { .. } => {
            CookError::new(ctx.path, ErrorKind::Resource, e.to_string())
                .at_param(param.name)
                .with_source(e)
        }
        e => ctx.io(param, e),
    }
}

const FILE_FILE: P = P::new(
    "file",
    "File",
    T::File,
    D::Str(""),
    "Path of the file to read.",
);

static FILE: NodeSpec = NodeSpec::new(
    "file",
    "File",
    "io",
    "Reads a geometry file (.obj, .stl, .ply, .gltf, .glb, Houdini's .geo and .bgeo). `$HIP` in the path is the network file's folder, `$F`/`$F4`/`$FF` the frame. The file's content is part of the cache key: editing the file recooks the node.",
    &[],
    &[
        FILE_FILE,
    ],
);

fn cook_file(ctx: &CookContext, _: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let path = p.string(&FILE_FILE)?;
    if path.is_empty() {
        return Err(ctx.param_error(&FILE_FILE, "names no file to read"));
    }
    // Where first, then what: a file the studio may not read is refused
    // before its name is judged.
    ctx.readable_file(&FILE_FILE, path)?;
    let format =
        geode_io::read_format(Path::new(path)).map_err(|e| io_error(ctx, &FILE_FILE, e))?;
    let bytes = ctx.read_file(&FILE_FILE, path)?;
    let g = geode_io::read_bytes(&bytes, format, Path::new(path), &CookProgress::new(ctx))
        .map_err(|e| io_error(ctx, &FILE_FILE, e))?;
    geometry(g)
}

fn key_file(ctx: &KeyContext, p: &Params) -> Result<Option<u128>, CookError> {
    Ok(ctx.file_hash(p.string(&FILE_FILE)?))
}

const WRITE_FILE: P = P::new(
    "file",
    "File",
    T::File,
    D::Str(""),
    "Path to write; the extension picks the format (.obj, .stl, .ply, .glb, .usda, .geo, .bgeo).",
);

static WRITE: NodeSpec = NodeSpec::new(
    "write",
    "Write",
    "io",
    "Writes its input to a file (atomically) every time it cooks, and passes the input through. `$HIP` in the path is the network file's folder, `$F`/`$F4`/`$FF` the frame, so a cook over frames writes one file per frame. A write is an output, never served from the cache.",
    &[geometry_input("geometry")],
    &[
        WRITE_FILE,
    ],
)
.writes(&[&WRITE_FILE]);

fn cook_write(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let path = p.string(&WRITE_FILE)?;
    if path.is_empty() {
        return Err(ctx.param_error(&WRITE_FILE, "names no file to write"));
    }
    let real = ctx.writable_file(&WRITE_FILE, path)?;
    ctx.check()?;
    let progress = CookProgress::new(ctx);
    geode_io::write_limited(g, &real, &progress, ctx.env.memory_budget)
        .map_err(|e| io_error(ctx, &WRITE_FILE, e))?;
    Ok(Value::Geometry(g.clone()))
}

pub fn register(r: &mut Registry) {
    r.add(FnOperator {
        spec: &FILE,
        cook: cook_file,
        key_extra: Some(key_file),
    });
    r.node(&WRITE, cook_write);
}
