//! Random numbers and noise (SideFX's "Noise and randomness" category):
//! hashes of their seeds, so the same seed gives the same value on every
//! machine and thread count. The noise kernels are `crate::noise`.

use super::{a, form, lane, Category, Function, Ret, F, T, V};
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

fn perlin(l: &Lane, a: &[Val], unsigned: bool) -> Val {
    let pos = a[0].v3();
    let n = l.out.floats().max(1);
    let xs: Vec<f32> = (0..n)
        .map(|k| {
            let v = crate::noise::perlin(pos, k as i32);
            if unsigned {
                0.5 + 0.5 * v
            } else {
                v
            }
        })
        .collect();
    Val::vec(&xs)
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
