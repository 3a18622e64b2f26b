//! Adaptive refinement: the midpoint split of a triangle into four and the local (depth
//! first) refinement loop that `adaptive_area`, `adaptive_gauss` and `adaptive_point`
//! share. What differs between them (the rule on a piece, when a piece is done, what it
//! adds, the budget) is the caller's `visit`; the loop owns the order in which pieces are
//! taken, so every caller sums its pieces in the same (last in, first out) order.
//!
//! `obstructed::clipping::adaptive_over_source` refines **globally** instead (a heap of
//! leaves by error estimate, stopped when their sum meets the pair's goal) and uses only
//! [`split_in_four`] from here: see docs/architecture.md, "Adaptive integrators".

use crate::geometry::Vec3;

/// The four children of triangle `t` cut at its edge midpoints: the three corner triangles
/// (in the order of their corners) and the middle one, all with t's orientation. Each has a
/// quarter of t's area.
#[inline]
pub fn split_in_four(t: &[Vec3; 3]) -> [[Vec3; 3]; 4] {
    let m01 = 0.5 * (t[0] + t[1]);
    let m12 = 0.5 * (t[1] + t[2]);
    let m20 = 0.5 * (t[2] + t[0]);
    [[t[0], m01, m20], [m01, t[1], m12], [m20, m12, t[2]], [m01, m12, m20]]
}

/// Deepest bisection of [`graded_panels`].
pub const MAX_PANEL_DEPTH: u32 = 60;

/// Panels of [0, len] graded toward the complex singularities `sing` of a 1-D integrand
/// (each: its real part along the interval, its distance from the interval's line), as the
/// edge-pair kernels of `analytic` and `contour` integrate: a panel [a, b] is bisected
/// while `split(a, b, d2)` holds, d2 its squared distance to the nearest singularity
/// (infinite when there is none), at most [`MAX_PANEL_DEPTH`] times; returns the sum of
/// `panel(a, b, d2)` over the panels kept, depth first, the left half first or (not
/// `left_first`) the right half first, each caller's sum in the order it was calibrated in.
/// No allocation: a stack of MAX_PANEL_DEPTH + 4 panels on the call's frame.
pub fn graded_panels(
    len: f64,
    sing: &[(f64, f64)],
    left_first: bool,
    split: impl Fn(f64, f64, f64) -> bool,
    mut panel: impl FnMut(f64, f64, f64) -> f64,
) -> f64 {
    let d2 = |a: f64, b: f64| {
        sing.iter()
            .map(|&(t, e)| {
                let dx = (a - t).max(t - b).max(0.0);
                dx * dx + e * e
            })
            .fold(f64::INFINITY, f64::min)
    };
    let mut stack = [(0.0f64, 0.0f64, 0u32); MAX_PANEL_DEPTH as usize + 4];
    stack[0] = (0.0, len, 0);
    let mut top = 1;
    let mut total = 0.0;
    while top > 0 {
        top -= 1;
        let (a, b, depth) = stack[top];
        let d = d2(a, b);
        if depth < MAX_PANEL_DEPTH && split(a, b, d) {
            let m = 0.5 * (a + b);
            let (first, second) = ((a, m, depth + 1), (m, b, depth + 1));
            // the half taken first is pushed last
            (stack[top], stack[top + 1]) = if left_first { (second, first) } else { (first, second) };
            top += 2;
        } else {
            total += panel(a, b, d);
        }
    }
    total
}

/// What [`refine_locally`]'s `visit` decides for a piece.
pub enum Step<P, const N: usize> {
    /// The piece is done (`visit` has added what it contributes).
    Done,
    /// Refine these pieces instead (taken last first).
    Split([P; N]),
    /// Give up the whole integral (budget spent, integrand not finite).
    GiveUp,
}

/// Local adaptive refinement: pieces are taken from a stack, the last pushed first, and
/// `visit` either finishes a piece or replaces it by its children. Returns false when a
/// visit gave up. A piece carries whatever `visit` needs (its rule value, depth, area):
/// the loop holds no numbers of its own, so each caller's sums are as it writes them.
pub fn refine_locally<P, const N: usize>(mut stack: Vec<P>, mut visit: impl FnMut(P) -> Step<P, N>) -> bool {
    while let Some(piece) = stack.pop() {
        match visit(piece) {
            Step::Done => {}
            Step::Split(kids) => stack.extend(kids),
            Step::GiveUp => return false,
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(t: &[Vec3; 3]) -> Vec3 {
        0.5 * (t[1] - t[0]).cross(t[2] - t[0])
    }

    #[test]
    fn the_four_children_tile_the_triangle_with_its_orientation() {
        let t = [Vec3::new(0.1, -0.3, 0.2), Vec3::new(1.7, 0.2, -0.4), Vec3::new(0.4, 1.1, 0.9)];
        let kids = split_in_four(&t);
        let a = area(&t);
        for k in &kids {
            // a quarter of the vector area each: same orientation, a quarter of the size
            assert!((area(k) - 0.25 * a).length() <= 1e-15 * a.length(), "{k:?}");
        }
        // the corner children keep t's corners; the middle one is made of the midpoints
        for (c, k) in kids.iter().take(3).enumerate() {
            assert!(k.contains(&t[c]));
        }
        let centroid = |t: &[Vec3; 3]| (t[0] + t[1] + t[2]) / 3.0;
        assert!((centroid(&kids[3]) - centroid(&t)).length() <= 1e-15);
    }

    #[test]
    fn local_refinement_integrates_to_its_tolerance_and_gives_up_on_demand() {
        // int_0^1 sqrt(x) dx = 2/3 by the midpoint rule on intervals, split in two until a
        // piece and its halves agree to 1e-10: the loop visits every piece once and the
        // accepted sum meets the target (an independent closed form).
        let mid = |a: f64, b: f64| (b - a) * (0.5 * (a + b)).sqrt();
        let (mut sum, mut visits) = (0.0, 0);
        let ok = refine_locally(vec![(0.0, 1.0)], |(a, b): (f64, f64)| {
            visits += 1;
            let m = 0.5 * (a + b);
            let parts = mid(a, m) + mid(m, b);
            if (parts - mid(a, b)).abs() <= 1e-10 {
                sum += parts;
                Step::Done
            } else {
                Step::Split([(a, m), (m, b)])
            }
        });
        assert!(ok);
        assert!((sum - 2.0 / 3.0).abs() < 1e-7, "{sum}");
        assert!(visits > 10);
        // a visit that gives up ends the loop at once
        let mut seen = 0;
        let ok = refine_locally(vec![1, 2, 3], |k: i32| {
            seen += 1;
            if k == 2 {
                Step::GiveUp
            } else {
                Step::<i32, 1>::Done
            }
        });
        assert!(!ok);
        assert_eq!(seen, 2); // 3, then 2
    }
}
