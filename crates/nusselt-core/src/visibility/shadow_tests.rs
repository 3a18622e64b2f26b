use super::*;
use crate::visibility::bvh::tests::{ray_polygon, rect, Rng};

fn poly(v: &[[f64; 3]]) -> Polygon {
    Polygon::new(v.iter().map(|p| Vec3::from_array(*p)).collect()).unwrap()
}

/// Signed area of the visible part about the receiver's normal (holes subtract).
fn visible_area(p: Vec3, n: Vec3, rec: &Polygon, blockers: &[&Polygon]) -> f64 {
    visible_part(p, n, rec, blockers).iter().map(|c| 0.5 * newell_normal(c).dot(rec.normal())).sum()
}

fn floor() -> Polygon {
    rect(2, 0.0, (0., 1.), (0., 1.), true)
}

/// Regular n-gon of radius r centred on the z axis at height z, facing `up` or down.
fn ngon(r: f64, z: f64, n: usize, up: bool) -> Polygon {
    let mut v: Vec<Vec3> = (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            Vec3::new(r * a.cos(), r * a.sin(), z)
        })
        .collect();
    if !up {
        v.reverse();
    }
    Polygon::new(v).unwrap()
}

fn ngon_area(r: f64, n: usize) -> f64 {
    0.5 * n as f64 * r * r * (std::f64::consts::TAU / n as f64).sin()
}

const P: Vec3 = Vec3::new(0.5, 0.5, 1.0);
const DOWN: Vec3 = Vec3::new(0.0, 0.0, -1.0);

#[test]
fn unobstructed_is_the_receiver() {
    let f = floor();
    let parts = visible_part(P, DOWN, &f, &[]);
    assert_eq!(parts.len(), 1);
    assert!((visible_area(P, DOWN, &f, &[]) - 1.0).abs() < 1e-15);
    // p behind the receiver, or on its plane: it sees the back side, nothing is received
    assert!(visible_part(Vec3::new(0.5, 0.5, -1.0), Vec3::Z, &f, &[]).is_empty());
    assert!(visible_part(Vec3::new(2.0, 0.5, 0.0), -Vec3::X, &f, &[]).is_empty());
    // bad input
    assert!(visible_part(Vec3::NAN, DOWN, &f, &[]).is_empty());
    assert!(visible_part(P, Vec3::ZERO, &f, &[]).is_empty());
}

#[test]
fn receiver_is_clipped_to_the_points_front() {
    // p's element faces +x at x = 0.3: only x >= 0.3 of the floor is in front of it.
    let f = floor();
    let a = visible_area(Vec3::new(0.3, 0.5, 0.5), Vec3::X, &f, &[]);
    assert!((a - 0.7).abs() < 1e-14, "{a}");
}

#[test]
fn blocker_hiding_exactly_half() {
    // Blocker at half height over x in [0.5, 1.0]: its shadow from p (height 1) doubles about
    // p's foot, covering x in [0.5, 1.5] -> hides exactly the half x > 0.5.
    let f = floor();
    for up in [true, false] {
        let b = rect(2, 0.5, (0.5, 1.0), (-1.0, 2.0), up);
        let a = visible_area(P, DOWN, &f, &[&b]);
        assert!((a - 0.5).abs() < 1e-14, "{a}");
    }
}

#[test]
fn full_behind_source_behind_receiver_and_two_sided() {
    let f = floor();
    let big = rect(2, 0.5, (-1.0, 2.0), (-1.0, 2.0), true);
    assert!(visible_part(P, DOWN, &f, &[&big]).is_empty());
    let big_down = rect(2, 0.5, (-1.0, 2.0), (-1.0, 2.0), false);
    assert!(visible_part(P, DOWN, &f, &[&big_down]).is_empty());
    // behind the source point (above it), and behind the receiver (below it): no effect
    let above = rect(2, 1.5, (-1.0, 2.0), (-1.0, 2.0), true);
    let below = rect(2, -0.5, (-1.0, 2.0), (-1.0, 2.0), false);
    assert!((visible_area(P, DOWN, &f, &[&above, &below]) - 1.0).abs() < 1e-15);
    // a blocker in the receiver's plane (a neighbour patch) and one through p (edge-on)
    let neighbour = rect(2, 0.0, (1.0, 2.0), (0.0, 1.0), true);
    let edge_on = rect(0, 0.5, (-1.0, 2.0), (0.5, 1.0), true);
    assert!((visible_area(P, DOWN, &f, &[&neighbour, &edge_on]) - 1.0).abs() < 1e-15);
}

#[test]
fn coaxial_disc_blocker_area() {
    // docs/algorithms.md §8.3(a) with polygons: the blocker N-gon (r3, h3) casts from the apex an
    // N-gon of radius r3 h2 / h3 on the target plane; inside the target when r3/h3 <= r2/h2.
    // Source at the origin looking up, target at height h2 facing down.
    let nsides = 96;
    let (r2, h2) = (1.3, 2.0);
    let target = ngon(r2, h2, nsides, false);
    for (r3, h3) in [(0.3, 0.7), (0.5, 1.0), (0.6, 1.5)] {
        for up in [true, false] {
            let blocker = ngon(r3, h3, nsides, up);
            let a = visible_area(Vec3::ZERO, Vec3::Z, &target, &[&blocker]);
            let want = ngon_area(r2, nsides) - ngon_area(r3 * h2 / h3, nsides);
            assert!((a - want).abs() < 1e-13, "r3 {r3} h3 {h3}: {a} vs {want}");
            // one outer contour (CCW about the target normal) and one hole (CW)
            let parts = visible_part(Vec3::ZERO, Vec3::Z, &target, &[&blocker]);
            assert_eq!(parts.len(), 2);
            let areas: Vec<f64> = parts.iter().map(|c| 0.5 * newell_normal(c).dot(target.normal())).collect();
            assert!(areas.iter().filter(|a| **a > 0.0).count() == 1 && areas.iter().filter(|a| **a < 0.0).count() == 1);
            // all contour points lie on the target plane
            for c in &parts {
                for x in c {
                    assert!((x.z - h2).abs() < 1e-14);
                }
            }
        }
    }
    // r3/h3 > r2/h2: nothing visible
    assert!(visible_part(Vec3::ZERO, Vec3::Z, &target, &[&ngon(1.0, 1.0, nsides, true)]).is_empty());
}

