use super::*;
use crate::geometry::tangent_frame;
use crate::sampling::mix64;

pub(crate) struct Rng(u64);
impl Rng {
    pub(crate) fn new(seed: u64) -> Self {
        Rng(seed)
    }
    pub(crate) fn f(&mut self) -> f64 {
        self.0 = mix64(self.0);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    pub(crate) fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.f()
    }
    pub(crate) fn unit(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(self.range(-1., 1.), self.range(-1., 1.), self.range(-1., 1.));
            let l = v.length();
            if l > 0.1 && l <= 1.0 {
                return v / l;
            }
        }
    }
}

fn poly(v: &[[f64; 3]]) -> Polygon {
    Polygon::new(v.iter().map(|p| Vec3::from_array(*p)).collect()).unwrap()
}

/// Axis-aligned rectangle in the plane `axis = c`, [u0,u1] x [v0,v1] in the other two axes,
/// facing +axis (`up`) or -axis.
pub(crate) fn rect(axis: usize, c: f64, u: (f64, f64), v: (f64, f64), up: bool) -> Polygon {
    let (ia, ib) = ((axis + 1) % 3, (axis + 2) % 3);
    let mk = |a: f64, b: f64| {
        let mut p = Vec3::ZERO;
        p[axis] = c;
        p[ia] = a;
        p[ib] = b;
        p
    };
    // (ia, ib, axis) is right-handed, so this order is CCW about +axis.
    let mut vs = vec![mk(u.0, v.0), mk(u.1, v.0), mk(u.1, v.1), mk(u.0, v.1)];
    if !up {
        vs.reverse();
    }
    Polygon::new(vs).unwrap()
}

/// Inward-facing box [lo, hi] with each face split into k x k patches (shared vertices are
/// bit-identical: they come from the same expression).
pub(crate) fn room(lo: Vec3, hi: Vec3, k: usize, inward: bool) -> Vec<Polygon> {
    let mut out = Vec::new();
    for axis in 0..3 {
        let (ia, ib) = ((axis + 1) % 3, (axis + 2) % 3);
        let grid = |lo_: f64, hi_: f64, i: usize| lo_ + (hi_ - lo_) * (i as f64 / k as f64);
        for (c, up) in [(lo[axis], inward), (hi[axis], !inward)] {
            for i in 0..k {
                for j in 0..k {
                    out.push(rect(
                        axis,
                        c,
                        (grid(lo[ia], hi[ia], i), grid(lo[ia], hi[ia], i + 1)),
                        (grid(lo[ib], hi[ib], j), grid(lo[ib], hi[ib], j + 1)),
                        up,
                    ));
                }
            }
        }
    }
    out
}

/// Independent reference: plane intersection plus winding-number point-in-polygon, over all
/// polygons (no tree, no triangles).
fn brute_first_hit(polys: &[Polygon], o: Vec3, d: Vec3, tmin: f64, tmax: f64) -> Option<(u32, f64)> {
    let mut best: Option<(u32, f64)> = None;
    for (i, p) in polys.iter().enumerate() {
        if let Some(t) = ray_polygon(p, o, d) {
            if t > tmin && t < tmax && best.is_none_or(|b| t < b.1) {
                best = Some((i as u32, t));
            }
        }
    }
    best
}

pub(crate) fn ray_polygon(p: &Polygon, o: Vec3, d: Vec3) -> Option<f64> {
    let n = p.normal();
    let den = n.dot(d);
    if den == 0.0 {
        return None;
    }
    let t = n.dot(p.centroid() - o) / den;
    let x = o + t * d;
    let (tu, tv) = tangent_frame(n);
    let q: Vec<[f64; 2]> = p.vertices().iter().map(|v| [(v - x).dot(tu), (v - x).dot(tv)]).collect();
    // Winding number of the origin.
    let mut wind = 0i32;
    for i in 0..q.len() {
        let (a, b) = (q[i], q[(i + 1) % q.len()]);
        let cross = a[0] * b[1] - a[1] * b[0];
        if a[1] <= 0.0 && b[1] > 0.0 && cross > 0.0 {
            wind += 1;
        } else if a[1] > 0.0 && b[1] <= 0.0 && cross < 0.0 {
            wind -= 1;
        }
    }
    (wind != 0).then_some(t)
}

#[test]
fn bvh_is_sync_and_send() {
    fn check<T: Sync + Send>() {}
    check::<Bvh>();
}

