//! Isotropic linear elastic material.

use crate::scenario::Material;

/// Elastic constants in the forms the kernels use.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elastic {
    /// Density ρ [kg/m³].
    pub density: f64,
    /// Young's modulus E [Pa].
    pub young: f64,
    /// Poisson's ratio ν [-].
    pub poisson: f64,
    /// Lamé λ = Eν/((1+ν)(1−2ν)) [Pa].
    pub lambda: f64,
    /// Shear modulus μ = E/(2(1+ν)) [Pa].
    pub mu: f64,
}

impl Elastic {
    /// From the scenario entry.
    pub fn new(m: &Material) -> Self {
        let (e, nu) = (m.young, m.poisson);
        Self {
            density: m.density,
            young: e,
            poisson: nu,
            lambda: e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            mu: e / (2.0 * (1.0 + nu)),
        }
    }
}
