//! File nodes: read a geometry file (keyed by its content hash) and write one.

use std::path::Path;

use geode_io::NoProgress;
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, Operator, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{geometry, input};

/// The content hash of a file a node reads, for its cache key; an unreadable
/// file gets none (the cook reports the error).
pub(crate) fn content_key(path: &str) -> Option<u128> {
    std::fs::read(path).ok().map(|b| geode_geo::hash_bytes(&b))
}

struct File;
static FILE: NodeSpec = NodeSpec::new(
    "file",
    "File",
    "io",
    "Reads a geometry file (.obj, .stl, .ply, .gltf, .glb). `$HIP` in the path is the network file's folder, `$F`/`$F4`/`$FF` the frame. The file's content is part of the cache key: editing the file recooks the node.",
    &[],
    &[P::new("file", "File", T::File, D::Str(""), "Path of the file to read.")],
);
impl Operator for File {
    fn spec(&self) -> &'static NodeSpec {
        &FILE
    }
    fn cook(&self, ctx: &CookContext, _: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
        let path = p.string("file")?;
        let g = geode_io::read(Path::new(path), &NoProgress).map_err(|e| ctx.io("file", e))?;
        geometry(g)
    }
    fn key_extra(&self, p: &Params) -> Result<Option<u128>, CookError> {
        Ok(content_key(p.string("file")?))
    }
}

struct Write;
static WRITE: NodeSpec = NodeSpec::new(
    "write",
    "Write",
    "io",
    "Writes its input to a file (atomically) every time it cooks, and passes the input through. `$HIP` in the path is the network file's folder, `$F`/`$F4`/`$FF` the frame, so a cook over frames writes one file per frame. A write is an output, never served from the cache.",
    &[geometry_input("geometry")],
    &[P::new(
        "file",
        "File",
        T::File,
        D::Str(""),
        "Path to write; the extension picks the format (.obj, .stl, .ply, .glb, .usda).",
    )],
)
.writes(&["file"]);
impl Operator for Write {
    fn spec(&self) -> &'static NodeSpec {
        &WRITE
    }
    fn cook(
        &self,
        ctx: &CookContext,
        inputs: &[Option<Value>],
        p: &Params,
    ) -> Result<Value, CookError> {
        let g = input(ctx, inputs, 0)?;
        let path = p.string("file")?;
        if path.is_empty() {
            return Err(ctx.param_error("file", "names no file to write"));
        }
        ctx.check()?;
        geode_io::write(g, Path::new(path), &NoProgress).map_err(|e| ctx.io("file", e))?;
        Ok(Value::Geometry(g.clone()))
    }
}

pub fn register(r: &mut Registry) {
    r.add(File);
    r.add(Write);
}
