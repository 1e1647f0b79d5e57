//! The wrangle library's signatures: one row per form of each function the
//! resolver in `calls.rs` accepts, with argument names and types, the
//! return type and a one-line summary, for editors' completion and help.
//!
//! The table is checked against the resolver (tests below): its names are
//! exactly `calls::LIBRARY`, the only names the resolver accepts, and every
//! row compiles when called with its argument types (optional arguments
//! left out one by one, a variadic last argument repeated) and gives its
//! return type.

use crate::ty::{Elem, Ty};

/// One form of a library function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Signature {
    pub name: &'static str,
    /// What the call gives; `Void` for calls used as statements.
    pub ret: Ty,
    /// Argument types and names, in order.
    pub args: &'static [(Ty, &'static str)],
    /// How many trailing arguments may be left out.
    pub optional: usize,
    /// Whether the last argument may be repeated.
    pub variadic: bool,
    pub summary: &'static str,
}

impl Signature {
    /// The form as VEX documents it: `float fit01(float x, float nmin, float nmax)`,
    /// optional arguments in brackets, a repeatable last one followed by `...`.
    pub fn display(&self) -> String {
        let required = self.args.len() - self.optional;
        let mut text = format!("{} {}(", self.ret, self.name);
        for (k, (ty, name)) in self.args.iter().enumerate() {
            let sep = if k == 0 { "" } else { ", " };
            if k >= required {
                text.push_str(&format!("[{sep}{ty} {name}]"));
            } else {
                text.push_str(&format!("{sep}{ty} {name}"));
            }
        }
        if self.variadic {
            text.push_str(", ...");
        }
        text.push(')');
        text
    }
}

const I: Ty = Ty::Int;
const F: Ty = Ty::Float;
const V2: Ty = Ty::Vec2;
const V: Ty = Ty::Vec3;
const V4: Ty = Ty::Vec4;
const M3: Ty = Ty::Mat3;
const M4: Ty = Ty::Mat4;
const S: Ty = Ty::Str;
const VOID: Ty = Ty::Void;
const IA: Ty = Ty::Array(Elem::Int);
const FA: Ty = Ty::Array(Elem::Float);
const SA: Ty = Ty::Array(Elem::Str);

const fn sig(
    name: &'static str,
    ret: Ty,
    args: &'static [(Ty, &'static str)],
    summary: &'static str,
) -> Signature {
    Signature {
        name,
        ret,
        args,
        optional: 0,
        variadic: false,
        summary,
    }
}

/// A form whose last `n` arguments may be left out.
const fn opt(s: Signature, n: usize) -> Signature {
    Signature { optional: n, ..s }
}

/// A form whose last argument may repeat.
const fn many(s: Signature) -> Signature {
    Signature {
        variadic: true,
        ..s
    }
}

/// Every form of every library function, grouped as docs/wrangle.md lists them.
pub fn signatures() -> &'static [Signature] {
    SIGNATURES
}