#[test]
fn first_hit_nearest_front_back_and_ignore() {
    let polys = vec![
        rect(2, 1.0, (0., 1.), (0., 1.), false), // z = 1 facing down
        rect(2, 2.0, (0., 1.), (0., 1.), true),  // z = 2 facing up
    ];
    let bvh = Bvh::new(&polys).unwrap();
    let o = Vec3::new(0.3, 0.4, 0.0);
    let h = bvh.first_hit(o, Vec3::Z, 0.0, f64::INFINITY, &[]).unwrap();
    assert_eq!((h.id, h.front), (0, true));
    assert!((h.t - 1.0).abs() < 1e-15);
    let h = bvh.first_hit(o, Vec3::Z, 0.0, f64::INFINITY, &[0]).unwrap();
    assert_eq!((h.id, h.front), (1, false));
    assert!((h.t - 2.0).abs() < 1e-15);
    // tmax before the first plane, tmin past it
    assert!(bvh.first_hit(o, Vec3::Z, 0.0, 0.99, &[]).is_none());
    assert_eq!(bvh.first_hit(o, Vec3::Z, 1.01, 10.0, &[]).unwrap().id, 1);
    // ray direction scaled: t in units of dir
    assert!((bvh.first_hit(o, 2.0 * Vec3::Z, 0.0, 9.0, &[]).unwrap().t - 0.5).abs() < 1e-15);
    // misses beside and in the plane
    assert!(bvh.first_hit(Vec3::new(1.5, 0.5, 0.), Vec3::Z, 0.0, 9.0, &[]).is_none());
    assert!(bvh.first_hit(Vec3::new(-1., 0.5, 1.), Vec3::X, 0.0, 9.0, &[]).is_none());
    // bad input: nothing, no panic
    assert!(bvh.first_hit(Vec3::NAN, Vec3::Z, 0.0, 9.0, &[]).is_none());
    assert!(bvh.first_hit(o, Vec3::ZERO, 0.0, 9.0, &[]).is_none());
}

#[test]
fn concave_polygon_notch_is_empty() {
    // L-shape: the square [1,2]x[1,2] is missing.
    let l = poly(&[[0., 0., 0.], [2., 0., 0.], [2., 1., 0.], [1., 1., 0.], [1., 2., 0.], [0., 2., 0.]]);
    let bvh = Bvh::new(&[l]).unwrap();
    let down = -Vec3::Z;
    assert!(bvh.first_hit(Vec3::new(1.5, 1.5, 1.), down, 0.0, 9.0, &[]).is_none());
    for p in [[0.5, 0.5], [1.5, 0.5], [0.5, 1.5], [0.99, 1.99]] {
        assert!(bvh.first_hit(Vec3::new(p[0], p[1], 1.), down, 0.0, 9.0, &[]).is_some(), "{p:?}");
    }
}

#[test]
fn mask_removes_polygons_and_is_validated() {
    let polys = vec![rect(2, 1.0, (0., 1.), (0., 1.), false), rect(2, 2.0, (0., 1.), (0., 1.), false)];
    let bvh = Bvh::with_mask(&polys, Some(&[false, true])).unwrap();
    let h = bvh.first_hit(Vec3::new(0.5, 0.5, 0.), Vec3::Z, 0.0, 9.0, &[]).unwrap();
    assert_eq!(h.id, 1);
    assert!(matches!(Bvh::with_mask(&polys, Some(&[true])), Err(Error::InvalidArgument(_))));
    let empty = Bvh::new(&[]).unwrap();
    assert!(empty.first_hit(Vec3::ZERO, Vec3::Z, 0.0, 1.0, &[]).is_none());
    assert!(!empty.occluded(Vec3::ZERO, Vec3::Z, &[]));
}