#[test]
fn overlapping_blockers_union_not_double_subtraction() {
    // Two blockers at half height whose shadows (doubled about p's foot (0.5, 0.5)) are the
    // squares [0, 0.6]^2 and [0.4, 1]^2: union area 0.36 + 0.36 - 0.04 = 0.68.
    let f = floor();
    let b1 = rect(2, 0.5, (0.25, 0.55), (0.25, 0.55), true);
    let b2 = rect(2, 0.5, (0.45, 0.75), (0.45, 0.75), false);
    let a = visible_area(P, DOWN, &f, &[&b1, &b2]);
    assert!((a - (1.0 - 0.68)).abs() < 1e-14, "{a}");
    // the same blocker twice hides what it hides once
    let a1 = visible_area(P, DOWN, &f, &[&b1]);
    let a11 = visible_area(P, DOWN, &f, &[&b1, &b1]);
    assert!((a1 - (1.0 - 0.36)).abs() < 1e-14 && (a11 - a1).abs() < 1e-14);
}

#[test]
fn blocker_crossing_the_source_plane() {
    // Wall x = 0.75 over z in [0.2, 1.5] crosses p's plane z = 1. A ray from p to (x, y, 0)
    // meets x = 0.75 at z = 1 - 0.25 / (x - 0.5), which is >= 0.2 for x >= 0.8125.
    let f = floor();
    for up in [true, false] {
        let wall = rect(0, 0.75, (-1.0, 2.0), (0.2, 1.5), up);
        let a = visible_area(P, DOWN, &f, &[&wall]);
        assert!((a - 0.8125).abs() < 1e-14, "{a}");
    }
    // A wall reaching exactly up to p's height and beyond, right beside p, with p's element
    // tilted so that part of the floor is behind it.
    let wall = rect(0, 0.6, (-1.0, 2.0), (0.5, 3.0), true);
    let n = Vec3::new(-0.3, 0.0, -1.0).normalize();
    // Front of p's element: -0.3 (x - 0.5) - (z - 1) >= 0 -> on the floor x <= 0.5 + 1/0.3.
    // The wall hides x >= 0.5 + 0.1 / 0.5 = 0.7.
    let a = visible_area(P, n, &f, &[&wall]);
    assert!((a - 0.7).abs() < 1e-14, "{a}");
}

#[test]
fn concave_blocker_and_receiver() {
    // L-shaped receiver (area 3) seen from above its corner; an L-shaped blocker at half
    // height, whose shadow doubles about p's foot.
    let rec = poly(&[[0., 0., 0.], [2., 0., 0.], [2., 1., 0.], [1., 1., 0.], [1., 2., 0.], [0., 2., 0.]]);
    let p = Vec3::new(0.0, 0.0, 1.0);
    // blocker: L of the square [0, 0.5]^2 minus [0.25, 0.5]^2, at z = 0.5 -> shadow
    // [0, 1]^2 minus [0.5, 1]^2, area 0.75, all inside the receiver
    let b =
        poly(&[[0., 0., 0.5], [0.5, 0., 0.5], [0.5, 0.25, 0.5], [0.25, 0.25, 0.5], [0.25, 0.5, 0.5], [0., 0.5, 0.5]]);
    let a = visible_area(p, DOWN, &rec, &[&b]);
    assert!((a - (3.0 - 0.75)).abs() < 1e-14, "{a}");
}

#[test]
fn scale_and_translation_invariance() {
    let f = floor();
    let b1 = rect(2, 0.5, (0.25, 0.55), (0.25, 0.55), true);
    let wall = rect(0, 0.75, (-1.0, 2.0), (0.2, 1.5), true);
    let tilted = poly(&[[0.1, 0.2, 0.3], [0.7, 0.1, 0.6], [0.6, 0.8, 0.4]]);
    let base = visible_area(P, DOWN, &f, &[&b1, &wall, &tilted]);
    assert!(base > 0.1 && base < 0.9);
    let tr = |p: &Polygon, s: f64, o: Vec3| Polygon::new(p.vertices().iter().map(|v| v * s + o).collect()).unwrap();
    for (s, o) in
        [(1e-3, Vec3::ZERO), (1e3, Vec3::ZERO), (1.0, Vec3::new(1e3, -2e3, 5e2)), (1e-3, Vec3::new(7.0, 3.0, -1.0))]
    {
        let a = visible_area(P * s + o, DOWN, &tr(&f, s, o), &[&tr(&b1, s, o), &tr(&wall, s, o), &tr(&tilted, s, o)]);
        let rel = (a / (s * s) - base).abs() / base;
        let lim = if o == Vec3::ZERO { 1e-12 } else { 1e-9 }; // translation costs digits of o/s
        assert!(rel < lim, "scale {s} offset {o}: {rel:e}");
    }
}

/// Independent check: fraction of a fine grid of receiver points whose segment to p crosses
/// no blocker (plane intersection + winding number, no shadows, no booleans).
#[test]
fn random_blockers_match_point_sampling() {
    let mut rng = Rng::new(99);
    let rec = poly(&[[0., 0., 0.], [1.0, -0.1, 0.], [1.2, 0.9, 0.], [0.1, 1.0, 0.]]);
    let k = 160;
    for case in 0..6 {
        let p = Vec3::new(rng.range(0.2, 0.8), rng.range(0.2, 0.8), rng.range(0.6, 1.2));
        let n = (DOWN + 0.4 * rng.unit()).normalize();
        // regular polygons tilted up to ~35 degrees from horizontal, facing either way
        let blockers: Vec<Polygon> =
            (0..6).map(|_| random_blocker(&mut rng, p, (0.0, 1.0), (0.05, 0.2), 0.7, 3)).collect();
        let refs: Vec<&Polygon> = blockers.iter().collect();
        let got = visible_area(p, n, &rec, &refs);
        // Midpoint grid over the receiver's bounding box, kept where inside the receiver.
        let mut seen = 0.0;
        let mut f_grid = 0.0;
        let cell = 1.3 * 1.1 / (k * k) as f64;
        for i in 0..k {
            for j in 0..k {
                let x =
                    Vec3::new(-0.05 + 1.3 * (i as f64 + 0.5) / k as f64, -0.1 + 1.1 * (j as f64 + 0.5) / k as f64, 0.0);
                if ray_polygon(&rec, x + Vec3::Z, -Vec3::Z).is_none() || n.dot(x - p) < 0.0 {
                    continue;
                }
                let blocked = blockers.iter().any(|b| ray_polygon(b, p, x - p).is_some_and(|t| t > 0.0 && t < 1.0));
                if !blocked {
                    seen += cell;
                    let d = x - p;
                    let r2 = d.length_squared();
                    f_grid += cell * n.dot(d) * p.z / (std::f64::consts::PI * r2 * r2);
                }
            }
        }
        // grid error ~ boundary length x cell size
        assert!(got < 0.9 * rec.area(), "case {case}: blockers hide too little ({got})");
        assert!((got - seen).abs() < 0.002, "case {case}: shadow {got} vs grid {seen}");
        // the view factor against the same grid weighted by cos cos / (pi r^2)
        let f = point_visible_view_factor(p, n, &rec, &refs);
        assert!((f - f_grid).abs() < 2e-3 * f.max(0.05), "case {case}: F {f} vs grid {f_grid}");
    }
}

