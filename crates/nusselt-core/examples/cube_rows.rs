//! Times `auto` pair rows of the closed unit cube with n x n squares per face (no Python):
//!     cargo run --release -p nusselt-core --example cube_rows -- 32 0.03
use nusselt_core::matrix::{mirror_upper, UpperRow};
use nusselt_core::scene::{AnyMethod, Scene};
use nusselt_core::unobstructed::method::AutoOptions;
use nusselt_core::Vec3;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

#[path = "common/room.rs"]
#[allow(dead_code)] // room() serves the other examples
mod room;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let k: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(32);
    let tol: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(0.03);
    let polys = room::meshed_box(1.0, Vec3::ZERO, k, true);
    let n = polys.len();
    let scene = Scene::new(polys, vec![true; n]).unwrap();
    let t = Instant::now();
    assert!(scene.unobstructed());
    println!("unobstructed check: {:.3} s", t.elapsed().as_secs_f64());
    let m = AnyMethod::Auto(AutoOptions { tol, ..Default::default() });
    let rows: Vec<usize> = (0..n).collect();
    for _ in 0..2 {
        let t = Instant::now();
        let b = scene.pair_block(&rows, &m, &AtomicBool::new(false)).unwrap();
        let t1 = t.elapsed().as_secs_f64();
        let pairs = n * (n - 1) / 2;
        println!(
            "{n} patches, tol {tol:e}: pair rows {t1:.3} s ({:.1} M pairs/s), {} entries",
            pairs as f64 / t1 / 1e6,
            b.g.len()
        );
        let areas: Vec<f64> = scene.polygons().iter().map(|p| p.area()).collect();
        let upper: Vec<UpperRow> = (0..n)
            .map(|i| {
                let (s, e) = (b.indptr[i] as usize, b.indptr[i + 1] as usize);
                UpperRow { row: i, cols: &b.cols[s..e], g: &b.g[s..e], std: None }
            })
            .collect();
        let mut times = Vec::new();
        for _ in 0..4 {
            let t = Instant::now();
            let (f, _) = mirror_upper::<f64>(&areas, &upper, false).unwrap();
            times.push(t.elapsed().as_secs_f64());
            assert_eq!(f.data.len(), 2 * b.g.len());
        }
        println!("mirror: {:.3?} s", times);
    }
}
