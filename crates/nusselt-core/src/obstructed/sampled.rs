//! Point-pair sampling with visibility: Gauss rules on both areas (`quadrature`) and
//! area-to-area quasi-Monte Carlo (`montecarlo`), both composite over the pieces the
//! blockers' planes cut the polygons into.

use super::Estimate;
use super::VisOptions;
use crate::geometry::{clip_to_halfspace, Polygon, Vec3};
use crate::quadrature::AreaRule;
use crate::sampling::{hash_seed, sobol4, PolygonSampler};
use std::f64::consts::PI;

/// The kernel cos_i cos_j / (pi r^2) between x (normal nx) and y (normal ny), 0 behind.
#[inline]
pub(super) fn kernel(x: Vec3, nx: Vec3, y: Vec3, ny: Vec3) -> f64 {
    let r = y - x;
    let r2 = r.length_squared();
    let ci = r.dot(nx);
    let cj = -r.dot(ny);
    if ci <= 0.0 || cj <= 0.0 || r2 == 0.0 {
        0.0
    } else {
        ci * cj / (PI * r2 * r2)
    }
}

/// Double Gauss rule: sum w_k w_l K(x_k, y_l) [pred(x_k, y_l)] (pred None = always 1),
/// composite over the pieces of both polygons cut along the blockers' planes (see
/// [`cut_at_blocker_planes`]), a piece of a fraction f of its polygon's area getting order
/// ceil(order sqrt f): about order^2 points per polygon however it is cut.
pub(super) fn quadrature(
    a: &Polygon,
    b: &Polygon,
    pred: Option<&dyn Fn(Vec3, Vec3) -> bool>,
    blockers: &[&Polygon],
    o: &VisOptions,
) -> f64 {
    let rules = |p: &Polygon| -> Vec<AreaRule> {
        cut_at_blocker_planes(p, blockers)
            .iter()
            .map(|q| AreaRule::new(q, per_direction(o.order, q.area() / p.area()).clamp(2.min(o.order), o.order)))
            .collect()
    };
    let (ra, rb) = (rules(a), rules(b));
    let mut g = 0.0;
    for ra in &ra {
        for rb in &rb {
            for (x, wx) in ra.points.iter().zip(&ra.weights) {
                for (y, wy) in rb.points.iter().zip(&rb.weights) {
                    let k = kernel(*x, a.normal(), *y, b.normal());
                    if k > 0.0 && pred.is_none_or(|p| p(*x, *y)) {
                        g += wx * wy * k;
                    }
                }
            }
        }
    }
    g
}

/// Most pieces [`cut_at_blocker_planes`] cuts a polygon into.
pub(super) const MAX_QUADRATURE_PIECES: usize = 8;

/// `p` cut along the planes of the blockers that pass through it, into at most
/// [`MAX_QUADRATURE_PIECES`] convex pieces (p itself when none does). A blocker that touches
/// or pierces a polygon (a partition between two plates, a fin standing on a floor) hides
/// from each side of its plane much of the other side: a step along the plane, which a Gauss
/// rule over the whole polygon resolves only to O(1/order) (5.2e-3 at order 24 for a
/// partition spanning two parallel unit plates at x = 0.13; 2.4e-9 with the cut).
pub(super) fn cut_at_blocker_planes(p: &Polygon, blockers: &[&Polygon]) -> Vec<Polygon> {
    let tol = 1e-9 * p.radius();
    let mut pieces = vec![p.vertices().to_vec()];
    let (mut lo, mut hi) = (Vec::new(), Vec::new());
    for b in blockers {
        if pieces.len() >= MAX_QUADRATURE_PIECES {
            break;
        }
        let (q, n) = (b.vertices()[0], b.normal());
        let mut next = Vec::with_capacity(pieces.len() + 1);
        for piece in pieces {
            let side = |x: &Vec3| n.dot(*x - q);
            if !(piece.iter().any(|x| side(x) > tol) && piece.iter().any(|x| side(x) < -tol)) {
                next.push(piece);
                continue;
            }
            clip_to_halfspace(&piece, q, n, 0.0, &mut hi);
            clip_to_halfspace(&piece, q, -n, 0.0, &mut lo);
            next.extend([&hi, &lo].into_iter().filter(|v| v.len() >= 3).cloned());
        }
        pieces = next;
    }
    if pieces.len() == 1 {
        return vec![p.clone()];
    }
    // a sliver too thin to be a valid polygon carries no weight worth a rule
    pieces.into_iter().filter_map(|v| Polygon::new(v).ok()).collect()
}