fn f_vis(p: Vec3, n: Vec3, rec: &Polygon, blockers: &[&Polygon]) -> f64 {
    point_visible_view_factor(p, n, rec, blockers)
}

/// Unobstructed Lambert F to a polygon's own outline (flipped to face p if needed).
fn f_plain(p: Vec3, n: Vec3, poly: &Polygon) -> f64 {
    crate::unobstructed::analytic::point_contour(p, n, poly.vertices()).abs()
}

#[test]
fn lambert_matches_corner_rectangle_formula_and_quadrature() {
    // dA on the axis of a square (side 1) at distance 1 = 4 x corner rectangle 0.5 x 0.5
    // (Howell B-3): F = (1/2pi) [A/sqrt(1+A^2) atan(B/sqrt(1+A^2)) + (A <-> B)], A = B = 0.5.
    let (a, b) = (0.5f64, 0.5f64);
    let corner = (a / (1.0 + a * a).sqrt() * (b / (1.0 + a * a).sqrt()).atan()
        + b / (1.0 + b * b).sqrt() * (a / (1.0 + b * b).sqrt()).atan())
        / std::f64::consts::TAU;
    // midpoint quadrature of cos cos / (pi r^2) over the square: checks the closed form
    let k = 400;
    let mut quad = 0.0;
    for i in 0..k {
        for j in 0..k {
            let (x, y) = ((i as f64 + 0.5) / k as f64 - 0.5, (j as f64 + 0.5) / k as f64 - 0.5);
            let r2 = x * x + y * y + 1.0;
            quad += 1.0 / (std::f64::consts::PI * r2 * r2) / (k * k) as f64;
        }
    }
    assert!((quad - 4.0 * corner).abs() < 1e-6, "{quad} {}", 4.0 * corner);
    let f = f_vis(P, DOWN, &floor(), &[]);
    assert!((f - 4.0 * corner).abs() < 1e-15, "{f}");
    assert!((f - 0.239456).abs() < 1e-6);
}

#[test]
fn coaxial_disc_blocker_view_factor() {
    // docs/algorithms.md §8.3(a): with the blocker's central shadow inside the target,
    // F_visible = F(target) - F(blocker), both unobstructed (same polygonal geometry).
    let nsides = 128;
    let (r2, h2) = (1.3, 2.0);
    let target = ngon(r2, h2, nsides, false);
    let disc = |r: f64, h: f64| r * r / (h * h + r * r);
    for (r3, h3) in [(0.3, 0.7), (0.5, 1.0), (0.6, 1.5)] {
        for up in [true, false] {
            let blocker = ngon(r3, h3, nsides, up);
            let f = f_vis(Vec3::ZERO, Vec3::Z, &target, &[&blocker]);
            let want = f_plain(Vec3::ZERO, Vec3::Z, &target) - f_plain(Vec3::ZERO, Vec3::Z, &blocker);
            assert!((f - want).abs() < 1e-14, "{f} vs {want}");
            // and the discs' closed form, up to the polygon's O(1/N^2) shortfall
            let exact_disc = disc(r2, h2) - disc(r3, h3);
            assert!((f - exact_disc).abs() < 1e-3, "{f} vs disc {exact_disc}");
        }
    }
    assert_eq!(f_vis(Vec3::ZERO, Vec3::Z, &target, &[&ngon(1.0, 1.0, nsides, true)]), 0.0);
}

#[test]
fn view_factor_half_hidden_crossing_two_sided_and_scaled() {
    let f = floor();
    let half = rect(2, 0.0, (0.0, 0.5), (0.0, 1.0), true);
    let b = rect(2, 0.5, (0.5, 1.0), (-1.0, 2.0), true);
    let b_rev = rect(2, 0.5, (0.5, 1.0), (-1.0, 2.0), false);
    let want = f_plain(P, DOWN, &half);
    assert!((f_vis(P, DOWN, &f, &[&b]) - want).abs() < 1e-15);
    assert!((f_vis(P, DOWN, &f, &[&b_rev]) - want).abs() < 1e-15);
    // symmetric about x = 0.5: half of the whole
    assert!((2.0 * want - f_plain(P, DOWN, &f)).abs() < 1e-15);
    // wall crossing the source plane: visible strip x in [0, 0.8125]
    let wall = rect(0, 0.75, (-1.0, 2.0), (0.2, 1.5), false);
    let strip = rect(2, 0.0, (0.0, 0.8125), (0.0, 1.0), true);
    assert!((f_vis(P, DOWN, &f, &[&wall]) - f_plain(P, DOWN, &strip)).abs() < 1e-14);
    // behind source / behind receiver: no effect
    let above = rect(2, 1.5, (-1.0, 2.0), (-1.0, 2.0), true);
    let below = rect(2, -0.5, (-1.0, 2.0), (-1.0, 2.0), false);
    assert_eq!(f_vis(P, DOWN, &f, &[&above, &below]), f_plain(P, DOWN, &f));
    // scale invariance of F
    let tilted = poly(&[[0.1, 0.2, 0.3], [0.7, 0.1, 0.6], [0.6, 0.8, 0.4]]);
    let base = f_vis(P, DOWN, &f, &[&b, &wall, &tilted]);
    assert!(base > 0.01);
    let sc = |p: &Polygon, s: f64| Polygon::new(p.vertices().iter().map(|v| v * s).collect()).unwrap();
    for s in [1e-3, 1e3] {
        let fs = f_vis(P * s, DOWN, &sc(&f, s), &[&sc(&b, s), &sc(&wall, s), &sc(&tilted, s)]);
        assert!((fs - base).abs() < 1e-12 * base, "{s}: {fs} vs {base}");
    }
    assert!(f_vis(Vec3::NAN, DOWN, &f, &[]).is_nan());
}