#[rustfmt::skip]
static SIGNATURES: &[Signature] = &[
    // Math: per component on vectors and matrices.
    sig("abs", F, &[(F, "x")], "Absolute value; ints stay ints, vectors per component."),
    sig("floor", F, &[(F, "x")], "Largest integer not above x (per component)."),
    sig("ceil", F, &[(F, "x")], "Smallest integer not below x (per component)."),
    sig("frac", F, &[(F, "x")], "Fractional part, x - floor(x) (per component)."),
    sig("rint", F, &[(F, "x")], "Rounds to the nearest integer (per component)."),
    sig("trunc", F, &[(F, "x")], "Drops the fractional part, towards zero (per component)."),
    sig("sqrt", F, &[(F, "x")], "Square root (per component)."),
    sig("exp", F, &[(F, "x")], "e raised to x (per component)."),
    sig("log", F, &[(F, "x")], "Natural logarithm (per component)."),
    sig("log10", F, &[(F, "x")], "Base-10 logarithm (per component)."),
    sig("sin", F, &[(F, "radians")], "Sine (per component)."),
    sig("cos", F, &[(F, "radians")], "Cosine (per component)."),
    sig("tan", F, &[(F, "radians")], "Tangent (per component)."),
    sig("asin", F, &[(F, "x")], "Arc sine, in radians (per component)."),
    sig("acos", F, &[(F, "x")], "Arc cosine, in radians (per component)."),
    sig("atan", F, &[(F, "x")], "Arc tangent, in radians (per component)."),
    sig("atan", F, &[(F, "y"), (F, "x")], "Angle of the point (x, y), in radians: atan2."),
    sig("atan2", F, &[(F, "y"), (F, "x")], "Angle of the point (x, y), in radians."),
    sig("sinh", F, &[(F, "x")], "Hyperbolic sine (per component)."),
    sig("cosh", F, &[(F, "x")], "Hyperbolic cosine (per component)."),
    sig("tanh", F, &[(F, "x")], "Hyperbolic tangent (per component)."),
    sig("radians", F, &[(F, "degrees")], "Degrees to radians (per component)."),
    sig("degrees", F, &[(F, "radians")], "Radians to degrees (per component)."),
    sig("sign", F, &[(F, "x")], "-1, 0 or 1 by the sign of x (per component)."),
    sig("pow", F, &[(F, "base"), (F, "exponent")], "base raised to exponent; a vector base takes a float or a vector exponent."),
    many(sig("min", F, &[(F, "a"), (F, "b")], "The smallest argument (ints stay ints, vectors per component).")),
    sig("min", F, &[(V, "v")], "The smallest component of a vector."),
    many(sig("max", F, &[(F, "a"), (F, "b")], "The largest argument (ints stay ints, vectors per component).")),
    sig("max", F, &[(V, "v")], "The largest component of a vector."),
    sig("clamp", F, &[(F, "x"), (F, "lo"), (F, "hi")], "x limited to [lo, hi] (ints stay ints, vectors per component)."),
    sig("lerp", F, &[(F, "a"), (F, "b"), (F, "t")], "Linear blend: a at t = 0, b at t = 1."),
    sig("lerp", V, &[(V, "a"), (V, "b"), (F, "t")], "Linear blend of vectors: a at t = 0, b at t = 1."),
    sig("fit", F, &[(F, "x"), (F, "omin"), (F, "omax"), (F, "nmin"), (F, "nmax")], "x mapped from [omin, omax] to [nmin, nmax], clamped."),
    sig("efit", F, &[(F, "x"), (F, "omin"), (F, "omax"), (F, "nmin"), (F, "nmax")], "x mapped from [omin, omax] to [nmin, nmax], not clamped."),
    sig("fit01", F, &[(F, "x"), (F, "nmin"), (F, "nmax")], "x mapped from [0, 1] to [nmin, nmax], clamped."),
    sig("fit10", F, &[(F, "x"), (F, "nmin"), (F, "nmax")], "x mapped from [1, 0] to [nmin, nmax], clamped."),
    sig("fit11", F, &[(F, "x"), (F, "nmin"), (F, "nmax")], "x mapped from [-1, 1] to [nmin, nmax], clamped."),
    sig("smooth", F, &[(F, "lo"), (F, "hi"), (F, "x")], "Smooth step: 0 below lo, 1 above hi, a cubic between."),
    sig("length", F, &[(V, "v")], "Length of a vector."),
    sig("length2", F, &[(V, "v")], "Squared length of a vector."),
    sig("distance", F, &[(V, "a"), (V, "b")], "Distance between two points."),
    sig("distance2", F, &[(V, "a"), (V, "b")], "Squared distance between two points."),
    sig("dot", F, &[(V, "a"), (V, "b")], "Dot product."),
    sig("cross", V, &[(V, "a"), (V, "b")], "Cross product."),
    sig("normalize", V, &[(V, "v")], "The vector scaled to length 1 (zero stays zero)."),
    sig("avg", F, &[(V, "v")], "Average of a vector's components."),
    many(sig("avg", F, &[(F, "a"), (F, "b")], "Average of the arguments.")),
    sig("set", V, &[(F, "x"), (F, "y"), (F, "z")], "A vector from components: 2, 3 or 4 floats give a vector2, vector or vector4."),
    sig("getcomp", F, &[(V, "v"), (I, "index")], "Component `index` (a constant) of a vector; with a column, of a matrix."),
    sig("setcomp", VOID, &[(V, "v"), (F, "value"), (I, "index")], "Sets component `index` (a constant) of a vector variable."),
    // The node's parameters.
    sig("ch", F, &[(S, "name")], "The node's (spare) parameter `name` at this frame, as a float."),
    sig("chf", F, &[(S, "name")], "The node's float parameter `name`."),
    sig("chi", I, &[(S, "name")], "The node's int parameter `name`."),
    sig("chv", V, &[(S, "name")], "The node's vector parameter `name`."),
    sig("chs", S, &[(S, "name")], "The node's string parameter `name`."),
    sig("chu", V2, &[(S, "name")], "The node's vector2 parameter `name`."),
    sig("chp", V4, &[(S, "name")], "The node's vector4 parameter `name`."),
    // Reading geometry.
    sig("point", F, &[(I, "geo"), (S, "attrib"), (I, "ptnum")], "A point attribute of input `geo`; its type is the attribute's (or the declared one)."),
    sig("prim", F, &[(I, "geo"), (S, "attrib"), (I, "primnum")], "A primitive attribute of input `geo`; its type is the attribute's (or the declared one)."),
    sig("vertex", F, &[(I, "geo"), (S, "attrib"), (I, "vtxnum")], "A vertex attribute of input `geo` by linear vertex number."),
    opt(sig("detail", F, &[(I, "geo"), (S, "attrib"), (I, "ignored")], "A detail attribute of input `geo`."), 1),
    sig("npoints", I, &[(I, "geo")], "Number of points of input `geo`."),
    sig("nprimitives", I, &[(I, "geo")], "Number of primitives of input `geo`."),
    sig("nvertices", I, &[(I, "geo")], "Number of vertices of input `geo`."),
    sig("primpoints", IA, &[(I, "geo"), (I, "primnum")], "The points of a primitive, in vertex order."),
    sig("pointprims", IA, &[(I, "geo"), (I, "ptnum")], "The primitives that use a point."),
    sig("neighbours", IA, &[(I, "geo"), (I, "ptnum")], "The points sharing an edge with a point."),
    sig("neighbourcount", I, &[(I, "geo"), (I, "ptnum")], "Number of points sharing an edge with a point."),
    opt(sig("nearpoint", I, &[(I, "geo"), (V, "pos"), (F, "maxdist")], "The closest point to pos (-1 if none within maxdist)."), 1),
    opt(sig("nearpoint", I, &[(I, "geo"), (S, "group"), (V, "pos"), (F, "maxdist")], "The closest point of a group to pos (-1 if none within maxdist)."), 1),
    opt(sig("nearpoints", IA, &[(I, "geo"), (V, "pos"), (F, "maxdist"), (I, "maxpoints")], "The points within maxdist of pos, closest first."), 1),
    opt(sig("nearpoints", IA, &[(I, "geo"), (S, "group"), (V, "pos"), (F, "maxdist"), (I, "maxpoints")], "The points of a group within maxdist of pos, closest first."), 1),
    sig("inpointgroup", I, &[(I, "geo"), (S, "group"), (I, "ptnum")], "1 if the point is in the point group."),
    sig("inprimgroup", I, &[(I, "geo"), (S, "group"), (I, "primnum")], "1 if the primitive is in the primitive group."),
    sig("haspointattrib", I, &[(I, "geo"), (S, "attrib")], "1 if input `geo` has the point attribute."),
    sig("hasprimattrib", I, &[(I, "geo"), (S, "attrib")], "1 if input `geo` has the primitive attribute."),
    sig("hasvertexattrib", I, &[(I, "geo"), (S, "attrib")], "1 if input `geo` has the vertex attribute."),
    sig("hasdetailattrib", I, &[(I, "geo"), (S, "attrib")], "1 if input `geo` has the detail attribute."),
    sig("pointhedge", I, &[(I, "geo"), (I, "ptnum")], "A half-edge leaving the point (-1 if none)."),
    sig("primhedge", I, &[(I, "geo"), (I, "primnum")], "The first half-edge of the primitive."),
    sig("hedge_next", I, &[(I, "geo"), (I, "hedge")], "The next half-edge around its primitive."),
    sig("hedge_srcpoint", I, &[(I, "geo"), (I, "hedge")], "The point a half-edge starts at."),
    sig("hedge_dstpoint", I, &[(I, "geo"), (I, "hedge")], "The point a half-edge ends at."),
    sig("hedge_isvalid", I, &[(I, "geo"), (I, "hedge")], "1 if the half-edge exists."),
    sig("hedge_prim", I, &[(I, "geo"), (I, "hedge")], "The primitive of a half-edge."),
    // Writing geometry: queued, applied after every element ran.
    opt(sig("setpointattrib", I, &[(I, "geo"), (S, "attrib"), (I, "ptnum"), (F, "value"), (S, "mode")], "Writes a point attribute of any type (mode: set, add, min, max, mult, append)."), 1),
    opt(sig("setprimattrib", I, &[(I, "geo"), (S, "attrib"), (I, "primnum"), (F, "value"), (S, "mode")], "Writes a primitive attribute of any type (mode: set, add, min, max, mult, append)."), 1),
    opt(sig("setvertexattrib", I, &[(I, "geo"), (S, "attrib"), (I, "primnum"), (I, "vertex"), (F, "value"), (S, "mode")], "Writes a vertex attribute of any type (mode: set, add, min, max, mult, append)."), 1),
    opt(sig("setdetailattrib", I, &[(I, "geo"), (S, "attrib"), (F, "value"), (S, "mode")], "Writes a detail attribute of any type (mode: set, add, min, max, mult, append)."), 1),
    sig("addpoint", I, &[(I, "geo"), (V, "pos")], "Adds a point at pos; the number is valid for calls in this element."),
    sig("addpoint", I, &[(I, "geo"), (I, "ptnum")], "Adds a copy of a point with its attributes."),
    many(opt(sig("addprim", I, &[(I, "geo"), (S, "type"), (I, "pt")], "Adds a \"poly\" or \"polyline\" through the given points."), 1)),
    sig("addprim", I, &[(I, "geo"), (S, "type"), (IA, "points")], "Adds a \"poly\" or \"polyline\" through an array of points."),
    sig("addvertex", I, &[(I, "geo"), (I, "primnum"), (I, "ptnum")], "Appends a vertex on a point to a primitive."),
    sig("removepoint", I, &[(I, "geo"), (I, "ptnum")], "Removes a point (and the primitives left without vertices)."),
    opt(sig("removeprim", I, &[(I, "geo"), (I, "primnum"), (I, "andpoints")], "Removes a primitive, its unused points too when andpoints is 1."), 1),
    sig("setpointgroup", I, &[(I, "geo"), (S, "group"), (I, "ptnum"), (I, "value")], "Puts a point in (1) or out of (0) a point group."),
    sig("setprimgroup", I, &[(I, "geo"), (S, "group"), (I, "primnum"), (I, "value")], "Puts a primitive in (1) or out of (0) a primitive group."),
    // Random numbers and noise: hashes, the same for the same seed.
    many(sig("rand", F, &[(F, "seed")], "A random number in [0, 1) from up to four seeds; a vector when one is declared.")),
    sig("rand", V, &[(V, "seed")], "A random vector in [0, 1) per component from the seed."),
    many(sig("random", F, &[(F, "seed")], "A random number in [0, 1) from up to four seeds, as rand.")),
    sig("noise", F, &[(V, "pos")], "Perlin noise in [0, 1] at pos; a vector when one is declared."),
    sig("noise", V, &[(V, "pos")], "Three Perlin noises in [0, 1] at pos."),
    sig("snoise", F, &[(V, "pos")], "Signed Perlin noise in [-1, 1] at pos; a vector when one is declared."),
    sig("curlnoise", V, &[(V, "pos")], "Divergence-free noise: the curl of a noise field at pos."),
    // Arrays and strings.
    sig("len", I, &[(FA, "array")], "Number of elements of an array (components of a vector)."),
    sig("strlen", I, &[(S, "text")], "Number of characters of a string."),
    sig("push", VOID, &[(FA, "array"), (F, "value")], "Appends a value (or an array's values) to an array variable."),
    sig("append", VOID, &[(FA, "array"), (F, "value")], "Appends a value (or an array's values) to an array or string variable."),
    sig("pop", F, &[(FA, "array")], "Removes and gives the last element of an array variable."),
    sig("insert", VOID, &[(FA, "array"), (I, "index"), (F, "value")], "Inserts a value at index of an array variable."),
    sig("removeindex", VOID, &[(FA, "array"), (I, "index")], "Removes the element at index of an array variable."),
    sig("resize", VOID, &[(FA, "array"), (I, "length")], "Changes the length of an array variable (new elements zero)."),
    sig("find", I, &[(FA, "array"), (F, "value")], "Index of the first element equal to value, or -1 (substrings in a string)."),
    sig("sort", FA, &[(FA, "array")], "The array sorted in ascending order."),
    sig("reverse", FA, &[(FA, "array")], "The array (or string) in reverse order."),
    many(opt(sig("array", FA, &[(F, "value")], "An array of the arguments; its type is the first one's (or the declared one)."), 1)),
    many(opt(sig("sprintf", S, &[(S, "format"), (F, "value")], "Formats values with %d %f %g %s %c %x and widths, as C's printf."), 1)),
    many(opt(sig("printf", VOID, &[(S, "format"), (F, "value")], "Prints formatted values to the cook's log, in element order."), 1)),
    sig("itoa", S, &[(I, "value")], "The int as decimal text."),
    sig("atof", F, &[(S, "text")], "The float the text spells (0 if none)."),
    sig("atoi", I, &[(S, "text")], "The int the text spells (0 if none)."),
    many(sig("concat", S, &[(S, "a"), (S, "b")], "The strings joined.")),
    sig("startswith", I, &[(S, "text"), (S, "prefix")], "1 if text starts with prefix."),
    sig("endswith", I, &[(S, "text"), (S, "suffix")], "1 if text ends with suffix."),
    opt(sig("split", SA, &[(S, "text"), (S, "separators")], "The parts of text between separator characters (whitespace by default)."), 1),
    // Matrices and quaternions.
    sig("ident", M4, &[], "The identity matrix; a matrix3 when one is declared."),
    sig("ident", M3, &[], "The 3x3 identity matrix."),
    sig("invert", M4, &[(M4, "m")], "The inverse matrix (a float's reciprocal)."),
    sig("transpose", M4, &[(M4, "m")], "The transposed matrix."),
    sig("determinant", F, &[(M4, "m")], "The determinant of a matrix."),
    sig("qmultiply", V4, &[(V4, "a"), (V4, "b")], "The product of two quaternions: rotation b, then a."),
    sig("qrotate", V, &[(V4, "q"), (V, "v")], "The vector rotated by a quaternion."),
    sig("qconvert", M3, &[(V4, "q")], "The rotation matrix of a quaternion."),
    sig("quaternion", V4, &[(M3, "rotation")], "The quaternion of a rotation matrix."),
    sig("quaternion", V4, &[(F, "angle"), (V, "axis")], "The quaternion rotating by angle (radians) about axis."),
    sig("quaternion", V4, &[(V, "angleaxis")], "The quaternion of an axis scaled by its angle (radians)."),
    sig("eulertoquaternion", V4, &[(V, "radians"), (I, "order")], "The quaternion of Euler angles in a rotation order (0 is XYZ)."),
    sig("dihedral", V4, &[(V, "a"), (V, "b")], "The shortest rotation taking direction a to b; a matrix3 when one is declared."),
    sig("rotate", VOID, &[(M4, "m"), (F, "angle"), (V, "axis")], "Rotates a matrix variable by angle (radians) about axis."),
    sig("scale", VOID, &[(M4, "m"), (V, "factors")], "Scales a matrix variable."),
    sig("translate", VOID, &[(M4, "m"), (V, "offset")], "Translates a matrix variable."),
    sig("maketransform", M3, &[(V, "zaxis"), (V, "yaxis")], "The rotation whose z and y axes point along zaxis and yaxis."),
    sig("maketransform", M4, &[(V, "zaxis"), (V, "yaxis"), (V, "translate")], "The transform with axes along zaxis and yaxis, moved by translate."),
    opt(sig("maketransform", M4, &[(I, "trs"), (I, "xyz"), (V, "translate"), (V, "rotate"), (V, "scale"), (V, "pivot")], "A transform from translate, rotate (degrees) and scale in the given orders."), 2),
    opt(sig("lookat", M3, &[(V, "from"), (V, "to"), (V, "up")], "The rotation that looks from `from` towards `to`, up as near `up` as it can."), 1),
];

