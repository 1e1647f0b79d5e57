//! The frep_file node: a field read from a program file, fidget's `.vm`
//! SSA text or a HyperFun `.hf` program. A 2D `.vm` program (no `var-z`)
//! is a prism along z: polygonise's bounds give its height.

use geode_op::{
    CookContext, CookError, FnOperator, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, PortType, Registry, Value,
};

const FREP_FILE_FILE: P = P::new(
    "file",
    "File",
    T::File,
    D::Str(""),
    "A fidget `.vm` program (negative inside in fidget; geode flips it to positive inside) or a HyperFun `.hf` program.",
);

const FREP_FILE_OBJECT: P = P::new(
    "object",
    "Object",
    T::String,
    D::Str(""),
    "For a HyperFun program: the object to read (empty: the last one defined). Its parameter array `a` is all zeros.",
);

static FREP_FILE: NodeSpec = NodeSpec::new(
    "frep_file",
    "FRep File",
    "frep",
    "Reads a field from a fidget `.vm` program or a HyperFun `.hf` program (its language, compiled to a field: arrays, `if`, `while` with conditions known before meshing, the set operations and the FRep library). A `.vm` program without `var-z` is a 2D shape, extruded along z (the meshing bounds give its height).",
    &[],
    &[FREP_FILE_FILE, FREP_FILE_OBJECT],
)
.output(PortType::Field);

fn cook_frep_file(
    ctx: &CookContext,
    _inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let path = p.string(&FREP_FILE_FILE)?;
    if path.is_empty() {
        return Err(ctx.param_error("file", "names no file to read"));
    }
    let extension = path.to_lowercase();
    let hyperfun = extension.ends_with(".hf");
    if !hyperfun && !extension.ends_with(".vm") {
        return Err(ctx.param_error(
            "file",
            format!("{path}: expected a fidget .vm or a HyperFun .hf program"),
        ));
    }
    let text = crate::util::text_file(ctx, "file", path)?;
    ctx.check()?;
    let field = if hyperfun {
        let object = p.string(&FREP_FILE_OBJECT)?;
        let object = (!object.is_empty()).then_some(object);
        geode_frep::parse_hf(&text, object, &[]).map_err(|e| {
            ctx.param_error("file", format!("{path}, {e}"))
                .with_source(e)
        })?
    } else {
        geode_frep::vm::parse_vm(&text).map_err(|e| {
            ctx.param_error("file", format!("{path}, {e}"))
                .with_source(e)
        })?
    };
    Ok(Value::Field(field))
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