/// `cargo test -p nusselt-core --release --lib visibility::shadow::tests::bench_visible -- --ignored --nocapture`
#[test]
#[ignore]
fn bench_visible() {
    let f = floor();
    let b1 = rect(2, 0.5, (0.25, 0.55), (0.25, 0.55), true);
    let wall = rect(0, 0.75, (-1.0, 2.0), (0.2, 1.5), true);
    let tilted = poly(&[[0.1, 0.2, 0.3], [0.7, 0.1, 0.6], [0.6, 0.8, 0.4]]);
    let n = 20_000;
    let t = std::time::Instant::now();
    let mut acc = 0.0;
    for i in 0..n {
        let p = Vec3::new(0.3 + 0.4 * (i as f64 / n as f64), 0.5, 1.0);
        acc += point_visible_view_factor(p, DOWN, &f, &[&b1, &wall, &tilted]);
    }
    let dt = t.elapsed().as_secs_f64() / n as f64;
    println!("point_visible_view_factor, 3 blockers: {:.1} us/call (mean F {:.4})", dt * 1e6, acc / n as f64);
    // a blocker meshed into 20 x 20 tiles
    let tiles: Vec<Polygon> = (0..400)
        .map(|k| {
            rect(
                2,
                0.5,
                (0.2 + 0.02 * (k % 20) as f64, 0.22 + 0.02 * (k % 20) as f64),
                (0.2 + 0.02 * (k / 20) as f64, 0.22 + 0.02 * (k / 20) as f64),
                true,
            )
        })
        .collect();
    let refs: Vec<&Polygon> = tiles.iter().collect();
    let t = std::time::Instant::now();
    let mut acc = 0.0;
    for i in 0..n / 20 {
        let p = Vec3::new(0.3 + 0.4 * (i as f64 / (n / 20) as f64), 0.5, 1.0);
        acc += point_visible_view_factor(p, DOWN, &f, &refs);
    }
    println!(
        "20 x 20 tiles: {:.1} us/call (mean F {:.4})",
        t.elapsed().as_secs_f64() / (n / 20) as f64 * 1e6,
        acc / (n / 20) as f64
    );
    let t = std::time::Instant::now();
    let mut free = 0.0;
    for i in 0..n {
        let p = Vec3::new(0.3 + 0.4 * (i as f64 / n as f64), 0.5, 1.0);
        free += point_visible_view_factor(p, DOWN, &f, &[]);
    }
    println!("no blockers: {:.2} us/call (mean F {:.4})", t.elapsed().as_secs_f64() / n as f64 * 1e6, free / n as f64);
}

#[test]
fn shadowed_part_is_free_minus_visible_and_zero_without_shadow() {
    let f = floor();
    let up = Vec3::new(0.0, 0.0, 1.0);
    // Blocker over the half x < 0.5 of the floor, the point above the floor's centre.
    let half = rect(2, 0.5, (0., 0.5), (0., 1.), true);
    let b = [&half];
    let free = f_plain(P, DOWN, &f);
    let vis = f_vis(P, DOWN, &f, &b);
    let hid = point_shadowed_view_factor(P, DOWN, &f, &b);
    assert!((hid - (free - vis)).abs() < 1e-14, "{hid} {free} {vis}");
    assert!((hid - 0.5 * free).abs() < 1e-12, "symmetric: half hidden");
    // A blocker off to the side, between nothing: exactly 0, not a rounding residue.
    let aside = rect(2, 0.5, (3., 4.), (3., 4.), true);
    assert_eq!(point_shadowed_view_factor(P, DOWN, &f, &[&aside]), 0.0);
    assert_eq!(point_shadowed_view_factor(P, DOWN, &f, &[]), 0.0);
    // Point behind the receiver: nothing visible, nothing hidden.
    assert_eq!(point_shadowed_view_factor(Vec3::new(0.5, 0.5, -1.0), up, &f, &b), 0.0);
    assert!(point_shadowed_view_factor(Vec3::NAN, DOWN, &f, &b).is_nan());
}

/// Random receiver point and blockers between it and a receiver: convex tilted n-gons, and
/// (when `tiles`) a flat blocker cut into edge-adjacent tiles, as meshed scenes have.
/// A regular polygon (3 to 2 + `sides` corners, `size` its circumradius range) centred on the
/// segment from `p` to a random point of the square `span` x `span` at z = 0, some beyond
/// either end; its normal is ±z plus up to `tilt` of a random direction.
fn random_blocker(rng: &mut Rng, p: Vec3, span: (f64, f64), size: (f64, f64), tilt: f64, sides: usize) -> Polygon {
    let y = Vec3::new(rng.range(span.0, span.1), rng.range(span.0, span.1), 0.0);
    let c = p + rng.range(-0.1, 1.1) * (y - p);
    let s = rng.range(size.0, size.1);
    let nb = (Vec3::Z * if rng.f() < 0.5 { 1.0 } else { -1.0 } + tilt * rng.unit()).normalize();
    let (t, b) = crate::geometry::tangent_frame(nb);
    let m = 3 + (rng.f() * sides as f64) as usize;
    let ph = rng.f();
    let vs = (0..m)
        .map(|k| {
            let a = std::f64::consts::TAU * (k as f64 + ph) / m as f64;
            c + s * (a.cos() * t + a.sin() * b)
        })
        .collect();
    Polygon::new(vs).unwrap()
}

fn random_case(rng: &mut Rng, tiles: bool) -> (Vec3, Vec3, Vec<Polygon>) {
    let p = Vec3::new(rng.range(-0.2, 1.2), rng.range(-0.2, 1.2), rng.range(0.3, 1.5));
    let n = (DOWN + 0.8 * rng.unit()).normalize();
    let mut blockers: Vec<Polygon> =
        (0..1 + (rng.f() * 4.0) as usize).map(|_| random_blocker(rng, p, (-0.2, 1.2), (0.02, 0.5), 1.2, 4)).collect();
    if tiles {
        let z = rng.range(0.05, 0.9) * p.z;
        let (x0, y0) = (rng.range(-0.3, 0.8), rng.range(-0.3, 0.8));
        let (k, h) = (2 + (rng.f() * 3.0) as usize, rng.range(0.05, 0.3));
        for i in 0..k {
            for j in 0..k {
                let (x, y) = (x0 + i as f64 * h, y0 + j as f64 * h);
                blockers.push(rect(2, z, (x, x + h), (y, y + h), rng.f() < 0.5));
            }
        }
    }
    (p, n, blockers)
}

#[test]
fn convex_path_matches_the_boolean() {
    let mut rng = Rng::new(2024);
    let recs =
        [floor(), poly(&[[0., 0., 0.], [1.0, -0.1, 0.], [1.2, 0.9, 0.], [0.1, 1.0, 0.]]), ngon(0.6, 0.0, 7, true)];
    let (mut convex, mut shadowed) = (0, 0);
    for case in 0..3000 {
        let rec = &recs[case % recs.len()];
        let (p, n, blockers) = random_case(&mut rng, case % 2 == 1);
        let refs: Vec<&Polygon> = blockers.iter().collect();
        let Some(cast) = cast(p, n, rec, &refs) else { continue };
        let fast = shadowed_convex(p, n, &cast);
        let slow = shadowed_boolean(p, n, &cast);
        if let Some(fast) = fast {
            convex += 1;
            shadowed += (slow > 0.0) as usize;
            let free = crate::unobstructed::analytic::point_contour(p, n, &cast.rec);
            assert!((fast - slow).abs() <= 1e-12 * free.max(1e-3), "case {case}: convex {fast} vs boolean {slow}");
        }
        // the public entry points agree with the boolean either way
        let hid = point_shadowed_view_factor(p, n, rec, &refs);
        assert!((hid - slow).abs() < 1e-12, "case {case}: {hid} vs {slow}");
    }
    assert!(convex > 2000 && shadowed > 1000, "{convex} convex cases, {shadowed} with a shadow");
}

