//! File nodes: read a geometry file (keyed by its content hash) and write one.

use std::path::Path;

use geode_io::NoProgress;
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, Operator, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{geometry, input};

/// Expands `$HIP` (the folder of the network being cooked, set by the CLI as
/// Houdini does) so networks can refer to files beside them.
pub(crate) fn expand(path: &str) -> String {
    match std::env::var("HIP") {
        Ok(hip) => path.replace("$HIP", &hip),
        Err(_) => path.replace("$HIP", "."),
    }
}

struct File;
static FILE: NodeSpec = NodeSpec::new(
    "file",
    "File",
    "io",
    "Reads a geometry file (.obj, .stl, .ply, .gltf, .glb). `$HIP` in the path is the network file's folder. The file's content is part of the cache key: editing the file recooks the node.",
    &[],
    &[P::new("file", "File", T::File, D::Str(""), "Path of the file to read.")],
);
impl Operator for File {
    fn spec(&self) -> &'static NodeSpec {
        &FILE
    }
    fn cook(&self, ctx: &CookContext, _: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
        let path = expand(p.string("file")?);
        let g = geode_io::read(Path::new(&path), &NoProgress)
            .map_err(|e| ctx.param_error("file", e.to_string()))?;
        geometry(g)
    }
    fn key_extra(&self, p: &Params) -> Result<Option<u128>, CookError> {
        let path = expand(p.string("file")?);
        // An unreadable file gets no extra key: the cook reports the error.
        Ok(std::fs::read(path).ok().map(|b| geode_geo::hash_bytes(&b)))
    }
}

struct Write;
static WRITE: NodeSpec = NodeSpec::new(
    "write",
    "Write",
    "io",
    "Writes its input to a file (atomically) when it cooks, and passes the input through.",
    &[geometry_input("geometry")],
    &[P::new(
        "file",
        "File",
        T::File,
        D::Str(""),
        "Path to write; the extension picks the format (.obj, .stl, .ply, .glb, .usda).",
    )],
);
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
        let path = expand(p.string("file")?);
        geode_io::write(g, Path::new(&path), &NoProgress)
            .map_err(|e| ctx.param_error("file", e.to_string()))?;
        Ok(Value::Geometry(g.clone()))
    }
}

pub fn register(r: &mut Registry) {
    r.add(File);
    r.add(Write);
}
