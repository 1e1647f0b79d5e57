//! HyperFun's standard functions and FRep library, each written from the
//! definition HyperFun documents for it (f >= 0 inside): primitives
//! (hfSphere, hfBlock, hfTorusX, ...), operations (hfBlendUni, ...) and
//! transformations, which are inverse mappings of the coordinate array.

use super::compile::{add, bin, div, intersect, konst, mul, pow, sq, sqrt, sub, un, union, Value};
use crate::field::{Binary, Field, Unary};

/// What a call gives.
pub(crate) enum Lib {
    Value(Field),
    /// The new coordinate array of a transformation.
    Transform(Vec<Field>),
    Unknown,
}

/// Each function's arguments as HyperFun documents them: `name[3]` (or
/// `name[]`, any length) is an array, anything else a value.
const SIGNATURES: &[(&str, &str)] = &[
    ("sqrt", "v"),
    ("exp", "v"),
    ("log", "v"),
    ("logd", "v"),
    ("sin", "v"),
    ("cos", "v"),
    ("tan", "v"),
    ("asin", "v"),
    ("acos", "v"),
    ("atan", "v"),
    ("abs", "v"),
    ("sign", "v"),
    ("max", "a, b"),
    ("min", "a, b"),
    ("mod", "a, b"),
    ("hfsphere", "x[3], center[3], R"),
    ("hfellipsoid", "x[3], center[3], a, b, c"),
    ("hfcylinderx", "x[3], center[3], R"),
    ("hfcylindery", "x[3], center[3], R"),
    ("hfcylinderz", "x[3], center[3], R"),
    ("hfellcylx", "x[3], center[3], a, b"),
    ("hfellcyly", "x[3], center[3], a, b"),
    ("hfellcylz", "x[3], center[3], a, b"),
    ("hftorusx", "x[3], center[3], R, r0"),
    ("hftorusy", "x[3], center[3], R, r0"),
    ("hftorusz", "x[3], center[3], R, r0"),
    ("hfconex", "x[3], center[3], R"),
    ("hfconey", "x[3], center[3], R"),
    ("hfconez", "x[3], center[3], R"),
    ("hfblock", "x[3], vertex[3], dx, dy, dz"),
    ("hfsuperell", "x[3], center[3], a, b, c, s1, s2"),
    ("hfblobby", "x[3], x0[], y0[], z0[], a[], b[], T"),
    ("hfblenduni", "f1, f2, a0, a1, a2"),
    ("hfblendint", "f1, f2, a0, a1, a2"),
    ("hfscale3d", "x[3], sx, sy, sz"),
    ("hfshift3d", "x[3], dx, dy, dz"),
    ("hfstretch3d", "x[3], x0[3], sx, sy, sz"),
    ("hfrotate3dx", "x[3], theta"),
    ("hfrotate3dy", "x[3], theta"),
    ("hfrotate3dz", "x[3], theta"),
    ("hftwistx", "x[3], x1, x2, theta1, theta2"),
    ("hftwisty", "y[3], y1, y2, theta1, theta2"),
    ("hftwistz", "x[3], z1, z2, theta1, theta2"),
    ("hftaperx", "x[3], x1, x2, s1, s2"),
    ("hftapery", "x[3], y1, y2, s1, s2"),
    ("hftaperz", "x[3], z1, z2, s1, s2"),
];

/// One checked argument.
enum Arg<'a> {
    Num(&'a Field),
    Arr(&'a [Field]),
}

impl<'a> Arg<'a> {
    fn v(&self) -> &'a Field {
        match self {
            Arg::Num(f) => f,
            Arg::Arr(_) => unreachable!("checked against the signature"),
        }
    }
    fn a(&self) -> &'a [Field] {
        match self {
            Arg::Arr(a) => a,
            Arg::Num(_) => unreachable!("checked against the signature"),
        }
    }
}

/// Calls `name` (lower-cased) on `values`; `Err` says what is wrong with
/// the arguments.
pub(crate) fn call(name: &str, values: &[Value]) -> Result<Lib, String> {
    let Some((_, signature)) = SIGNATURES.iter().find(|(n, _)| *n == name) else {
        return Ok(Lib::Unknown);
    };
    let params: Vec<&str> = signature.split(", ").collect();
    if params.len() != values.len() {
        return Err(format!(
            "{name} takes {} arguments ({signature}), given {}",
            params.len(),
            values.len()
        ));
    }
    let mut args = Vec::with_capacity(values.len());
    for (param, value) in params.iter().zip(values) {
        let wanted = param
            .find('[')
            .map(|b| param[b + 1..param.len() - 1].parse::<usize>().ok());
        args.push(match (wanted, value) {
            (None, Value::Scalar(f)) => Arg::Num(f),
            (Some(None), Value::Array(a)) => Arg::Arr(a),
            (Some(Some(n)), Value::Array(a)) if a.len() == n => Arg::Arr(a),
            (Some(Some(n)), Value::Array(a)) => {
                return Err(format!(
                    "{name}: '{param}' needs {n} elements, given {}",
                    a.len()
                ))
            }
            (Some(_), Value::Scalar(_)) => {
                return Err(format!("{name}: '{param}' must be an array"))
            }
            (None, Value::Array(_)) => {
                return Err(format!("{name}: '{param}' must be a value, not an array"))
            }
        });
    }
    if name == "hfblobby" {
        let n = args[1].a().len();
        if args[2..6].iter().any(|a| a.a().len() != n) {
            return Err(format!(
                "{name}: x0, y0, z0, a and b need the same number of elements"
            ));
        }
    }
    Ok(evaluate(name, &args))
}