#[cfg(test)]
mod tests {
    use std::collections::BTreeSet;

    use geode_geo::{AttribClass, Geometry};

    use super::*;
    use crate::ast::{ExprKind, Stmt};
    use crate::bind::{BindSpec, Channel};
    use crate::calls::LIBRARY;
    use crate::{lex, lower, parse, Counts};

    /// The argument as written in the test call: ints and strings as
    /// literals (some arguments must be constants: a component index, a
    /// parameter name), everything else a variable declared before.
    fn arg_text(k: usize, ty: Ty) -> String {
        match ty {
            Ty::Int => "0".into(),
            Ty::Str => "\"P\"".into(),
            _ => format!("a{k}"),
        }
    }

    fn declaration(k: usize, ty: Ty) -> Option<String> {
        match ty {
            Ty::Int | Ty::Str => None,
            Ty::Array(e) => Some(format!("{} a{k}[];", e.ty())),
            t => Some(format!("{t} a{k};")),
        }
    }

    /// The argument lists the form accepts: every optional argument left
    /// out in turn and, if variadic, the last one repeated.
    fn arg_lists(s: &Signature) -> Vec<Vec<Ty>> {
        let full: Vec<Ty> = s.args.iter().map(|a| a.0).collect();
        let mut lists: Vec<Vec<Ty>> = (0..=s.optional)
            .map(|dropped| full[..full.len() - dropped].to_vec())
            .collect();
        if s.variadic {
            let mut more = full.clone();
            more.push(*full.last().expect("a variadic form has an argument"));
            lists.push(more);
        }
        lists
    }