#[test]
fn matches_brute_force_on_random_scene() {
    let mut rng = Rng::new(7);
    // 300 random convex quads and triangles (some tilted) in the unit cube.
    let mut polys = Vec::new();
    while polys.len() < 300 {
        let c = Vec3::new(rng.f(), rng.f(), rng.f());
        let n = rng.unit();
        let (t, b) = tangent_frame(n);
        let m = 3 + (rng.f() * 3.0) as usize;
        let s = rng.range(0.02, 0.15);
        let ph = rng.f();
        let vs: Vec<Vec3> = (0..m)
            .map(|k| {
                let a = std::f64::consts::TAU * (k as f64 + ph) / m as f64;
                c + s * (a.cos() * t + a.sin() * b)
            })
            .collect();
        polys.push(Polygon::new(vs).unwrap());
    }
    let bvh = Bvh::new(&polys).unwrap();
    let mut hits = 0;
    for _ in 0..4000 {
        let o = Vec3::new(rng.range(-0.2, 1.2), rng.range(-0.2, 1.2), rng.range(-0.2, 1.2));
        let d = rng.unit();
        let got = bvh.first_hit(o, d, 0.0, 3.0, &[]);
        let want = brute_first_hit(&polys, o, d, 0.0, 3.0);
        match (got, want) {
            (None, None) => {}
            (Some(g), Some(w)) => {
                hits += 1;
                assert!((g.t - w.1).abs() < 1e-12, "t {} vs {}", g.t, w.1);
                if g.id != w.0 {
                    // only acceptable when two polygons are hit at the same distance
                    assert!((g.t - w.1).abs() < 1e-12);
                }
                assert_eq!(g.front, d.dot(polys[g.id as usize].normal()) < 0.0);
                // occluded agrees: the segment to just past the hit is blocked, to just
                // before it is not (when nothing else is in between)
                assert!(bvh.occluded(o, o + d * (g.t * 1.01), &[]));
                assert!(!bvh.occluded(o, o + d * (g.t * 0.99), &[]));
            }
            (g, w) => panic!("bvh {g:?} vs brute force {w:?}"),
        }
    }
    assert!(hits > 500, "too few hits to mean anything: {hits}");
}

#[test]
fn axis_parallel_rays_from_box_planes_hit_the_wall_ahead() {
    // Directions with zero components (+-0.0) from origins on the grid planes, where node
    // boxes have their faces: the slab test must neither miss a box nor produce NaN.
    let k = 5;
    let polys = room(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0), k, true);
    let bvh = Bvh::new(&polys).unwrap();
    let size = [1.0, 2.0, 3.0];
    let mut n = 0;
    for a in 1..k {
        for b in 1..k {
            for axis in 0..3 {
                let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
                let mut o = [0.0; 3];
                o[axis] = 0.5 * size[axis];
                o[u] = size[u] * a as f64 / k as f64;
                o[w] = size[w] * b as f64 / k as f64;
                for sign in [1.0, -1.0] {
                    for zero in [0.0, -0.0] {
                        let mut d = [zero; 3];
                        d[axis] = sign;
                        let (o, d) = (Vec3::from_array(o), Vec3::from_array(d));
                        let h = bvh.first_hit(o, d, 0.0, f64::INFINITY, &[]).expect("axis ray escaped the room");
                        assert!((h.t - 0.5 * size[axis]).abs() < 1e-12 && h.front, "{o} {d}: {h:?}");
                        assert!(bvh.occluded(o, o + d * size[axis], &[]));
                        n += 1;
                    }
                }
            }
        }
    }
    assert_eq!(n, 3 * 16 * 4);
}

#[test]
fn closed_room_is_watertight_at_edges_and_corners() {
    // Rays from inside a closed, subdivided room aimed exactly at grid vertices and along
    // grid lines (the edges shared by neighbouring patches and by walls) never escape.
    let k = 5;
    let polys = room(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0), k, true);
    let bvh = Bvh::new(&polys).unwrap();
    let mut rng = Rng::new(11);
    let mut n = 0;
    for _ in 0..200 {
        let o = Vec3::new(rng.range(0.1, 0.9), rng.range(0.1, 1.9), rng.range(0.1, 2.9));
        for p in polys.iter().step_by(3) {
            for (i, v) in p.vertices().iter().enumerate() {
                let w = p.vertices()[(i + 1) % 4];
                for target in [*v, 0.5 * (v + w)] {
                    let h = bvh.first_hit(o, target - o, 0.0, f64::INFINITY, &[]);
                    let h = h.unwrap_or_else(|| panic!("ray from {o} to {target} escaped"));
                    assert!((h.t - 1.0).abs() < 1e-12, "{}", h.t);
                    assert!(h.front);
                    n += 1;
                }
            }
        }
    }
    assert!(n > 10000);
}