#[test]
fn convex_path_special_cases() {
    let f = floor();
    // shadow covering the whole receiver: all of Lambert hidden
    let big = rect(2, 0.5, (-1.0, 2.0), (-1.0, 2.0), true);
    let cast1 = cast(P, DOWN, &f, &[&big]).unwrap();
    let hid = shadowed_convex(P, DOWN, &cast1).unwrap();
    assert!((hid - f_plain(P, DOWN, &f)).abs() < 1e-15);
    // the same cover as 3 x 3 edge-adjacent tiles and a duplicate on top: no double counting
    let tiles: Vec<Polygon> = (0..9)
        .map(|k| {
            rect(2, 0.5, (-1.0 + (k % 3) as f64, (k % 3) as f64), (-1.0 + (k / 3) as f64, (k / 3) as f64), k % 2 == 0)
        })
        .collect();
    let mut refs: Vec<&Polygon> = tiles.iter().collect();
    refs.push(&big);
    let cast2 = cast(P, DOWN, &f, &refs).unwrap();
    assert!((shadowed_convex(P, DOWN, &cast2).unwrap() - hid).abs() < 1e-14);
    // a concave blocker (L shape) is left to the boolean
    let l =
        poly(&[[0.2, 0.2, 0.5], [0.8, 0.2, 0.5], [0.8, 0.4, 0.5], [0.4, 0.4, 0.5], [0.4, 0.8, 0.5], [0.2, 0.8, 0.5]]);
    let cast3 = cast(P, DOWN, &f, &[&l]).unwrap();
    assert!(shadowed_convex(P, DOWN, &cast3).is_none());
    assert!(point_shadowed_view_factor(P, DOWN, &f, &[&l]) > 0.0);
}

#[test]
fn edge_adjacent_shadows_join_where_the_union_is_convex() {
    let sq = |x: f64, y: f64| vec![[x, y], [x + 1.0, y], [x + 1.0, y + 1.0], [x, y + 1.0]];
    // a 3 x 3 grid of tiles: one square with its four corners only
    let mut grid: Vec<Cow<[[f64; 2]]>> = (0..9).map(|k| Cow::Owned(sq((k % 3) as f64, (k / 3) as f64))).collect();
    merge_adjacent(&mut grid);
    assert_eq!(grid.len(), 1);
    let mut corners = grid[0].to_vec();
    corners.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert_eq!(corners, vec![[0.0, 0.0], [0.0, 3.0], [3.0, 0.0], [3.0, 3.0]]);
    // an L of three tiles: its union is not convex, so two shadows remain (same total area)
    let mut ell: Vec<Cow<[[f64; 2]]>> = vec![sq(0.0, 0.0).into(), sq(1.0, 0.0).into(), sq(0.0, 1.0).into()];
    merge_adjacent(&mut ell);
    assert_eq!(ell.len(), 2);
    assert!(ell.iter().all(|s| is_convex(s)));
    assert_eq!(ell.iter().map(|s| signed_area(s)).sum::<f64>(), 3.0);
    // a shared point or a partly shared edge (T-junction) is no joint
    let mut apart: Vec<Cow<[[f64; 2]]>> =
        vec![sq(0.0, 0.0).into(), sq(1.0, 1.0).into(), vec![[1.0, -0.5], [2.0, -0.5], [2.0, 0.5], [1.0, 0.5]].into()];
    merge_adjacent(&mut apart);
    assert_eq!(apart.len(), 3);
}

#[test]
fn meshed_and_nested_shadows_in_the_convex_path() {
    // shadows of a meshed blocker in the convex path: the same F as the boolean
    let f = floor();
    let tiles: Vec<Polygon> = (0..16)
        .map(|k| {
            rect(
                2,
                0.5,
                (0.1 + 0.2 * (k % 4) as f64, 0.3 + 0.2 * (k % 4) as f64),
                (0.1 + 0.2 * (k / 4) as f64, 0.3 + 0.2 * (k / 4) as f64),
                k % 3 == 0,
            )
        })
        .collect();
    let refs: Vec<&Polygon> = tiles.iter().collect();
    let c = cast(P, DOWN, &f, &refs).unwrap();
    let (fast, slow) = (shadowed_convex(P, DOWN, &c).unwrap(), shadowed_boolean(P, DOWN, &c));
    assert!((fast - slow).abs() < 1e-14 && slow > 0.1, "{fast} vs {slow}");
    // 6 x 6 tiles: enough shadows to be joined first (MERGE_FROM)
    let fine: Vec<Polygon> = (0..36)
        .map(|k| {
            rect(
                2,
                0.5,
                (0.3 + 0.06 * (k % 6) as f64, 0.36 + 0.06 * (k % 6) as f64),
                (0.3 + 0.06 * (k / 6) as f64, 0.36 + 0.06 * (k / 6) as f64),
                k % 5 == 0,
            )
        })
        .collect();
    let refs: Vec<&Polygon> = fine.iter().collect();
    let c = cast(P, DOWN, &f, &refs).unwrap();
    assert!(c.shadows.len() >= MERGE_FROM);
    let (fast, slow) = (shadowed_convex(P, DOWN, &c).unwrap(), shadowed_boolean(P, DOWN, &c));
    assert!((fast - slow).abs() < 1e-14 && slow > 0.1, "{fast} vs {slow}");
    // the walls of two coaxial open prisms standing on the receiver: 24 shadows, nested and
    // overlapping, subtracted in any order
    let walls: Vec<Polygon> = [0.15, 0.3]
        .iter()
        .flat_map(|&r| {
            (0..12).map(move |k| {
                let (a0, a1) = (std::f64::consts::TAU * k as f64 / 12.0, std::f64::consts::TAU * (k + 1) as f64 / 12.0);
                let at = |a: f64, z: f64| [0.4 + r * a.cos(), 0.6 + r * a.sin(), z];
                poly(&[at(a0, 0.0), at(a1, 0.0), at(a1, 0.3), at(a0, 0.3)])
            })
        })
        .collect();
    let refs: Vec<&Polygon> = walls.iter().collect();
    for p in [Vec3::new(0.5, 0.5, 1.0), Vec3::new(1.3, -0.2, 0.6), Vec3::new(0.45, 0.62, 0.4)] {
        let c = cast(p, DOWN, &f, &refs).unwrap();
        assert!(c.shadows.len() >= 12);
        let (fast, slow) = (shadowed_convex(p, DOWN, &c).unwrap(), shadowed_boolean(p, DOWN, &c));
        assert!((fast - slow).abs() < 1e-14 && slow > 0.01, "{p:?}: {fast} vs {slow}");
    }
}

