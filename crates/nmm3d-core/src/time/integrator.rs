//! Newmark time integration of (K + M/(βΔt²)) d = F − F_int + M(v/(βΔt) + (1/(2β) − 1) a).
//!
//! The DDA scheme is Newmark with β = ½, γ = 1 (Shi 1988; thesis §3.3): (K + 2M/Δt²)d =
//! F + 2Mv₀/Δt − F_int, v₁ = 2d/Δt − v₀. It integrates constant acceleration exactly and is
//! dissipative (restitution < 1, see `docs/theory/time-integration.md`); β = ¼, γ = ½ (the
//! trapezoidal rule) conserves energy of linear systems.

use crate::scenario::{Analysis, Integrator};

/// Newmark parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Newmark {
    /// β.
    pub beta: f64,
    /// γ.
    pub gamma: f64,
}

/// Coefficients of one step size.
#[derive(Debug, Clone, Copy)]
pub struct StepCoefficients {
    /// 1/(βΔt²): mass factor in the matrix.
    pub c0: f64,
    /// 1/(βΔt): velocity factor in the right-hand side.
    pub c1: f64,
    /// 1/(2β) − 1: acceleration factor in the right-hand side.
    pub c2: f64,
}

impl Newmark {
    /// From the analysis controls.
    pub fn from_analysis(a: &Analysis) -> Self {
        match a.integrator {
            Integrator::Dda => Self { beta: 0.5, gamma: 1.0 },
            Integrator::Newmark => Self { beta: a.newmark_beta, gamma: a.newmark_gamma },
        }
    }

    /// Coefficients for step `dt`.
    pub fn coefficients(&self, dt: f64) -> StepCoefficients {
        StepCoefficients { c0: 1.0 / (self.beta * dt * dt), c1: 1.0 / (self.beta * dt), c2: 0.5 / self.beta - 1.0 }
    }

    /// Whether the previous acceleration enters the right-hand side.
    pub fn uses_acceleration(&self) -> bool {
        (self.beta - 0.5).abs() > 0.0
    }
}
