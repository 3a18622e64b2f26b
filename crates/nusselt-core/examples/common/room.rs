use nusselt_core::{Polygon, Vec3};

/// The box room of bench/obstructed.py: 6 n^2 wall quads, 6 (n/3)^2 inner-box quads.
pub fn room(n: usize) -> Vec<Polygon> {
    let mut out = meshed_box(3.0, Vec3::ZERO, n, true);
    out.extend(meshed_box(1.0, Vec3::new(0.8, 0.7, 1.1), (n / 3).max(2), false));
    out
}

/// The cube [0, size]^3 + offset, each face split into m x m quads facing inward or outward.
pub fn meshed_box(size: f64, offset: Vec3, m: usize, inward: bool) -> Vec<Polygon> {
    let mut out = Vec::new();
    let t: Vec<f64> = (0..=m).map(|k| size * k as f64 / m as f64).collect();
    for axis in 0..3 {
        for side in [0.0, size] {
            let others: Vec<usize> = (0..3).filter(|&k| k != axis).collect();
            let (u, w) = (others[0], others[1]);
            let mut normal = [0.0; 3];
            normal[axis] = (if side == 0.0 { 1.0 } else { -1.0 }) * (if inward { 1.0 } else { -1.0 });
            let normal = Vec3::from_array(normal);
            for i in 0..m {
                for j in 0..m {
                    let mut q: Vec<Vec3> = [(0, 0), (1, 0), (1, 1), (0, 1)]
                        .iter()
                        .map(|&(di, dj)| {
                            let mut v = [0.0; 3];
                            v[axis] = side;
                            v[u] = t[i + di];
                            v[w] = t[j + dj];
                            Vec3::from_array(v) + offset
                        })
                        .collect();
                    if (q[1] - q[0]).cross(q[2] - q[0]).dot(normal) < 0.0 {
                        q.reverse();
                    }
                    out.push(Polygon::new(q).unwrap());
                }
            }
        }
    }
    out
}
