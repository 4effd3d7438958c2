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