/// `hides_whole` against segment sampling: whenever it says a blocker hides a target
/// triangle from a source triangle, random segments between them all hit the blocker, and
/// the exact visible F from random source points is 0; its cases are common enough to matter.
#[test]
fn hides_whole_only_when_every_segment_is_blocked() {
    let mut rng = Rng::new(7);
    let tri = |rng: &mut Rng, z: f64, s: f64| -> Vec<Vec3> {
        let c = Vec3::new(rng.range(-0.5, 0.5), rng.range(-0.5, 0.5), z);
        (0..3).map(|_| c + s * Vec3::new(rng.range(-1., 1.), rng.range(-1., 1.), rng.range(-0.2, 0.2))).collect()
    };
    let (mut hidden, mut open) = (0, 0);
    for case in 0..400 {
        let src = tri(&mut rng, 0.0, 0.3);
        let dst = tri(&mut rng, 2.0, 0.3);
        // a tilted regular polygon (3 to 6 corners) between them
        let c = Vec3::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), rng.range(0.6, 1.4));
        let nb = (Vec3::Z + 0.5 * rng.unit()).normalize();
        let (t, u) = crate::geometry::tangent_frame(nb);
        let (m, r, ph) = (3 + (rng.f() * 4.0) as usize, rng.range(0.3, 1.2), rng.f());
        let b = Polygon::new(
            (0..m)
                .map(|k| {
                    let a = std::f64::consts::TAU * (k as f64 + ph) / m as f64;
                    c + r * (a.cos() * t + a.sin() * u)
                })
                .collect(),
        )
        .unwrap();
        if !hides_whole(&src, &dst, &b) {
            open += 1;
            continue;
        }
        hidden += 1;
        let dst_poly = Polygon::new(dst.clone()).unwrap();
        for _ in 0..200 {
            let w = |rng: &mut Rng, v: &[Vec3]| {
                let (a, c) = (rng.f(), rng.f());
                let (a, c) = if a + c > 1.0 { (1.0 - a, 1.0 - c) } else { (a, c) };
                v[0] + a * (v[1] - v[0]) + c * (v[2] - v[0])
            };
            let (x, y) = (w(&mut rng, &src), w(&mut rng, &dst));
            assert!(
                ray_polygon(&b, x, y - x).is_some_and(|t| t > 0.0 && t < 1.0),
                "case {case}: segment {x} -> {y} passes"
            );
        }
        let x = src[0] + 0.3 * (src[1] - src[0]) + 0.3 * (src[2] - src[0]);
        let n = (dst_poly.centroid() - x).normalize();
        assert_eq!(point_visible_view_factor(x, n, &dst_poly, &[&b]), 0.0, "case {case}");
    }
    assert!(hidden > 30 && open > 30, "{hidden} hidden, {open} open");
}

/// A U-shaped (concave) blocker can catch every vertex-to-vertex segment while the notch lets
/// the middle through: never "hidden". The same outline's convex hull does hide.
#[test]
fn hides_whole_needs_a_convex_blocker() {
    let u = poly(&[
        [-2., -2., 1.],
        [2., -2., 1.],
        [2., 2., 1.],
        [0.5, 2., 1.],
        [0.5, 0., 1.],
        [-0.5, 0., 1.],
        [-0.5, 2., 1.],
        [-2., 2., 1.],
    ]);
    let p = [Vec3::ZERO];
    // target corners project to (+-0.8, +-0.8) in the blocker's plane: all in the U, the
    // target's centre line (0, 0.8) in the notch
    let target: Vec<Vec3> =
        [[-1.6, -1.6], [1.6, -1.6], [1.6, 1.6], [-1.6, 1.6]].iter().map(|c| Vec3::new(c[0], c[1], 2.0)).collect();
    assert!(ray_polygon(&u, p[0], Vec3::new(0.0, 1.6, 2.0)).is_none());
    assert!(!hides_whole(&p, &target, &u));
    let hull = poly(&[[-2., -2., 1.], [2., -2., 1.], [2., 2., 1.], [-2., 2., 1.]]);
    assert!(hides_whole(&p, &target, &hull));
    // a source straddling the blocker's plane, or a target reaching past its outline: not hidden
    assert!(!hides_whole(&[Vec3::ZERO, Vec3::new(0.0, 0.0, 1.5)], &target, &hull));
    let wide: Vec<Vec3> = target.iter().map(|v| Vec3::new(4.2 * v.x / 1.6, v.y, 2.0)).collect();
    assert!(!hides_whole(&p, &wide, &hull));
}

/// A blocker passing 1e-10 above p, nearly parallel to p's plane, hides everything but the
/// wedge between them: the visible part of the receiver is the same triangle V from every
/// such p (the blocker's plane separates p from the rest), so F is Lambert's over V. The
/// blocker's part nearer p's height than 1e-9 of p's height above the receiver used to be
/// cut off: F 0.029 at (0.49, -0.01, 0) instead of 5e-16.
#[test]
fn a_blocker_passing_just_above_the_point_hides_all_but_the_wedge() {
    let g = 1e-8;
    let receiver = poly(&[[0., 0., 0.], [0., 0., -1.], [1., 0., 1.]]);
    let blocker = poly(&[[0., -1., 0.], [0., 0., g], [1., 1., 0.]]);
    let x = g / (1.0 + 2.0 * g);
    let wedge = [Vec3::new(0., 0., 0.), Vec3::new(0.5, 0., 0.), Vec3::new(x, 0., x)];
    for (px, d) in [(0.49, 0.01), (0.45, 0.01), (0.3, 0.01), (0.3, 1e-6), (0.1, 1e-8)] {
        let p = Vec3::new(px, -d, 0.0);
        let f = point_visible_view_factor(p, Vec3::Z, &receiver, &[&blocker]);
        let exact = crate::unobstructed::analytic::point_contour(p, Vec3::Z, &wedge).abs();
        assert!((f - exact).abs() <= 1e-6 * exact + 1e-15, "p {p}: {f:e} against {exact:e}");
    }
}