#[test]
fn occluded_ignores_end_polygons_and_their_neighbours() {
    let k = 4;
    let mut polys = room(Vec3::ZERO, Vec3::ONE, k, true);
    let empty = polys.len();
    let bvh = Bvh::new(&polys).unwrap();
    // End points exactly on shared patch corners and edges of the floor and ceiling, and on
    // the room's edges: nothing blocks, with or without `ignore`.
    for i in 0..=k {
        for j in 0..=k {
            let a = Vec3::new(i as f64 / k as f64, j as f64 / k as f64, 0.0);
            let b = Vec3::new(j as f64 / k as f64, 1.0 - i as f64 / k as f64, 1.0);
            assert!(!bvh.occluded(a, b, &[]), "{a} -> {b}");
            assert!(!bvh.occluded(b, a, &[]), "{b} -> {a}");
        }
    }
    // A point on the floor to a point on a wall, both on the room's edges.
    assert!(!bvh.occluded(Vec3::new(0.5, 0.0, 0.0), Vec3::new(0.0, 0.5, 0.0), &[]));
    // Segment lying in the floor plane: grazes, is not blocked.
    assert!(!bvh.occluded(Vec3::new(0.1, 0.1, 0.0), Vec3::new(0.9, 0.8, 0.0), &[]));
    // Add an inner box and check blocking, the ignore list and the open ends.
    polys.extend(room(Vec3::splat(0.4), Vec3::splat(0.6), 2, false));
    let bvh = Bvh::new(&polys).unwrap();
    let (a, b) = (Vec3::new(0.5, 0.5, 0.0), Vec3::new(0.5, 0.5, 1.0));
    assert!(bvh.occluded(a, b, &[]));
    assert!(bvh.occluded(b, a, &[]));
    let blockers: Vec<u32> = (empty as u32..polys.len() as u32).collect();
    assert!(!bvh.occluded(a, b, &blockers));
    // ends on the inner box's faces: the segment from the floor to the box's bottom face is
    // free, one that continues through the box is not
    assert!(!bvh.occluded(a, Vec3::new(0.5, 0.5, 0.4), &[]));
    assert!(bvh.occluded(a, Vec3::new(0.5, 0.5, 0.6), &[]));
    // degenerate segment
    assert!(!bvh.occluded(a, a, &[]));
}

#[test]
fn occluded_is_scale_invariant() {
    let mut rng = Rng::new(5);
    let base: Vec<Polygon> = {
        let mut p = room(Vec3::ZERO, Vec3::ONE, 3, true);
        p.extend(room(Vec3::splat(0.3), Vec3::new(0.6, 0.7, 0.5), 1, false));
        p
    };
    let pairs: Vec<(Vec3, Vec3)> = (0..2000)
        .map(|_| {
            // end points on the floor and the ceiling
            (Vec3::new(rng.f(), rng.f(), 0.0), Vec3::new(rng.f(), rng.f(), 1.0))
        })
        .collect();
    let answers = |s: f64| -> Vec<bool> {
        let polys: Vec<Polygon> =
            base.iter().map(|p| Polygon::new(p.vertices().iter().map(|v| v * s).collect()).unwrap()).collect();
        let bvh = Bvh::new(&polys).unwrap();
        pairs.iter().map(|(a, b)| bvh.occluded(a * s, b * s, &[])).collect()
    };
    let one = answers(1.0);
    let blocked = one.iter().filter(|b| **b).count();
    assert!(blocked > 100 && blocked < 1900, "{blocked}");
    assert_eq!(one, answers(1e-3));
    assert_eq!(one, answers(1e3));
}

/// Independent check of whether the segment x -> y crosses polygon p strictly inside.
fn segment_crosses(p: &Polygon, x: Vec3, y: Vec3) -> bool {
    ray_polygon(p, x, y - x).is_some_and(|t| t > 1e-9 && t < 1.0 - 1e-9)
}

