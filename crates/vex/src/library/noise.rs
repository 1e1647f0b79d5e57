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
        form(SCALAR_OR_VECTOR, &[a(T::Num, "seed")], rand),
        form(SCALAR_OR_VECTOR, &[a(F, "seed"), a(F, "seed2")], rand).opt(1).many(),
    ]),
    lane("random", C, "A random number in [0, 1) from up to four seeds, as rand.", &[
        form(SCALAR_OR_VECTOR, &[a(T::Num, "seed")], rand),
        form(SCALAR_OR_VECTOR, &[a(F, "seed"), a(F, "seed2")], rand).opt(1).many(),
    ]),
    lane("noise", C, "Perlin noise in about [0, 1], centred on 0.5, at a position; a vector when one is declared.", &[
        form(SCALAR_OR_VECTOR, &[a(T::Num, "pos")], noise),
    ]),
    lane("snoise", C, "Signed Perlin noise in about [-1, 1] at a position; a vector when one is declared.", &[
        form(SCALAR_OR_VECTOR, &[a(T::Num, "pos")], snoise),
    ]),
    lane("curlnoise", C, "Divergence-free noise: the curl of a noise field at a position.", &[
        form(Ret::Is(Ty::Vec3), &[a(V, "pos")], curlnoise),
    ]),
    lane("curlnoise2d", C, "Divergence-free noise in the plane: the curl of a 2D noise field at (x, y); z is 0.", &[
        form(Ret::Is(Ty::Vec3), &[a(T::Num, "pos")], curlnoise2d),
    ]),
    lane("onoise", C, "Perlin's original (1985) noise, signed, about [-1, 1]; a vector when one is declared.", &[
        form(SCALAR_OR_VECTOR, &[a(T::Num, "pos")], onoise),
    ]),
    lane("xnoise", C, "Simplex noise in about [0, 1], centred on 0.5; a vector when one is declared.", &[
        form(SCALAR_OR_VECTOR, &[a(T::Num, "pos")], xnoise),
    ]),
    lane("xnoised", C, "Signed simplex noise, about [-1, 1]; a vector when one is declared.", &[
        form(SCALAR_OR_VECTOR, &[a(T::Num, "pos")], xnoised),
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

fn rand(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let seed: Vec<f32> = a
        .iter()
        .flat_map(|v| match v {
            Val::I(i) => vec![*i as f32],
            v => v.floats().to_vec(),
        })
        .collect();
    let n = l.out.floats().max(1);
    let xs: Vec<f32> = (0..n).map(|k| rand_of(&seed, k as u64)).collect();
    Ok(Val::vec(&xs))
}

/// A noise kernel per component the call asks for (independent channels),
/// signed or mapped to [0, 1]; a float position splats as before.
fn field(l: &Lane, a: &[Val], kernel: fn([f32; 3], i32) -> f32, unsigned: bool) -> Val {
    let pos = match a[0].floats() {
        [x] => [*x; 3],
        _ => a[0].v3(),
    };
    let n = l.out.floats().max(1);
    let xs: Vec<f32> = (0..n)
        .map(|k| {
            let v = kernel(pos, k as i32);
            if unsigned {
                0.5 + 0.5 * v
            } else {
                v
            }
        })
        .collect();
    Val::vec(&xs)
}

fn perlin(l: &Lane, a: &[Val], unsigned: bool) -> Val {
    field(l, a, crate::noise::perlin, unsigned)
}

fn onoise(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(field(l, a, crate::noise::original, false))
}

fn xnoise(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(field(l, a, crate::noise::simplex, true))
}

fn xnoised(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(field(l, a, crate::noise::simplex, false))
}

fn wnoise(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let cell = crate::noise::worley(a[0].v3(), 1.0);
    a[1] = Val::I(cell.id);
    a[2] = Val::float(cell.f1);
    a[3] = Val::float(cell.f2);
    Ok(Val::I(0))
}

fn curlnoise2d(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let p = a[0].floats();
    let xy = [
        p.first().copied().unwrap_or(0.0),
        p.get(1).copied().unwrap_or(0.0),
    ];
    Ok(Val::vec(&crate::noise::curl2d(xy)))
}

fn noise(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(perlin(l, a, true))
}

fn snoise(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(perlin(l, a, false))
}

fn curlnoise(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::vec(&crate::noise::curl(a[0].v3())))
}
