//! Blocks a static analysis no longer holds (`System::beyond_travel_limit`): their forces
//! leave the unbalanced force and their covers stay where the limit found them, so a static run
//! can stop once the other blocks are in equilibrium — a verdict for every block from one run,
//! without following a failing one down its slope (contact releases them: no points on them).

use std::borrow::Cow;

use nmm3d_geom::Vec3;

use crate::system::System;

/// Per-cover forces `f` without those on the covers of blocks beyond the limit.
pub(super) fn of_held<'a>(sys: &System, u: &[Vec3], f: &'a [Vec3]) -> Cow<'a, [Vec3]> {
    let gone = sys.released(u);
    if !gone.contains(&true) {
        return Cow::Borrowed(f);
    }
    let mut out = f.to_vec();
    zero_on(sys, &gone, &mut out);
    Cow::Owned(out)
}

/// The increment `d` with the covers of blocks beyond the limit held in place. Released from
/// every contact, such a block's equations are its own, so zeroing its part of the solution
/// leaves the others' exact — and keeps its fall out of the step's displacement ratio.
pub(super) fn pin(sys: &System, u: &[Vec3], d: &mut [Vec3]) {
    zero_on(sys, &sys.released(u), d);
}

/// Zero the per-cover values `v` on the covers of the blocks marked in `gone`.
fn zero_on(sys: &System, gone: &[bool], v: &mut [Vec3]) {
    for (c, x) in v.iter_mut().enumerate() {
        if gone[sys.covers.covers[c].block] {
            *x = Vec3::zeros();
        }
    }
}