#[test]
fn shaft_between_plates_hand_built() {
    // Plates z = 0 (up) and z = 1 (down), unit squares.
    let a = rect(2, 0.0, (0., 1.), (0., 1.), true);
    let b = rect(2, 1.0, (0., 1.), (0., 1.), false);
    let polys = vec![
        a.clone(),
        b.clone(),
        rect(2, 0.5, (0.25, 0.75), (0.25, 0.75), true), // 2: blocker in the middle
        rect(2, 0.5, (2.0, 3.0), (0.0, 1.0), true),     // 3: far to the side
        rect(2, 0.0, (1.0, 2.0), (0.0, 1.0), true),     // 4: a's coplanar neighbour
        rect(0, 1.0, (0.0, 1.0), (0.0, 1.0), false),    // 5: wall x = 1 touching both edges
        rect(2, 1.5, (0.0, 1.0), (0.0, 1.0), true),     // 6: behind b
        rect(0, 0.5, (0.0, 1.0), (0.2, 0.3), true),     // 7: vertical strip inside the shaft
        // 8: tilted quad beside the shaft whose box overlaps it: only a plane test rejects it
        poly(&[[1.05, -0.5, 0.0], [1.05, 1.5, 0.0], [1.8, 1.5, 1.0], [1.8, -0.5, 1.0]]),
        // 9: small triangle just outside the side face x = 0 (touching it with a vertex)
        poly(&[[0.0, 0.5, 0.5], [-0.2, 0.6, 0.5], [-0.2, 0.4, 0.6]]),
        // 10: a sliver poking 1e-3 into the shaft: kept
        poly(&[[0.001, 0.5, 0.5], [-0.2, 0.6, 0.5], [-0.2, 0.4, 0.6]]),
    ];
    let bvh = Bvh::new(&polys).unwrap();
    let mut out = vec![99];
    bvh.candidates_between(&a, &b, &[0, 1], &mut out);
    assert_eq!(out, vec![2, 7, 10]);
    bvh.candidates_between(&b, &a, &[0, 1], &mut out);
    assert_eq!(out, vec![2, 7, 10]);
    bvh.candidates_between(&a, &b, &[0, 1, 2], &mut out);
    assert_eq!(out, vec![7, 10]);
    // Offset plates: the shaft leans over, the middle blocker is now out of it.
    let b2 = rect(2, 1.0, (3.0, 4.0), (0., 1.), false);
    bvh.candidates_between(&a, &b2, &[0], &mut out);
    assert_eq!(out, vec![3, 5, 8]);
    // (4, a's neighbour in a's plane, only touches the hull along their shared edge)
}

#[test]
fn shaft_empty_room_pairs_have_no_candidates() {
    // In an empty convex room no patch can block another: every pair must get none.
    let polys = room(Vec3::ZERO, Vec3::new(1.0, 1.5, 2.0), 3, true);
    let bvh = Bvh::new(&polys).unwrap();
    let mut out = Vec::new();
    for i in 0..polys.len() {
        for j in (i + 1)..polys.len() {
            bvh.candidates_between(&polys[i], &polys[j], &[i as u32, j as u32], &mut out);
            assert!(out.is_empty(), "pair {i} {j}: {out:?}");
        }
    }
}

#[test]
fn shaft_never_drops_a_real_blocker() {
    let mut rng = Rng::new(2024);
    let mut real = 0;
    let mut rejected = 0;
    for case in 0..300 {
        // Random quads a, b roughly facing each other, and 40 small random triangles.
        let quad = |rng: &mut Rng, c: Vec3, n: Vec3| {
            let (t, b) = tangent_frame(n);
            let (sx, sy) = (rng.range(0.2, 1.0), rng.range(0.2, 1.0));
            let sk = rng.range(-0.3, 0.3);
            Polygon::new(vec![
                c + sx * (-t) + sy * (-b),
                c + sx * t + sy * (-b + sk * t),
                c + sx * t + sy * b,
                c + sx * (-t) + sy * (b - sk * t),
            ])
            .unwrap()
        };
        let na = (Vec3::Z + 0.5 * rng.unit()).normalize();
        let nb = (-Vec3::Z + 0.5 * rng.unit()).normalize();
        let a = quad(&mut rng, Vec3::ZERO, na);
        let cb = Vec3::new(rng.range(-0.5, 0.5), rng.range(-0.5, 0.5), rng.range(0.5, 2.0));
        let b = quad(&mut rng, cb, nb);
        let mut polys = vec![a.clone(), b.clone()];
        for _ in 0..40 {
            let c = Vec3::new(rng.range(-1.5, 1.5), rng.range(-1.5, 1.5), rng.range(-0.3, 2.3));
            let s = rng.range(0.02, 0.3);
            let vs = vec![c + s * rng.unit(), c + s * rng.unit(), c + s * rng.unit()];
            if let Ok(p) = Polygon::new(vs) {
                polys.push(p);
            }
        }
        let bvh = Bvh::new(&polys).unwrap();
        let mut cand = Vec::new();
        bvh.candidates_between(&a, &b, &[0, 1], &mut cand);
        let pa = crate::sampling::PolygonSampler::new(&a);
        let pb = crate::sampling::PolygonSampler::new(&b);
        let segs: Vec<(Vec3, Vec3)> =
            (0..400).map(|_| (pa.sample([rng.f(), rng.f()]), pb.sample([rng.f(), rng.f()]))).collect();
        for (k, p) in polys.iter().enumerate().skip(2) {
            let blocks = segs.iter().any(|(x, y)| segment_crosses(p, *x, *y));
            if blocks {
                real += 1;
                assert!(cand.contains(&(k as u32)), "case {case}: blocker {k} dropped");
            } else if !cand.contains(&(k as u32)) {
                rejected += 1;
            }
        }
    }
    assert!(real > 200, "too few real blockers to mean anything: {real}");
    // The shaft must also cull: most non-blockers are rejected.
    assert!(rejected > 5000, "shaft culled only {rejected}");
}

