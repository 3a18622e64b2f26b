use nusselt_core::unobstructed::method::{self, Facing};
use nusselt_core::Polygon;

/// Random pairs (i, j), i != j, of polygons that face each other, without end: an xorshift
/// stream with a fixed seed, so every run picks the same pairs.
pub fn facing_pairs(polys: &[Polygon]) -> impl Iterator<Item = (usize, usize)> + '_ {
    let n = polys.len() as u64;
    let mut s = 0x9e37_79b9_7f4a_7c15u64;
    std::iter::repeat_with(move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        ((s % n) as usize, ((s >> 20) % n) as usize)
    })
    .filter(|&(i, j)| i != j && method::facing(&polys[i], &polys[j]) != Facing::None)
}