    fn two_points() -> Geometry {
        let mut g = Geometry::new();
        g.add_points(&[[0.0, 0.0, 0.0].into(), [1.0, 0.0, 0.0].into()]);
        g
    }

    /// Compiles `name(args)` (after declaring the arguments) and gives the
    /// type the call lowers to.
    fn call_type(s: &Signature, args: &[Ty]) -> Result<Ty, String> {
        let g = two_points();
        // A parameter of the type the call reads, whatever its name.
        let reads_string = s.ret == Ty::Str;
        let channels = move |_: &str| {
            Some(if reads_string {
                Channel::Str("x".into())
            } else {
                Channel::Num(vec![0.5; 4])
            })
        };
        let names = Vec::new;
        let spec = BindSpec {
            run_over: AttribClass::Point,
            inputs: vec![Some(&g)],
            channels: &channels,
            channel_names: &names,
            frame: 1.0,
            time: 0.0,
        };
        let decls: Vec<String> = args
            .iter()
            .enumerate()
            .filter_map(|(k, t)| declaration(k, *t))
            .collect();
        let texts: Vec<String> = args
            .iter()
            .enumerate()
            .map(|(k, t)| arg_text(k, *t))
            .collect();
        let call = format!("{}({})", s.name, texts.join(", "));
        let whole = match s.ret {
            Ty::Void => format!("{}\n{call};", decls.join("\n")),
            Ty::Array(e) => format!("{}\n{} r[] = {call};", decls.join("\n"), e.ty()),
            t => format!("{}\n{t} r = {call};", decls.join("\n")),
        };
        crate::compile(&whole, &spec).map_err(|e| format!("{whole}\n{e}"))?;
        // The call's own type, lowered with the declared type as its hint
        // (as a declaration gives it) after the arguments' declarations.
        let src = format!("{}\n{call};", decls.join("\n"));
        let tokens = lex::fold_prefixes(lex::lex(&src).unwrap()).unwrap();
        let snippet = parse::Parser::new(tokens).snippet().unwrap();
        let mut counts = Counts::default();
        let bindings = crate::bind::bindings(&snippet, &spec, &mut counts).unwrap();
        let mut lowering = lower::Lower::new(&snippet, &bindings, &spec, counts);
        let (last, before) = snippet.body.split_last().expect("the call");
        lowering.snippet_body(before).unwrap();
        let Stmt::Expr(e) = last else {
            panic!("the call is an expression statement")
        };
        assert!(matches!(e.kind, ExprKind::Call(..)));
        let hint = (s.ret != Ty::Void).then_some(s.ret);
        let loc = lowering.expr(e, hint).map_err(|e| e.to_string())?;
        Ok(loc.ty)
    }