#[test]
fn shaft_from_a_point_sized_source() {
    // obstructed::point uses a tiny triangle around the point as the source polygon.
    let p = Vec3::new(0.5, 0.5, 0.0);
    let eps = 1e-9;
    let (t, s) = tangent_frame(Vec3::Z);
    let src = Polygon::new(vec![p + eps * t, p + eps * s, p - eps * (t + s)]).unwrap();
    let b = rect(2, 1.0, (0., 1.), (0., 1.), false);
    let polys = vec![
        b.clone(),
        rect(2, 0.5, (0.45, 0.55), (0.45, 0.55), true), // on the axis: blocks
        rect(2, 0.5, (0.6, 0.7), (0.6, 0.7), true),     // in the cone ([0.25, 0.75]^2 at z = 0.5)
        rect(2, 0.5, (0.76, 0.9), (0.1, 0.2), true),    // outside the cone
        rect(2, 0.5, (0.74, 0.9), (0.5, 0.6), true),    // pokes 0.01 into the cone
    ];
    let bvh = Bvh::new(&polys).unwrap();
    let mut out = Vec::new();
    bvh.candidates_between(&src, &b, &[0], &mut out);
    assert_eq!(out, vec![1, 2, 4]);
}

/// Throughput on a subdivided room (120 x 120 patches per wall) with an inner box:
/// `cargo test -p nusselt-core --release --lib visibility::bvh::tests::bench_rays -- --ignored --nocapture`
#[test]
#[ignore]
fn bench_rays() {
    use rayon::prelude::*;
    use std::time::Instant;
    let mut polys = room(Vec3::ZERO, Vec3::new(4.0, 5.0, 3.0), 120, true);
    polys.extend(room(Vec3::new(1.5, 2.0, 0.5), Vec3::new(2.5, 3.0, 1.5), 10, false));
    let t = Instant::now();
    let bvh = Bvh::new(&polys).unwrap();
    let build = t.elapsed().as_secs_f64();
    println!(
        "{} polygons, {} triangles, {} nodes, build {:.3} s",
        polys.len(),
        bvh.triangle_count(),
        bvh.nodes.len(),
        build
    );
    // Rays from random floor points, cosine-distributed directions.
    let n = 1_000_000usize;
    let mut rng = Rng::new(1);
    let rays: Vec<(Vec3, Vec3)> = (0..n)
        .map(|_| {
            let o = Vec3::new(rng.range(0.0, 4.0), rng.range(0.0, 5.0), 0.0);
            (o, crate::sampling::cosine_hemisphere([rng.f(), rng.f()]))
        })
        .collect();
    let segs: Vec<(Vec3, Vec3)> = (0..n)
        .map(|_| {
            (
                Vec3::new(rng.range(0.0, 4.0), rng.range(0.0, 5.0), 0.0),
                Vec3::new(rng.range(0.0, 4.0), rng.range(0.0, 5.0), 3.0),
            )
        })
        .collect();
    let t = Instant::now();
    let hits = rays.iter().filter(|(o, d)| bvh.first_hit(*o, *d, 1e-9, f64::INFINITY, &[]).is_some()).count();
    let fh = n as f64 / t.elapsed().as_secs_f64();
    let t = Instant::now();
    let blocked = segs.iter().filter(|(a, b)| bvh.occluded(*a, *b, &[])).count();
    let oc = n as f64 / t.elapsed().as_secs_f64();
    let t = Instant::now();
    let hits2 = rays.par_iter().filter(|(o, d)| bvh.first_hit(*o, *d, 1e-9, f64::INFINITY, &[]).is_some()).count();
    let fh_par = n as f64 / t.elapsed().as_secs_f64();
    println!(
        "first_hit: {:.2} Mrays/s (1 thread), {:.2} Mrays/s ({} threads); hits {hits}",
        fh / 1e6,
        fh_par / 1e6,
        rayon::current_num_threads()
    );
    println!("occluded:  {:.2} Mrays/s (1 thread), blocked {blocked}", oc / 1e6);
    assert_eq!(hits, hits2);
    assert_eq!(hits, n); // closed room: every ray hits something
                         // Shaft culling cost for pairs of floor and ceiling patches.
    let k = 120 * 120;
    let t = Instant::now();
    let mut out = Vec::new();
    let mut total = 0;
    let mut nonempty = 0;
    let pairs = 20_000;
    for p in 0..pairs {
        // floor patch (ids 4k..5k) to ceiling patch (ids 5k..6k)
        let i = 4 * k + (p * 7919) % k;
        let j = 5 * k + (p * 104729) % k;
        bvh.candidates_between(&polys[i], &polys[j], &[i as u32, j as u32], &mut out);
        total += out.len();
        nonempty += !out.is_empty() as usize;
    }
    println!(
        "candidates_between floor-ceiling: {:.1} us/pair, {nonempty} of {pairs} pairs have candidates, mean {:.1} candidates",
        t.elapsed().as_secs_f64() / pairs as f64 * 1e6,
        total as f64 / pairs as f64
    );
}