fn evaluate(name: &str, a: &[Arg]) -> Lib {
    use Lib::{Transform, Value as V};
    // The point relative to a primitive's centre (its first two arguments).
    let d = || -> [Field; 3] {
        let (x, c) = (a[0].a(), a[1].a());
        std::array::from_fn(|k| sub(&x[k], &c[k]))
    };
    let one = konst(1.0);
    match name {
        "sqrt" => V(sqrt(a[0].v())),
        "exp" => V(un(Unary::Exp, a[0].v())),
        "log" => V(un(Unary::Ln, a[0].v())),
        "logd" => V(div(
            &un(Unary::Ln, a[0].v()),
            &konst(std::f64::consts::LN_10),
        )),
        "sin" => V(un(Unary::Sin, a[0].v())),
        "cos" => V(un(Unary::Cos, a[0].v())),
        "tan" => V(un(Unary::Tan, a[0].v())),
        "asin" => V(un(Unary::Asin, a[0].v())),
        "acos" => V(un(Unary::Acos, a[0].v())),
        "atan" => V(un(Unary::Atan, a[0].v())),
        "abs" => V(un(Unary::Abs, a[0].v())),
        "sign" => V(bin(Binary::Compare, a[0].v(), &konst(0.0))),
        "max" => V(bin(Binary::Max, a[0].v(), a[1].v())),
        "min" => V(bin(Binary::Min, a[0].v(), a[1].v())),
        "mod" => V(bin(Binary::Mod, a[0].v(), a[1].v())),
        "hfsphere" => {
            let t = d();
            V(sub(&sq(a[2].v()), &sum3(&t.map(|v| sq(&v)))))
        }
        "hfellipsoid" => {
            let t = d();
            let s = [
                div(&t[0], a[2].v()),
                div(&t[1], a[3].v()),
                div(&t[2], a[4].v()),
            ];
            V(sub(&one, &sum3(&s.map(|v| sq(&v)))))
        }
        "hfcylinderx" | "hfcylindery" | "hfcylinderz" => {
            let t = d();
            let (u, w) = across(name);
            V(sub(&sub(&sq(a[2].v()), &sq(&t[u])), &sq(&t[w])))
        }
        "hfellcylx" | "hfellcyly" | "hfellcylz" => {
            let t = d();
            // a and b go with the two axes across in x, y, z order (hfEllCylY: a on x, b on z).
            let (u, w) = across(name);
            let (u, w) = (u.min(w), u.max(w));
            let (p, q) = (div(&t[u], a[2].v()), div(&t[w], a[3].v()));
            V(sub(&sub(&one, &sq(&p)), &sq(&q)))
        }
        "hftorusx" | "hftorusy" | "hftorusz" => {
            // r0^2 - |t|^2 - R^2 + 2 R sqrt(t_u^2 + t_w^2)
            let t = d();
            let (u, w) = across(name);
            let (big, small) = (a[2].v(), a[3].v());
            let ring = mul(&mul(&konst(2.0), big), &sqrt(&add(&sq(&t[u]), &sq(&t[w]))));
            let f = sub(
                &sub(&sq(small), &sum3(&t.clone().map(|v| sq(&v)))),
                &sq(big),
            );
            V(add(&f, &ring))
        }
        "hfconex" | "hfconey" | "hfconez" => {
            let t = d();
            let axis = axis_of(name);
            let (u, w) = across(name);
            let r = a[2].v();
            V(sub(
                &sub(&sq(&t[axis]), &sq(&div(&t[u], r))),
                &sq(&div(&t[w], r)),
            ))
        }
        "hfblock" => {
            let (x, v) = (a[0].a(), a[1].a());
            let slab =
                |k: usize, len: &Field| mul(&sub(&x[k], &v[k]), &sub(&add(&v[k], len), &x[k]));
            let s = [slab(0, a[2].v()), slab(1, a[3].v()), slab(2, a[4].v())];
            V(intersect(&intersect(&s[0], &s[1]), &s[2]))
        }
        "hfsuperell" => {
            let t = d();
            let (s1, s2) = (a[5].v(), a[6].v());
            let q = [
                div(&t[0], a[2].v()),
                div(&t[1], a[3].v()),
                div(&t[2], a[4].v()),
            ];
            let two = konst(2.0);
            let xy = add(
                &pow(&un(Unary::Abs, &q[0]), &div(&two, s2)),
                &pow(&un(Unary::Abs, &q[1]), &div(&two, s2)),
            );
            let z = pow(&un(Unary::Abs, &q[2]), &div(&two, s1));
            V(sub(&sub(&one, &pow(&xy, &div(s2, s1))), &z))
        }
        "hfblobby" => {
            let x = a[0].a();
            let (x0, y0, z0, ka, kb) = (a[1].a(), a[2].a(), a[3].a(), a[4].a(), a[5].a());
            let mut sum = konst(0.0);
            for i in 0..x0.len() {
                let r2 = sum3(&[
                    sq(&sub(&x[0], &x0[i])),
                    sq(&sub(&x[1], &y0[i])),
                    sq(&sub(&x[2], &z0[i])),
                ]);
                let term = mul(&kb[i], &un(Unary::Exp, &un(Unary::Neg, &mul(&ka[i], &r2))));
                sum = add(&sum, &term);
            }
            V(sub(&sum, a[6].v()))
        }
        "hfblenduni" | "hfblendint" => {
            let (f1, f2) = (a[0].v(), a[1].v());
            let bump = div(
                a[2].v(),
                &add(&add(&one, &sq(&div(f1, a[3].v()))), &sq(&div(f2, a[4].v()))),
            );
            let base = if name == "hfblenduni" {
                union(f1, f2)
            } else {
                intersect(f1, f2)
            };
            V(add(&base, &bump))
        }
        "hfscale3d" => {
            let x = a[0].a();
            Transform((0..3).map(|k| div(&x[k], a[k + 1].v())).collect())
        }
        "hfshift3d" => {
            let x = a[0].a();
            Transform((0..3).map(|k| sub(&x[k], a[k + 1].v())).collect())
        }
        "hfstretch3d" => {
            let (x, o) = (a[0].a(), a[1].a());
            Transform(
                (0..3)
                    .map(|k| add(&o[k], &div(&sub(&x[k], &o[k]), a[k + 2].v())))
                    .collect(),
            )
        }
        "hfrotate3dx" | "hfrotate3dy" | "hfrotate3dz" => {
            Transform(rotate(a[0].a(), axis_of(name), a[1].v()))
        }
        "hftwistx" | "hftwisty" | "hftwistz" => {
            let x = a[0].a();
            let axis = axis_of(name);
            let t = div(&sub(&x[axis], a[1].v()), &sub(a[2].v(), a[1].v()));
            let theta = add(&mul(&sub(&one, &t), a[3].v()), &mul(&t, a[4].v()));
            Transform(rotate(x, axis, &theta))
        }
        "hftaperx" | "hftapery" | "hftaperz" => {
            let x = a[0].a();
            let axis = axis_of(name);
            let t = div(&sub(&x[axis], a[1].v()), &sub(a[2].v(), a[1].v()));
            let t = bin(Binary::Max, &bin(Binary::Min, &t, &one), &konst(0.0));
            let scale = add(&mul(&sub(&one, &t), a[3].v()), &mul(&t, a[4].v()));
            let (u, w) = across(name);
            let mut out = x.to_vec();
            out[u] = div(&x[u], &scale);
            out[w] = div(&x[w], &scale);
            Transform(out)
        }
        _ => Lib::Unknown,
    }
}

fn sum3(v: &[Field; 3]) -> Field {
    add(&add(&v[0], &v[1]), &v[2])
}

/// The axis a function's name ends in (x, y or z).
fn axis_of(name: &str) -> usize {
    match name.as_bytes().last() {
        Some(b'x') => 0,
        Some(b'y') => 1,
        _ => 2,
    }
}

/// The two axes across a function's axis, in cyclic order.
fn across(name: &str) -> (usize, usize) {
    let a = axis_of(name);
    ((a + 1) % 3, (a + 2) % 3)
}

/// HyperFun's rotation about `axis` as an inverse mapping: with (u, w) the
/// axes across it in cyclic order, u' = u cos + w sin, w' = -u sin + w cos.
fn rotate(x: &[Field], axis: usize, theta: &Field) -> Vec<Field> {
    let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
    let (c, s) = (un(Unary::Cos, theta), un(Unary::Sin, theta));
    let mut out = x.to_vec();
    out[u] = add(&mul(&x[u], &c), &mul(&x[w], &s));
    out[w] = sub(&mul(&x[w], &c), &mul(&x[u], &s));
    out
}