    #[test]
    fn the_table_names_exactly_the_functions_the_resolver_accepts() {
        let table: BTreeSet<&str> = signatures().iter().map(|s| s.name).collect();
        let library: BTreeSet<&str> = LIBRARY.iter().copied().collect();
        assert_eq!(
            LIBRARY.len(),
            library.len(),
            "LIBRARY names a function twice"
        );
        let missing: Vec<_> = library.difference(&table).collect();
        let extra: Vec<_> = table.difference(&library).collect();
        assert!(missing.is_empty(), "no signature for {missing:?}");
        assert!(
            extra.is_empty(),
            "signatures of unknown functions {extra:?}"
        );
    }

    /// Every name a match arm of the resolver handles is in `LIBRARY`: an
    /// arm for a name the list lacks would be unreachable (the resolver
    /// refuses names outside the list first).
    #[test]
    fn every_name_the_resolver_matches_is_in_the_library() {
        let source = include_str!("calls.rs");
        let mut arms: BTreeSet<String> = BTreeSet::new();
        // A pattern of many names continues over lines until its `=>`.
        let mut pending = String::new();
        for line in source.lines() {
            let line = format!("{pending} {}", line.trim());
            let Some((pattern, _)) = line.split_once("=>") else {
                let continued = line.trim().starts_with('"') && line.trim().ends_with('"');
                pending = if continued { line } else { String::new() };
                continue;
            };
            pending.clear();
            let pattern = pattern.split(" if ").next().unwrap_or("").trim();
            let alternatives: Vec<&str> = pattern
                .trim_start_matches('|')
                .split('|')
                .map(str::trim)
                .collect();
            let names: Option<Vec<&str>> = alternatives
                .iter()
                .map(|a| a.strip_prefix('"').and_then(|a| a.strip_suffix('"')))
                .collect();
            if let Some(names) = names {
                arms.extend(names.into_iter().map(str::to_owned));
            }
        }
        assert!(arms.len() > 100, "the scan found the arms: {arms:?}");
        let unlisted: Vec<&String> = arms
            .iter()
            .filter(|a| !LIBRARY.contains(&a.as_str()))
            .collect();
        assert!(
            unlisted.is_empty(),
            "arms for names outside LIBRARY: {unlisted:?}"
        );
    }

