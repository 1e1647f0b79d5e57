//! The `python_input` node: geometry a host process (Python) holds in memory, named by its content hash.

use geode_op::{
    CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P, ParamType as T, Params,
    Registry, Value,
};

const HELD_GEOMETRY: P = P::new(
    "geometry",
    "Geometry",
    T::String,
    D::Str(""),
    "The content hash (32 hex digits) of a geometry the host process holds: Python sets it when a `geode.Geometry` is given as this parameter's value.",
)
.not_animatable();

static PYTHON_INPUT: NodeSpec = NodeSpec::new(
    "python_input",
    "Python Input",
    "io",
    "Geometry made in Python (`geode.Geometry.from_arrays`, or any cooked geometry) fed into the network. The parameter is the geometry's content hash, so the cook is a function of its key like every other; the geometry itself lives in the Python process that cooks the network.",
    &[],
    &[HELD_GEOMETRY],
);

/// The hash a `geometry` parameter names.
pub fn parse_hash(text: &str) -> Option<u128> {
    let t = text.trim();
    (t.len() == 32 && t.bytes().all(|b| b.is_ascii_hexdigit()))
        .then(|| u128::from_str_radix(t, 16).ok())
        .flatten()
}

/// How a `geometry` parameter writes a content hash.
pub fn format_hash(hash: u128) -> String {
    format!("{hash:032x}")
}

fn cook_python_input(
    ctx: &CookContext,
    _: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let text = p.string(&HELD_GEOMETRY)?;
    if text.trim().is_empty() {
        return Err(ctx.param_error(
            &HELD_GEOMETRY,
            "names no geometry: set it from Python (node.parm(\"geometry\").set(geo))",
        ));
    }
    let hash = parse_hash(text).ok_or_else(|| {
        ctx.param_error(
            &HELD_GEOMETRY,
            format!("`{text}` is not a geometry's content hash (32 hex digits)"),
        )
    })?;
    let g = ctx.env.held.get(hash).ok_or_else(|| {
        ctx.param_error(
            &HELD_GEOMETRY,
            format!("no geometry {text} is held by this process: python_input reads geometry a Python session hands to the cook, and cannot cook from the command line or the studio"),
        )
    })?;
    Ok(Value::Geometry(g.clone()))
}

pub fn register(r: &mut Registry) {
    r.node(&PYTHON_INPUT, cook_python_input);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_hash_reads_back_as_written_and_nothing_else_reads() {
        let h = 0x0123_4567_89ab_cdef_fedc_ba98_7654_3210u128;
        assert_eq!(parse_hash(&format_hash(h)), Some(h));
        assert_eq!(parse_hash(&format_hash(1)), Some(1));
        for bad in [
            "",
            "12",
            "g0000000000000000000000000000000",
            "+123456789abcdef0123456789abcdef",
        ] {
            assert_eq!(parse_hash(bad), None, "{bad}");
        }
    }
}