#[test]
fn box_shafts_keep_every_real_blocker_and_narrow_like_the_pair_shaft() {
    // A source quad, a cluster of receiver quads in a box, random triangles: the box query
    // (and a smaller box's query restricted to it) must keep every polygon some segment of a
    // pair meets, and the pair query restricted to it must give what the pair query gives,
    // up to polygons neither shaft can confirm.
    let mut rng = Rng::new(77);
    let (mut real, mut narrowed) = (0, 0);
    for case in 0..200 {
        let a = Polygon::new(vec![
            Vec3::new(-0.5, -0.5, 0.0),
            Vec3::new(0.5, -0.5, 0.0),
            Vec3::new(0.5, 0.5, 0.0),
            Vec3::new(-0.5, 0.5, 0.0),
        ])
        .unwrap();
        let c0 = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(1.0, 2.0));
        let mut polys = vec![a.clone()];
        for k in 0..4 {
            let c = c0 + Vec3::new(0.3 * (k % 2) as f64, 0.3 * (k / 2) as f64, 0.1 * rng.f());
            let s = 0.12;
            polys.push(
                Polygon::new(vec![
                    c + Vec3::new(-s, s, 0.),
                    c + Vec3::new(s, s, 0.),
                    c + Vec3::new(s, -s, 0.),
                    c + Vec3::new(-s, -s, 0.),
                ])
                .unwrap(),
            );
        }
        for _ in 0..40 {
            let c = Vec3::new(rng.range(-1.5, 1.5), rng.range(-1.5, 1.5), rng.range(-0.3, 2.3));
            let s = rng.range(0.02, 0.3);
            if let Ok(p) = Polygon::new(vec![c + s * rng.unit(), c + s * rng.unit(), c + s * rng.unit()]) {
                polys.push(p);
            }
        }
        let bvh = Bvh::new(&polys).unwrap();
        let bounds = |ks: &[usize]| {
            let (mut lo, mut hi) = (Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY));
            for &k in ks {
                for v in polys[k].vertices() {
                    lo = lo.min(*v);
                    hi = hi.max(*v);
                }
            }
            (lo, hi)
        };
        let (lo, hi) = bounds(&[1, 2, 3, 4]);
        let (mut all, mut half, mut cand, mut among) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        bvh.candidates_toward_box(&a, lo, hi, &[0], None, &mut all);
        assert!(all.windows(2).all(|w| w[0] < w[1]) && !all.contains(&0));
        let (lo2, hi2) = bounds(&[1, 2]);
        bvh.candidates_toward_box(&a, lo2, hi2, &[0], Some(&all), &mut half);
        assert!(half.iter().all(|k| all.contains(k)));
        let pa = crate::sampling::PolygonSampler::new(&a);
        for j in 1..5usize {
            let b = &polys[j];
            bvh.candidates_between(&a, b, &[0, j as u32], &mut cand);
            let parent = if j <= 2 { &half } else { &all };
            bvh.candidates_among(&a, b, &[0, j as u32], parent, &mut among);
            assert!(among.iter().all(|k| cand.contains(k)), "case {case} pair {j}: {among:?} not in {cand:?}");
            narrowed += cand.len() - among.len();
            let pb = crate::sampling::PolygonSampler::new(b);
            let segs: Vec<(Vec3, Vec3)> =
                (0..300).map(|_| (pa.sample([rng.f(), rng.f()]), pb.sample([rng.f(), rng.f()]))).collect();
            for (k, p) in polys.iter().enumerate().skip(1) {
                if k != j && segs.iter().any(|(x, y)| segment_crosses(p, *x, *y)) {
                    real += 1;
                    assert!(among.contains(&(k as u32)), "case {case} pair {j}: blocker {k} dropped");
                }
            }
        }
    }
    assert!(real > 150, "too few real blockers to mean anything: {real}");
    // the pair query restricted to the box's answer is almost always the pair query itself
    assert!(narrowed < real / 4, "{narrowed} candidates lost against {real} real blockers");
}

