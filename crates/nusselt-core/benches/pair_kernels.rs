//! Throughput of the unobstructed pair kernels (pairs/s), per geometry class:
//! triangle-triangle and quad-quad, separated, near, and touching (shared edge / vertex).
//!
//!     cargo bench -p nusselt-core --bench pair_kernels
//!
//! Criterion reports time per pair; pairs/s = 1 / time.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use glam::DVec3 as V;
use nusselt_core::geometry::Polygon;
use nusselt_core::quadrature::AreaRule;
use nusselt_core::unobstructed::far_field::{self, PackedRule};
use nusselt_core::unobstructed::method::{self, Method, Options};
use nusselt_core::unobstructed::moments::{moment4_pair, moment_pair, Moments};
use nusselt_core::unobstructed::{analytic, contour};
use std::hint::black_box;

fn poly(v: &[[f64; 3]]) -> Polygon {
    Polygon::new(v.iter().map(|p| V::from_array(*p)).collect()).expect("valid benchmark polygon")
}

/// (name, emitter, receiver): each receiver faces its emitter.
fn cases() -> Vec<(&'static str, Polygon, Polygon)> {
    let quad = poly(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]]);
    let tri = poly(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    vec![
        // parallel, facing, 5 sizes apart: the far-field case of a large matrix
        (
            "quad-quad separated",
            quad.clone(),
            poly(&[[0.3, 0.2, 5.0], [0.3, 1.2, 5.0], [1.3, 1.2, 5.0], [1.3, 0.2, 5.0]]),
        ),
        // parallel, facing, one size apart, offset: a neighbour across a room
        ("quad-quad near", quad.clone(), poly(&[[0.5, 0.2, 1.0], [0.5, 1.2, 1.0], [1.5, 1.2, 1.0], [1.5, 0.2, 1.0]])),
        // perpendicular with a shared edge: the corner of every box
        (
            "quad-quad shared edge",
            quad.clone(),
            poly(&[[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 0.0, 0.0]]),
        ),
        // perpendicular with a shared vertex only
        ("quad-quad shared vertex", quad, poly(&[[1.0, 1.0, 0.0], [1.0, 1.0, 1.0], [2.0, 1.0, 1.0], [2.0, 1.0, 0.0]])),
        ("tri-tri separated", tri.clone(), poly(&[[0.2, 0.1, 5.0], [0.2, 1.1, 5.0], [1.2, 0.1, 5.0]])),
        ("tri-tri near", tri.clone(), poly(&[[0.4, 0.3, 0.8], [0.1, 1.0, 1.2], [1.2, 0.5, 0.9]])),
        ("tri-tri shared edge", tri, poly(&[[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])),
    ]
}

fn pair_kernels(c: &mut Criterion) {
    let mut g = c.benchmark_group("pair");
    g.throughput(Throughput::Elements(1));
    for (name, a, b) in cases() {
        g.bench_with_input(BenchmarkId::new("analytic", name), &(&a, &b), |bch, (a, b)| {
            bch.iter(|| analytic::polygon_pair(black_box(a), black_box(b)))
        });
        g.bench_with_input(BenchmarkId::new("contour8", name), &(&a, &b), |bch, (a, b)| {
            bch.iter(|| contour::polygon_pair(black_box(a), black_box(b), 8).unwrap())
        });
        for tol in [1e-6, 1e-10] {
            let opts = Options { tol, ..Default::default() };
            g.bench_with_input(BenchmarkId::new(format!("auto{tol:e}"), name), &(&a, &b), |bch, (a, b)| {
                bch.iter(|| method::area_factor(black_box(a), black_box(b), Method::Auto, &opts, None).unwrap())
            });
        }
        for tol in [1e-6, 1e-10] {
            // as in a scene: the polygons' rules are built once and reused by every pair
            let opts = Options { tol, ..Default::default() };
            let cache = method::RuleCache::new(2);
            g.bench_with_input(BenchmarkId::new(format!("auto{tol:e} cached"), name), &(&a, &b), |bch, (a, b)| {
                bch.iter(|| {
                    method::area_factor(black_box(a), black_box(b), Method::Auto, &opts, Some((&cache, 0, 1))).unwrap()
                })
            });
        }
    }
    g.finish();
    // the far-field kernel alone, per Gauss order on both quads (order^4 point pairs)
    let mut g = c.benchmark_group("far_pair");
    let (a, b) = (&cases()[0].1, &cases()[0].2);
    for order in [1, 2, 3, 4, 5, 6, 8] {
        let pa = PackedRule::new(&AreaRule::new(a, order), a);
        let pb = PackedRule::new(&AreaRule::new(b, order), b);
        g.throughput(Throughput::Elements((order * order * order * order) as u64));
        g.bench_with_input(BenchmarkId::new("quad-quad order", order), &(&pa, &pb), |bch, (pa, pb)| {
            bch.iter(|| far_field::far_pair(black_box(pa), a.normal(), black_box(pb), b.normal()))
        });
        let (ra, rb) = (AreaRule::new(a, order), AreaRule::new(b, order));
        g.bench_with_input(BenchmarkId::new("area_area quad-quad order", order), &(&ra, &rb), |bch, (ra, rb)| {
            bch.iter(|| far_field::area_area(black_box(ra), a.normal(), black_box(rb), b.normal()))
        });
    }
    // the second-moment rule (what most pairs of a large enclosure use at low accuracy)
    let (ma, mb) = (Moments::new(a), Moments::new(b));
    g.throughput(Throughput::Elements(1));
    g.bench_function("moment rule", |bch| bch.iter(|| moment_pair(black_box(&ma), black_box(&mb))));
    // fourth order (pairs of parallelograms; scalar here, vectorised in scene rows)
    g.bench_function("moment rule order 4", |bch| bch.iter(|| moment4_pair(black_box(&ma), black_box(&mb))));
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(30).measurement_time(std::time::Duration::from_secs(1))
        .warm_up_time(std::time::Duration::from_millis(300));
    targets = pair_kernels
}
criterion_main!(benches);
