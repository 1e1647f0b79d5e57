//! Scratch (not committed).
use geode_geo::glam::Vec3;
fn main() {
    let ball = |p: &[Vec3]| p.iter().map(|q| q.length() <= 1.0).collect::<Vec<bool>>();
    for n in [15_000usize, 150_000, 2_500_000] {
        let t = std::time::Instant::now();
        let (c, share) =
            geode_growth::scatter::inside(Vec3::splat(-1.0), Vec3::ONE, n, 7, &ball, &|| false)
                .unwrap();
        let t1 = t.elapsed();
        let k = geode_growth::scatter::eliminate(&c, n / 5, 8.0 * share, 3, &|| false).unwrap();
        let el = t.elapsed() - t1;
        // quality: nearest-neighbour distances among kept (brute grid-free for small n)
        if n <= 150_000 {
            let pts: Vec<Vec3> = k.iter().map(|&i| c[i]).collect();
            let mut nn: Vec<f32> = pts
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    pts.iter()
                        .enumerate()
                        .filter(|(j, _)| *j != i)
                        .map(|(_, q)| p.distance(*q))
                        .fold(f32::MAX, f32::min)
                })
                .collect();
            nn.sort_by(|a, b| a.partial_cmp(b).unwrap());
            let mean: f32 = nn.iter().sum::<f32>() / nn.len() as f32;
            eprintln!(
                "{n}: elim {:?} nn min {:.5} p1 {:.5} mean {:.5}",
                el,
                nn[0],
                nn[nn.len() / 100],
                mean
            );
        } else {
            eprintln!("{n}: elim {:?}", el);
        }
    }
}
