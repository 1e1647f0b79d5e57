//! Random numbers and noise (SideFX's "Noise and randomness" category):
//! hashes of their seeds, so the same seed gives the same value on every
//! machine and thread count. The noise kernels are `crate::noise`.

use super::{a, form, lane, out, Category, Function, Ret, F, I, T, V};
use crate::program::{Lane, Stop};
use crate::ty::Ty;
use crate::value::Val;

const C: Category = Category::Noise;
/// The result is a float, or the vector the context declares.
const SCALAR_OR_VECTOR: Ret = Ret::Context(&[Ty::Float, Ty::Vec3, Ty::Vec2, Ty::Vec4]);

#[rustfmt::skip]
pub const FUNCTIONS: &[Function] = &[
    lane("rand", C, "A random number in [0, 1) from up to four seeds (a vector's components included); a vector when one is declared.", &[
        form(SCALAR_OR_VECTOR, &[a(T::Num, "seed")], rand).num(rand_num),
        form(SCALAR_OR_VECTOR, &[a(F, "seed"), a(F, "seed2")], rand).opt(1).many().num(rand_num),
    ]),
    lane("random", C, "A random number in [0, 1) from up to four seeds, as rand.", &[
        form(SCALAR_OR_VECTOR, &[a(T::Num, "seed")], rand).num(rand_num),
        form(SCALAR_OR_VECTOR, &[a(F, "seed"), a(F, "seed2")], rand).opt(1).many().num(rand_num),
    ]),
    lane("noise", C, "Perlin noise in about [0, 1], centred on 0.5, at a position; a vector when one is declared.", &[
        form(SCALAR_OR_VECTOR, &[a(T::Num, "pos")], noise).num(noise_num),
    ]),
    lane("snoise", C, "Signed Perlin noise in about [-1, 1] at a position; a vector when one is declared.", &[
        form(SCALAR_OR_VECTOR, &[a(T::Num, "pos")], snoise).num(snoise_num),
    ]),
    lane("curlnoise", C, "Divergence-free noise: the curl of a noise field at a position.", &[
        form(Ret::Is(Ty::Vec3), &[a(V, "pos")], curlnoise).num(curlnoise_num),
    ]),
    lane("curlnoise2d", C, "Divergence-free noise in the plane: the curl of a 2D noise field at (x, y); z is 0.", &[
        form(Ret::Is(Ty::Vec3), &[a(T::Num, "pos")], curlnoise2d).num(curlnoise2d_num),
    ]),
    lane("onoise", C, "Perlin's original (1985) noise, signed, about [-1, 1]; a vector when one is declared.", &[
        form(SCALAR_OR_VECTOR, &[a(T::Num, "pos")], onoise).num(onoise_num),
    ]),
    lane("xnoise", C, "Simplex noise in about [0, 1], centred on 0.5; a vector when one is declared.", &[
        form(SCALAR_OR_VECTOR, &[a(T::Num, "pos")], xnoise).num(xnoise_num),
    ]),
    lane("xnoised", C, "Signed simplex noise, about [-1, 1]; a vector when one is declared.", &[
        form(SCALAR_OR_VECTOR, &[a(T::Num, "pos")], xnoised).num(xnoised_num),
    ]),
    lane("wnoise", C, "Worley (cellular) noise: the distances to the nearest two feature points into f1 and f2 and the nearest one's id into seed.", &[
        form(Ret::Is(Ty::Void), &[a(T::Num, "pos"), out(I, "seed"), out(F, "f1"), out(F, "f2")], wnoise),
    ]),
];

fn rand_of(seed: &[f32], salt: u64) -> f32 {
    let mut h: u64 = 0x9e37_79b9_7f4a_7c15 ^ salt;
    for s in seed {
        h = (h ^ u64::from(s.to_bits())).wrapping_mul(0xff51_afd7_ed55_8ccd);
        h ^= h >> 33;
    }
    geode_geo::random::unit(h, 0, salt)
}

fn rand_num(seed: &[f32], out: &mut [f32]) {
    for (k, x) in out.iter_mut().enumerate() {
        *x = rand_of(seed, k as u64);
    }
}

fn rand(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(super::support::through_numbers(l, a, rand_num))
}

/// The position a noise function reads: a float splats to all three axes,
/// a vector2 lies in z = 0.
fn pos3(x: &[f32]) -> [f32; 3] {
    match x {
        [a] => [*a; 3],
        _ => pos3_plain(x),
    }
}

/// A noise kernel per component the call asks for (independent channels),
/// signed or mapped to [0, 1].
fn field(x: &[f32], out: &mut [f32], kernel: fn([f32; 3], i32) -> f32, unsigned: bool) {
    let pos = pos3(x);
    for (k, o) in out.iter_mut().enumerate() {
        let v = kernel(pos, k as i32);
        *o = if unsigned { 0.5 + 0.5 * v } else { v };
    }
}

fn noise_num(x: &[f32], out: &mut [f32]) {
    field(x, out, crate::noise::perlin, true);
}

fn snoise_num(x: &[f32], out: &mut [f32]) {
    field(x, out, crate::noise::perlin, false);
}

fn onoise_num(x: &[f32], out: &mut [f32]) {
    field(x, out, crate::noise::original, false);
}

fn xnoise_num(x: &[f32], out: &mut [f32]) {
    field(x, out, crate::noise::simplex, true);
}

fn xnoised_num(x: &[f32], out: &mut [f32]) {
    field(x, out, crate::noise::simplex, false);
}

fn curlnoise_num(x: &[f32], out: &mut [f32]) {
    out.copy_from_slice(&crate::noise::curl(pos3_plain(x))[..out.len()]);
}

fn curlnoise2d_num(x: &[f32], out: &mut [f32]) {
    let xy = [
        x.first().copied().unwrap_or(0.0),
        x.get(1).copied().unwrap_or(0.0),
    ];
    out.copy_from_slice(&crate::noise::curl2d(xy)[..out.len()]);
}

/// A vector's first three components (no splat: curl noise reads a vector).
fn pos3_plain(x: &[f32]) -> [f32; 3] {
    [
        x.first().copied().unwrap_or(0.0),
        x.get(1).copied().unwrap_or(0.0),
        x.get(2).copied().unwrap_or(0.0),
    ]
}

fn noise(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(super::support::through_numbers(l, a, noise_num))
}

fn snoise(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(super::support::through_numbers(l, a, snoise_num))
}

fn onoise(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(super::support::through_numbers(l, a, onoise_num))
}

fn xnoise(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(super::support::through_numbers(l, a, xnoise_num))
}

fn xnoised(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(super::support::through_numbers(l, a, xnoised_num))
}

fn curlnoise(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(super::support::through_numbers(l, a, curlnoise_num))
}

fn curlnoise2d(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(super::support::through_numbers(l, a, curlnoise2d_num))
}

fn wnoise(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let cell = crate::noise::worley(a[0].v3(), 1.0);
    a[1] = Val::I(cell.id);
    a[2] = Val::float(cell.f1);
    a[3] = Val::float(cell.f2);
    Ok(Val::I(0))
}
