//! The blocks a straight segment passes through, in order: where a grouted bolt crosses the
//! joints. Sampled at a fraction of the cover size, each change of block found by bisection.

use nmm3d_geom::Vec3;

use super::Geometry;

/// A grouted bolt is sampled this fraction of the cover size apart (its joints found between).
pub const BOLT_SAMPLING: f64 = 0.125;
/// Bisection halves the bracket of a block change this many times (2⁻⁶⁰ of a sample step).
const BISECTIONS: u32 = 60;

/// A stretch of the segment inside one block (or in no block: a void).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Run {
    /// The block, none in a void or outside the model.
    pub block: Option<usize>,
    /// Start and end as fractions of the segment [0, 1].
    pub from: f64,
    /// End.
    pub to: f64,
}

/// The runs of the segment `a` → `b`, sampled at most `step` [m] apart (a block thinner than
/// that along the segment may be missed); `tol` [m] the containment tolerance.
pub fn runs(geometry: &Geometry, a: &Vec3, b: &Vec3, step: f64, tol: f64) -> Vec<Run> {
    let at = |t: f64| {
        let x = a + (b - a) * t;
        geometry.blocks.iter().position(|blk| blk.contains(&x, tol))
    };
    let n = ((b - a).norm() / step).ceil().max(1.0) as usize;
    let (mut out, mut cur, mut start, mut lo) = (Vec::new(), at(0.0), 0.0, 0.0);
    for i in 1..=n {
        let t = i as f64 / n as f64;
        while at(t) != cur {
            let (last, first) = bisect(lo, t, |x| at(x) == cur);
            out.push(Run { block: cur, from: start, to: last });
            (cur, start, lo) = (at(first), first, first);
        }
        lo = t;
    }
    out.push(Run { block: cur, from: start, to: 1.0 });
    out
}

/// The last point where `inside` holds and the first where it does not, between `lo` (inside)
/// and `hi` (not).
fn bisect(mut lo: f64, mut hi: f64, inside: impl Fn(f64) -> bool) -> (f64, f64) {
    for _ in 0..BISECTIONS {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if inside(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::parse_toml;

    /// A 4 m bar of rock cut by joints at x = 1 and x = 3.2, a 0.5 m void at x = 2 … 2.5.
    const BAR: &str = r#"
[analysis]
kind = "static"
[[material]]
name = "rock"
density = 2500.0
young = 1e10
poisson = 0.25
[[body]]
name = "bar"
material = "rock"
shape = { box = { min = [0.0, 0.0, 0.0], max = [4.0, 1.0, 1.0] } }
[[joint_plane]]
point = [1.0, 0.0, 0.0]
dip = 90.0
dip_direction = 90.0
[[joint_plane]]
point = [3.2, 0.0, 0.0]
dip = 90.0
dip_direction = 90.0
[[excavation]]
shape = { box = { min = [2.0, -1.0, -1.0], max = [2.5, 2.0, 2.0] } }
"#;

    #[test]
    fn a_bar_through_joints_and_a_void_is_cut_where_they_are() {
        let s = parse_toml(BAR, "bar", &[]).unwrap();
        let g = Geometry::from_scenario(&s);
        let o = g.origin;
        let (a, b) = (Vec3::new(0.2, 0.5, 0.5) - o, Vec3::new(3.8, 0.5, 0.5) - o);
        let r = runs(&g, &a, &b, 0.3, 1e-9);
        let x = |t: f64| 0.2 + 3.6 * t;
        assert_eq!(r.len(), 5, "{r:?}");
        let ends: Vec<(bool, f64, f64)> = r.iter().map(|r| (r.block.is_some(), x(r.from), x(r.to))).collect();
        for (got, want) in
            ends.iter().zip([(true, 0.2, 1.0), (true, 1.0, 2.0), (false, 2.0, 2.5), (true, 2.5, 3.2), (true, 3.2, 3.8)])
        {
            assert_eq!(got.0, want.0);
            // Found to the containment tolerance (a point that far outside still counts as in).
            assert!((got.1 - want.1).abs() < 2e-9 && (got.2 - want.2).abs() < 2e-9, "{got:?} vs {want:?}");
        }
        assert_ne!(r[0].block, r[1].block);
    }
}
