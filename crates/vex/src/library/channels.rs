//! The node's parameters (SideFX's `ch*` functions): read once per cook by
//! the compiler, so a parameter is a constant of the compiled snippet and
//! part of the cook's key.

use super::{a, compiler, shape, Category, Function, Ret, F, S};
use crate::program::{Lane, Stop};
use crate::ty::Ty;
use crate::value::Val;

const C: Category = Category::Parameters;

#[rustfmt::skip]
pub const FUNCTIONS: &[Function] = &[
    compiler("ch", C, "The node's (spare) parameter name at this frame, as a float (or the declared type).", &[
        shape(Ret::Context(&[Ty::Float, Ty::Int, Ty::Vec3, Ty::Vec2, Ty::Vec4, Ty::Str]), &[a(S, "name"), a(F, "time")]).opt(1),
    ]),
    compiler("chf", C, "The node's float parameter name.", &[shape(Ret::Is(Ty::Float), &[a(S, "name"), a(F, "time")]).opt(1)]),
    compiler("chi", C, "The node's int parameter name.", &[shape(Ret::Is(Ty::Int), &[a(S, "name"), a(F, "time")]).opt(1)]),
    compiler("chv", C, "The node's vector parameter name.", &[shape(Ret::Is(Ty::Vec3), &[a(S, "name"), a(F, "time")]).opt(1)]),
    compiler("chs", C, "The node's string parameter name.", &[shape(Ret::Is(Ty::Str), &[a(S, "name"), a(F, "time")]).opt(1)]),
    compiler("chu", C, "The node's vector2 parameter name.", &[shape(Ret::Is(Ty::Vec2), &[a(S, "name"), a(F, "time")]).opt(1)]),
    compiler("chp", C, "The node's vector4 parameter name.", &[shape(Ret::Is(Ty::Vec4), &[a(S, "name"), a(F, "time")]).opt(1)]),
    compiler("chramp", C, "The node's ramp parameter name at x (clamped to [0, 1]): a float for a float ramp, a vector for a colour ramp.", &[
        shape(Ret::Context(&[Ty::Float, Ty::Vec3]), &[a(S, "name"), a(F, "x"), a(F, "time")]).opt(1),
    ]),
];

/// The call `chramp` lowers to: the ramp by its index in the program.
pub mod intrinsics {
    use super::super::Callee;

    pub const CHRAMP: Callee = Callee {
        name: "chramp",
        lane: super::chramp,
        bytes: None,
    };
}

fn chramp(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let x = f64::from(a[1].f());
    let Some(ramp) = usize::try_from(a[0].i()).ok().and_then(|k| l.host.ramp(k)) else {
        return Ok(Val::vec(&vec![0.0; l.out.floats().max(1)]));
    };
    let v = ramp.eval(x);
    let n = l.out.floats().max(1);
    Ok(match ramp.kind() {
        // A float ramp fills every component the context asks for.
        geode_geo::RampKind::Float => Val::vec(&vec![v[0] as f32; n]),
        _ => {
            let c = [v[0] as f32, v[1] as f32, v[2] as f32, 1.0];
            Val::vec(&c[..n.min(4)])
        }
    })
}
