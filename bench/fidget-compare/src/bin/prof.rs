// temporary profiling driver
fn main() {
    let name = std::env::var("MODEL").unwrap_or("colonnade.vm".into());
    let depth: u32 = std::env::var("DEPTH").ok().and_then(|d| d.parse().ok()).unwrap_or(6);
    let tol: f64 = std::env::var("TOL").ok().and_then(|d| d.parse().ok()).unwrap_or(0.03703);
    let n: usize = std::env::var("N").ok().and_then(|d| d.parse().ok()).unwrap_or(50);
    let path = format!("{}/../../../shared/corpus/fidget-models/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(path).unwrap();
    let field = geode_frep::parse_vm(&text).unwrap();
    let mut o = geode_mesher::MeshOptions::new([-1.0; 3], [1.0; 3], depth);
    o.tolerance = tol;
    let mut ts = vec![];
    for _ in 0..n {
        let t = std::time::Instant::now();
        let (g, s) = geode_mesher::polygonise(&field, &o, &|| false, &|_| {}).unwrap();
        ts.push(t.elapsed().as_secs_f64() * 1e3);
        if ts.len() == 1 { eprintln!("{} tris, {:?}", g.num_prims(), s); }
    }
    ts.sort_by(f64::total_cmp);
    println!("median {:.1} ms min {:.1}", ts[n / 2], ts[0]);
}
