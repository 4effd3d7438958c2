//! A fully grouted bolt or cable where it crosses a joint: the local reinforcement model of
//! UDEC and 3DEC (Lorig 1985), one spring across each joint with closed-form stiffness and
//! strength from the bar and its grout ([`super::bolt::BoltSpring`] carries it).
//!
//! * Axial: on each side the bar is bonded over its embedded length L (to the bolt's end or the
//!   next joint) by a grout of shear stiffness k_b per unit length; pulled at the joint it is a
//!   bar on an elastic shear foundation, u'' = β² u with β = √(k_b / EA), whose end stiffness
//!   is √(EA k_b) tanh(βL) (Farmer 1975). The two sides act in series.
//! * Dowel: on each side the bar is a beam on an elastic (Winkler) foundation of modulus k_f;
//!   the joint's shear V loads both ends with zero moment (antisymmetry), each deflecting
//!   2 V λ / k_f with λ = (k_f / 4EI)^¼ (Hetényi 1946), so k_s = k_f / (4λ).
//! * Strength: the tension at the joint is limited by the steel (yield force) and by pull-out
//!   of the shorter side, bond strength × its length; the shear by the dowel's capacity.

use super::bolt::SpringLaw;
use crate::scenario::Bolt;

/// Axial stiffness [N/m] of a bar of rigidity `ea` [N] bonded over `length` [m] by a grout of
/// stiffness `kb` [Pa], pulled at one end.
pub fn side_stiffness(ea: f64, kb: f64, length: f64) -> f64 {
    (ea * kb).sqrt() * ((kb / ea).sqrt() * length).tanh()
}

/// Axial stiffness [N/m] across a joint with `l1` and `l2` [m] of bonded bar on its sides.
pub fn axial_stiffness(ea: f64, kb: f64, l1: f64, l2: f64) -> f64 {
    let (k1, k2) = (side_stiffness(ea, kb, l1), side_stiffness(ea, kb, l2));
    k1 * k2 / (k1 + k2)
}

/// Shear stiffness [N/m] of a dowel of bending rigidity `ei` [N m²] in a foundation of modulus
/// `kf` [Pa] across a joint.
pub fn dowel_stiffness(kf: f64, ei: f64) -> f64 {
    let lambda = (kf / (4.0 * ei)).powf(0.25);
    kf / (4.0 * lambda)
}

/// The spring of grouted bolt `b` across a joint with `l1`, `l2` [m] of it on either side.
pub fn crossing_law(b: &Bolt, l1: f64, l2: f64) -> SpringLaw {
    let g = &b.grout;
    let ea = g.axial_rigidity.unwrap_or(0.0);
    let kb = g.bond_stiffness.unwrap_or(0.0);
    let shear_stiffness = match (g.foundation_modulus, g.diameter) {
        (Some(kf), Some(d)) => dowel_stiffness(kf, ea * d * d / 16.0),
        _ => 0.0,
    };
    let pull_out = g.bond_strength.map_or(f64::INFINITY, |t| t * l1.min(l2));
    SpringLaw {
        stiffness: axial_stiffness(ea, kb, l1, l2),
        shear_stiffness,
        pretension: 0.0,
        yield_force: b.yield_force.unwrap_or(f64::INFINITY).min(pull_out),
        shear_capacity: g.shear_capacity.unwrap_or(f64::INFINITY),
        rupture: b.rupture_elongation.unwrap_or(f64::INFINITY),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_bond_tends_to_the_semi_infinite_bar_and_a_short_one_to_the_grout() {
        let (ea, kb) = (1e8, 1e9);
        // β = √10 /m: 5 m is semi-infinite, 1 mm is the grout alone (k_b L).
        assert!((side_stiffness(ea, kb, 5.0) / (ea * kb).sqrt() - 1.0).abs() < 1e-12);
        assert!((side_stiffness(ea, kb, 1e-3) / (kb * 1e-3) - 1.0).abs() < 1e-5);
        // Equal sides in series: half of one.
        assert!((axial_stiffness(ea, kb, 5.0, 5.0) / (0.5 * (ea * kb).sqrt()) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn the_dowel_stiffness_is_twice_hetenyis_end_deflection() {
        // Semi-infinite beam on a Winkler foundation loaded at its free end by P: y = 2Pλ/k.
        let (kf, ei): (f64, f64) = (2e9, 1e4);
        let lambda = (kf / (4.0 * ei)).powf(0.25);
        let (p, y) = (1e3, 2.0 * 1e3 * lambda / kf);
        assert!((p / (2.0 * y) / dowel_stiffness(kf, ei) - 1.0).abs() < 1e-12);
    }
}