    #[test]
    fn every_form_compiles_with_its_argument_types_and_gives_its_return_type() {
        let mut failures = Vec::new();
        for s in signatures() {
            for args in arg_lists(s) {
                match call_type(s, &args) {
                    Ok(ty) if s.ret == Ty::Void || ty == s.ret => {}
                    Ok(ty) => failures.push(format!("{}: gives {ty}", s.display())),
                    Err(e) => failures.push(format!("{} with {args:?}: {e}", s.display())),
                }
            }
        }
        assert!(failures.is_empty(), "{}", failures.join("\n\n"));
    }

    #[test]
    fn forms_display_as_vex_documents_them() {
        let fit = signatures().iter().find(|s| s.name == "fit01").unwrap();
        assert_eq!(
            fit.display(),
            "float fit01(float x, float nmin, float nmax)"
        );
        let near = signatures()
            .iter()
            .find(|s| s.name == "nearpoints")
            .unwrap();
        assert_eq!(
            near.display(),
            "int[] nearpoints(int geo, vector pos, float maxdist[, int maxpoints])"
        );
        let max = signatures().iter().find(|s| s.name == "max").unwrap();
        assert_eq!(max.display(), "float max(float a, float b, ...)");
        assert!(signatures().iter().all(|s| !s.summary.is_empty()
            && s.summary.ends_with('.')
            && s.optional <= s.args.len()));
    }
}
