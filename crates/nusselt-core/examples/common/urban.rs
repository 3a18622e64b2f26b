use nusselt_core::{Polygon, Vec3};

/// The urban grid of bench/scenes.py `urban(k)`: ground [0, 8]^2 meshed 4k x 4k and 16
/// buildings 1 x 1 x 2 at (2i + 0.5, 2j + 0.5), roofs k x k, walls k x 2k: 144 k^2 patches.
pub fn urban(k: usize) -> Vec<Polygon> {
    let mut out = Vec::new();
    let mut grid = |o: Vec3, u: Vec3, v: Vec3, nu: usize, nv: usize, normal: Vec3| {
        for a in 0..nu {
            for b in 0..nv {
                let p = |s: usize, t: usize| o + u * (s as f64 / nu as f64) + v * (t as f64 / nv as f64);
                let mut q = vec![p(a, b), p(a + 1, b), p(a + 1, b + 1), p(a, b + 1)];
                if (q[1] - q[0]).cross(q[2] - q[0]).dot(normal) < 0.0 {
                    q.reverse();
                }
                out.push(Polygon::new(q).unwrap());
            }
        }
    };
    grid(Vec3::ZERO, Vec3::new(8., 0., 0.), Vec3::new(0., 8., 0.), 4 * k, 4 * k, Vec3::Z);
    for i in 0..4 {
        for j in 0..4 {
            let (x, y, h) = (2.0 * i as f64 + 0.5, 2.0 * j as f64 + 0.5, 2.0);
            let up = Vec3::new(0., 0., h);
            grid(Vec3::new(x, y, h), Vec3::X, Vec3::Y, k, k, Vec3::Z);
            grid(Vec3::new(x, y, 0.), Vec3::X, up, k, 2 * k, -Vec3::Y);
            grid(Vec3::new(x, y + 1., 0.), Vec3::X, up, k, 2 * k, Vec3::Y);
            grid(Vec3::new(x, y, 0.), Vec3::Y, up, k, 2 * k, -Vec3::X);
            grid(Vec3::new(x + 1., y, 0.), Vec3::Y, up, k, 2 * k, Vec3::X);
        }
    }
    out
}