/// A wall at z = 1 meshed into 3 x 3 unit tiles between two unit squares: no tile alone hides
/// the pair, the tiles together do (every random segment hits one of them). Without the
/// centre tile, or with the tiles 1e-3 apart, segments pass and the answer is false; a plate
/// behind the missing tile that catches every segment through the hole makes it true again.
/// The answers are the same for the scene scaled by 1e-3 or 1e3 and moved.
#[test]
fn tiles_of_a_wall_hide_together_and_only_when_they_cover() {
    let tiles = |gap: f64, skip: Option<(usize, usize)>, s: f64, off: f64| -> Vec<Polygon> {
        let mut out = Vec::new();
        for i in 0..3 {
            for j in 0..3 {
                if skip == Some((i, j)) {
                    continue;
                }
                let (x0, y0) = (i as f64 - 1.0 + gap, j as f64 - 1.0 + gap);
                let (x1, y1) = (i as f64 - gap, j as f64 - gap);
                let v = [[x0, y0, 1.0], [x1, y0, 1.0], [x1, y1, 1.0], [x0, y1, 1.0]];
                out.push(poly(&v.map(|p| p.map(|c| s * c + off))));
            }
        }
        out
    };
    let square = |z: f64, s: f64, off: f64| -> Vec<Vec3> {
        [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
            .iter()
            .map(|c| Vec3::new(s * (c[0] - 0.5) + off, s * (c[1] - 0.5) + off, s * z + off))
            .collect()
    };
    let blocked_by = |src: &[Vec3], dst: &[Vec3], bl: &[Polygon], rng: &mut Rng| -> bool {
        (0..2000).all(|_| {
            let w = |v: &[Vec3], rng: &mut Rng| {
                let (a, b) = (rng.f(), rng.f());
                v[0] + a * (v[1] - v[0]) + b * (v[3] - v[0])
            };
            let (x, y) = (w(src, rng), w(dst, rng));
            bl.iter().any(|b| ray_polygon(b, x, y - x).is_some_and(|t| t > 0.0 && t < 1.0))
        })
    };
    let mut rng = Rng::new(11);
    for (s, off) in [(1.0, 0.0), (1e-3, 7.0), (1e3, -5e3)] {
        let (src, dst) = (square(0.0, s, off), square(2.0, s, off));
        let whole = tiles(0.0, None, s, off);
        let refs: Vec<&Polygon> = whole.iter().collect();
        assert!(refs.iter().all(|b| !hides_whole(&src, &dst, b)));
        assert!(hides_whole_together(&src, &dst, &refs, 0.0), "scale {s}");
        if s == 1.0 {
            assert!(blocked_by(&src, &dst, &whole, &mut rng));
        }
        for (gap, skip) in [(0.0, Some((1, 1))), (1e-3, None)] {
            let open = tiles(gap, skip, s, off);
            let refs: Vec<&Polygon> = open.iter().collect();
            assert!(!hides_whole_together(&src, &dst, &refs, 0.0), "scale {s}, gap {gap}");
            if s == 1.0 {
                assert!(!blocked_by(&src, &dst, &open, &mut rng), "gap {gap}");
            }
        }
        // the centre tile missing, and behind the hole a plate at z = 1.2: hidden if the plate
        // catches every segment through the hole (it does from [-0.2, 1]^2 on; [0, 1]^2 lets
        // some pass), which only following the segments through both planes shows
        for (lo, covers) in [(-0.2, true), (0.0, false)] {
            let mut two = tiles(0.0, Some((1, 1)), s, off);
            let plate = [[lo, lo, 1.2], [1.0, lo, 1.2], [1.0, 1.0, 1.2], [lo, 1.0, 1.2]];
            two.push(poly(&plate.map(|p| p.map(|c| s * c + off))));
            let refs: Vec<&Polygon> = two.iter().collect();
            assert!(refs.iter().all(|b| !hides_whole(&src, &dst, b)));
            assert_eq!(hides_whole_together(&src, &dst, &refs, 0.0), covers, "scale {s}, plate from {lo}");
            if s == 1.0 {
                assert_eq!(blocked_by(&src, &dst, &two, &mut rng), covers, "plate from {lo}");
            }
        }
        // a source reaching through the wall's plane: not claimed
        let tall = [src[0], src[1], src[2] + Vec3::new(0.0, 0.0, 1.5 * s), src[3]];
        assert!(!hides_whole_together(&tall, &dst, &tiles(0.0, None, s, off).iter().collect::<Vec<_>>(), 1e-9));
    }
}

/// A floor and, past a partition tiled in two, the next room's ceiling: the floor's edge lies
/// on the partition's plane (as in any closed model), so the strict test never claims the pair;
/// with the band of 1e-9 it does, and every segment between interior points hits a tile. A
/// partition ending below what the steepest segment needs lets some through: false either way.
#[test]
fn a_partition_touching_the_floor_hides_with_the_band() {
    let floor = [[-1.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.5, 1.0, 0.0], [-1.0, 1.0, 0.0]].map(Vec3::from_array);
    let ceiling = [[0.6, 0.0, 1.0], [0.6, 1.0, 1.0], [2.0, 1.0, 1.0], [2.0, 0.0, 1.0]].map(Vec3::from_array);
    let tiles = |top: f64| {
        let tile = |z0: f64, z1: f64| poly(&[[0.5, 0.0, z0], [0.5, 0.0, z1], [0.5, 1.0, z1], [0.5, 1.0, z0]]);
        vec![tile(0.0, 0.5 * top), tile(0.5 * top, top)]
    };
    let mut rng = Rng::new(5);
    for (top, hidden) in [(1.0, true), (0.9, false)] {
        let wall = tiles(top);
        let refs: Vec<&Polygon> = wall.iter().collect();
        assert!(refs.iter().all(|b| !hides_whole(&floor, &ceiling, b)));
        assert!(!hides_whole_together(&floor, &ceiling, &refs, 0.0), "top {top}");
        assert_eq!(hides_whole_together(&floor, &ceiling, &refs, 1e-9), hidden, "top {top}");
        let passes = (0..4000).any(|_| {
            let w = |v: &[Vec3], rng: &mut Rng| v[0] + rng.f() * (v[1] - v[0]) + rng.f() * (v[3] - v[0]);
            let (x, y) = (w(&floor, &mut rng), w(&ceiling, &mut rng));
            !wall.iter().any(|b| ray_polygon(b, x, y - x).is_some_and(|t| t > 0.0 && t < 1.0))
        });
        assert_eq!(passes, !hidden, "top {top}");
    }
}

/// A blocker in a plane parallel to p's surface element, a tiny height e in front of p, hides
/// all of a receiver well in front of it when p's foot lies inside it (every ray crosses the
/// blocker's plane within e |q - p| / (q - p).x of the foot, here < 1e-5) and nothing when
/// the foot lies outside: the answer is the whole free F or 0, exactly. The cut of the
/// projection a little below p's height (2.2e-13 of the coordinates) let every ray through
/// below e of about 6e-13: F 0 became the whole free F.
#[test]
fn a_blocker_hovering_over_p_hides_all_or_nothing() {
    let receiver = [[0.1, -0.5, 0.0], [1.0, -0.5, 0.0], [0.5, 0.8, 0.0]];
    let over_foot = [[0.0, -3.0, -3.0], [0.0, 3.0, -3.0], [0.0, 0.0, 3.0]];
    let beside_foot = [[0.0, 1.0, -3.0], [0.0, 4.0, -3.0], [0.0, 2.5, 3.0]];
    let p0 = Vec3::new(0.0, 0.3, 0.5);
    for (scale, shift) in [(1.0, 0.0), (1e-6, 7e-6), (1.0, 100.0), (1e6, -3e6f64)] {
        for e in [3e-13, 1e-11, 1e-8, 1e-5] {
            if e * scale <= 1e3 * f64::EPSILON * (shift.abs() + scale) {
                continue; // p on the blocker's plane within rounding
            }
            let place = |v: &[[f64; 3]; 3], dx: f64| {
                poly(&v.map(|q| [(q[0] + dx) * scale + shift, q[1] * scale + shift, q[2] * scale + shift]))
            };
            let rec = place(&receiver, 0.0);
            let p = p0 * scale + Vec3::splat(shift);
            let free = point_visible_view_factor(p, Vec3::X, &rec, &[]);
            assert!(free > 0.05, "{free}");
            let over = place(&over_foot, e);
            let f = point_visible_view_factor(p, Vec3::X, &rec, &[&over]);
            assert!(f <= 1e-12 * free, "scale {scale} shift {shift} e {e}: F {f} of {free} left");
            let hidden = point_shadowed_view_factor(p, Vec3::X, &rec, &[&over]);
            assert!((hidden - free).abs() <= 1e-12 * free, "scale {scale} shift {shift} e {e}: {hidden} of {free}");
            let beside = place(&beside_foot, e);
            let f = point_visible_view_factor(p, Vec3::X, &rec, &[&beside]);
            assert!((f - free).abs() <= 1e-12 * free, "scale {scale} shift {shift} e {e}: F {f} for {free}");
        }
    }
}

/// A convex quad blocker that crosses p's height casts one shadow (the cone over its four
/// edges, beyond its plane) instead of one per fan triangle: the same visible F as the quad cut
/// into its two triangles (an identity: the cut changes no ray), for p at heights from well
/// above to just off the quad's plane, at several scales. The triangles take the fan path.
#[test]
fn a_quad_crossing_p_height_casts_the_shadow_of_its_two_triangles() {
    let receiver = [[0.0, -1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 2.0], [0.0, -1.0, 2.0]];
    // a fin standing out of the receiver's side past p's height (x = 1.5), a little askew
    let wall = [[0.5, 0.1, -0.5], [2.0, 0.15, -0.5], [2.0, 0.15, 2.5], [0.5, 0.1, 2.5]];
    let mut rng = Rng::new(11);
    for (scale, shift) in [(1.0, 0.0), (1e-6, 7e-6), (1e3, -50.0)] {
        let place = |v: &[[f64; 3]]| poly(&v.iter().map(|q| q.map(|c| c * scale + shift)).collect::<Vec<_>>());
        let rec = place(&receiver);
        let quad = place(&wall);
        let halves = [place(&[wall[0], wall[1], wall[2]]), place(&[wall[0], wall[2], wall[3]])];
        for _ in 0..200 {
            let p = Vec3::new(1.5, -0.8 + 1.6 * rng.f(), 0.2 + 1.6 * rng.f()) * scale + Vec3::splat(shift);
            let n = Vec3::new(-1.0, 0.3 * rng.f() - 0.15, 0.3 * rng.f() - 0.15).normalize();
            let f_quad = point_visible_view_factor(p, n, &rec, &[&quad]);
            let f_tris = point_visible_view_factor(p, n, &rec, &[&halves[0], &halves[1]]);
            let free = point_visible_view_factor(p, n, &rec, &[]);
            assert!(f_quad < free, "scale {scale}: the wall hides nothing ({f_quad} of {free})");
            assert!((f_quad - f_tris).abs() <= 1e-12 * free, "scale {scale}: {f_quad} for {f_tris}");
        }
    }
}

/// A blocker vertex doubled at 2.3e-13 (an edge whose direction is rounding, as cutting a
/// blocker at a plane through its vertex leaves) shadows what the plain vertex does. From
/// points of the face the blocker stands on, 1.9e-3 of the point F apart, and the pair's F
/// 4e-5 off (seed 48 of tests/test_properties.py).
#[test]
fn an_edge_within_rounding_casts_no_plane_of_its_own() {
    let v = |x: f64, y: f64, z: f64| Vec3::new(x, y, z);
    let x0 = 0.7000000000000001;
    let rec = Polygon::new(vec![
        v(x0, 0.76875, 0.7841473395305626),
        v(x0, x0, 0.7757812500000001),
        v(0.6875000000000001, x0, 0.7250000000000001),
    ])
    .unwrap();
    let tri = [v(x0, x0, x0), v(x0, 0.74375, 0.7808593750000001), v(0.6875000000000001, x0, 0.7250000000000001)];
    let plain = Polygon::new(tri.to_vec()).unwrap();
    let doubled = Polygon::new(vec![
        tri[0],
        tri[1],
        v(0.687500000000023, 0.7000000000000802, 0.7250000000001025),
        v(0.6875000000000002, x0, 0.725),
    ])
    .unwrap();
    assert_eq!(doubled.vertices().len(), 4);
    let face = Polygon::new(vec![v(x0, x0, x0), v(x0, x0, 0.8), v(x0, 0.8, x0)]).unwrap();
    let n = face.normal();
    let mut worst = 0.0_f64;
    let mut points = vec![v(x0, 0.7348934121603072, 0.7646771847347678), v(x0, 0.728937632534016, 0.753851950345316)];
    let f = face.vertices();
    for k in 0..400 {
        let (u, w) = (((k % 20) as f64 + 0.5) / 20.0, ((k / 20) as f64 + 0.5) / 20.0);
        if u + w < 1.0 {
            points.push(f[0] + u * (f[1] - f[0]) + w * (f[2] - f[0]));
        }
    }
    for p in points {
        let (a, free) = point_shadowed_and_free(p, n, &rec, &[&plain], true);
        let (b, _) = point_shadowed_and_free(p, n, &rec, &[&doubled], true);
        worst = worst.max((a - b).abs() / free.unwrap());
    }
    assert!(worst <= 1e-9, "{worst:e} of the point's free F apart");
}
