//! The examples' scene file: one polygon per line, the x y z of each vertex whitespace
//! separated; blank lines are skipped.
use nusselt_core::{Polygon, Vec3};

pub fn read_polygons(path: &str) -> Vec<Polygon> {
    let text = std::fs::read_to_string(path).expect("readable polygon file");
    text.lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let x: Vec<f64> = l.split_whitespace().map(|s| s.parse().expect("a number")).collect();
            Polygon::new(x.chunks(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect()).expect("a valid polygon")
        })
        .collect()
}