/// Depth of the four-wide tree below wide node `w` (1 for a node with leaves only).
fn wide_depth(bvh: &Bvh, w: usize) -> usize {
    let node = &bvh.wide[w];
    1 + (0..4)
        .filter(|&k| node.count[k] == 0 && node.lo[0][k] <= node.hi[0][k])
        .map(|k| wide_depth(bvh, node.child[k] as usize))
        .max()
        .unwrap_or(0)
}

#[test]
fn a_tree_deeper_than_the_traversal_stack_matches_brute_force() {
    // Squares of halving size and distance along x (a geometric chain: every split peels
    // off the largest), so the tree is deeper than the fixed traversal stack holds and the
    // traversal spills into its overflow list. Rays along the chain and across it must find
    // the hits brute force finds.
    let polys: Vec<Polygon> = (0..400)
        .map(|k| {
            let s = 0.9f64.powi(k);
            rect(0, s, (-0.3 * s, 0.3 * s), (-0.3 * s, 0.3 * s), k % 2 == 0)
        })
        .collect();
    let bvh = Bvh::new(&polys).unwrap();
    let depth = wide_depth(&bvh, 0);
    assert!(depth > 22, "the chain's tree is only {depth} levels deep");
    let mut rng = Rng::new(11);
    for _ in 0..2000 {
        let o = Vec3::new(rng.range(-0.1, 1.2), rng.range(-0.05, 0.05), rng.range(-0.05, 0.05));
        let d = (Vec3::new(rng.range(-1.0, 1.0), rng.range(-0.05, 0.05), rng.range(-0.05, 0.05))).normalize();
        let got = bvh.first_hit(o, d, 0.0, 3.0, &[]).map(|h| h.t);
        let want = brute_first_hit(&polys, o, d, 0.0, 3.0).map(|w| w.1);
        match (got, want) {
            (None, None) => {}
            (Some(g), Some(w)) => assert!((g - w).abs() < 1e-12, "t {g} vs {w}"),
            (g, w) => panic!("bvh {g:?} vs brute force {w:?}"),
        }
    }
}

/// A sliver 6e-8 wide with an edge 1e-7 long (the part of a face leaning 2^-24 out of the
/// plane x = 0 in front of its partner), and a face in x = 0 that a segment between the pair
/// crosses: a candidate wherever the scene lies. Scaled by 1e-6 and moved by 7e-6, the short
/// edge's planes took a tolerance of 3e-7 of the pair's size from the rounding of its direction
/// and culled it.
#[test]
fn shaft_of_a_sliver_with_a_short_edge_keeps_a_blocker_it_reaches() {
    let lean = -5.960464477539063e-8;
    let sliver = [[0.0, 1.0, 0.0], [lean, 0.0, 0.0], [-5.960464122267716e-8; 3]];
    let partner = [[0.0, 0.0, 0.0], [1.0, 0.0, 1.0], [0.0, 1.0, 0.0]];
    let wall = [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]];
    for (s, shift) in [(1.0, 0.0), (1e-6, 7e-6)] {
        let place =
            |p: &[[f64; 3]; 3]| -> Vec<Vec3> { p.iter().map(|v| Vec3::from_array(v.map(|x| s * x + shift))).collect() };
        let a = Polygon::with_tolerance(place(&sliver), 1e-6).unwrap();
        let b = Polygon::new(place(&partner)).unwrap();
        let w = Polygon::new(place(&wall)).unwrap();
        // (independent of the shaft: the segment between the centroids crosses the wall)
        assert!(segment_crosses(&w, a.centroid(), b.centroid()), "scale {s}");
        let bvh = Bvh::new(&[a.clone(), b.clone(), w]).unwrap();
        let mut out = Vec::new();
        bvh.candidates_between(&a, &b, &[0, 1], &mut out);
        assert_eq!(out, vec![2], "scale {s}");
    }
}