/// A count per direction (Gauss order, divisions) for a piece holding `fraction` of its
/// polygon's area: about as many points per unit area as `n` gives the whole.
pub(super) fn per_direction(n: usize, fraction: f64) -> usize {
    (n as f64 * fraction.sqrt()).ceil() as usize
}

/// Samples of a stratum holding `fraction` of the whole's `n` (at least 8).
pub(super) fn stratum_samples(n: usize, fraction: f64) -> usize {
    ((n as f64 * fraction).round() as usize).max(8)
}

/// The scrambling seed of stratum `s` (of `strata`) for `key`: the key's own seed when there
/// is one stratum, so unstratified results stay as they were.
pub(super) fn stratum_seed(seed: u64, key: [u64; 3], s: usize, strata: usize) -> u64 {
    let k = [key[0], key[1], key[2], s as u64];
    hash_seed(seed, &k[..if strata == 1 { 3 } else { 4 }])
}

/// Area-to-area RQMC: 8 independent Owen scramblings of a 4-D Sobol sequence; the spread of
/// the 8 estimates gives the standard error.
pub(super) fn montecarlo(
    a: &Polygon,
    b: &Polygon,
    pred: Option<&dyn Fn(Vec3, Vec3) -> bool>,
    blockers: &[&Polygon],
    o: &VisOptions,
    i: usize,
    j: usize,
) -> Estimate {
    // strata: the pairs of pieces of the two polygons cut along the blockers' planes (see
    // [`cut_at_blocker_planes`]), each with its share of the samples: behind a partition the
    // hidden part is then a whole stratum, sampled without the visibility step
    let (pa, pb) = (cut_at_blocker_planes(a, blockers), cut_at_blocker_planes(b, blockers));
    let reps = 8usize;
    let per = (o.samples / reps).max(1);
    let strata: Vec<(PolygonSampler, PolygonSampler, f64, usize)> = pa
        .iter()
        .flat_map(|x| pb.iter().map(move |y| (x, y)))
        .map(|(x, y)| {
            let share = x.area() * y.area() / (a.area() * b.area());
            (PolygonSampler::new(x), PolygonSampler::new(y), x.area() * y.area(), stratum_samples(per, share))
        })
        .collect();
    let mut est = Vec::with_capacity(reps);
    for r in 0..reps {
        let mut total = 0.0;
        for (s, (sa, sb, area, n)) in strata.iter().enumerate() {
            // every pair gets its own scrambling: results do not depend on the order of pairs
            let seed = stratum_seed(o.seed, [i as u64, j as u64, r as u64], s, strata.len());
            let mut acc = 0.0;
            for k in 0..*n {
                let u = sobol4(k as u32, seed);
                let x = sa.sample([u[0], u[1]]);
                let y = sb.sample([u[2], u[3]]);
                let kv = kernel(x, a.normal(), y, b.normal());
                if kv > 0.0 && pred.is_none_or(|p| p(x, y)) {
                    acc += kv;
                }
            }
            total += area * acc / *n as f64;
        }
        est.push(total);
    }
    mean_and_error(&est)
}

pub(super) fn mean_and_error(est: &[f64]) -> Estimate {
    let n = est.len() as f64;
    let mean = est.iter().sum::<f64>() / n;
    let var = est.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / (n - 1.0);
    Estimate { value: mean, std_err: (var / n).sqrt() }
}
