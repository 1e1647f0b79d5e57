//! The node's parameters (SideFX's `ch*` functions): read once per cook by
//! the compiler, so a parameter is a constant of the compiled snippet and
//! part of the cook's key.

use super::{a, compiler, shape, Category, Function, Ret, F, S};
use crate::ty::Ty;

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
];
