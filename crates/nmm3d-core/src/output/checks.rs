//! The run's answers beside their references (`[[expect]]`): the `checks` of `summary.json`.

use std::collections::BTreeMap;

use super::summary::Check;
use crate::scenario::Expect;

/// One entry per expectation: the final value, the reference, the signed relative difference
/// (difference / reference: negative when the answer falls short; null when the reference is zero) and whether the difference is within the tolerance.
pub fn checks(expect: &[Expect], last: &BTreeMap<String, Option<f64>>) -> Vec<Check> {
    expect.iter().map(|e| check(e, last.get(&e.quantity).copied().flatten())).collect()
}

fn check(e: &Expect, value: Option<f64>) -> Check {
    let diff = value.zip(e.reference).map(|(v, r)| v - r);
    let relative = diff.zip(e.reference.filter(|&r| r != 0.0)).map(|(d, r)| d / r);
    let allowed = (e.tolerance * e.reference.unwrap_or(0.0).abs()).max(e.absolute_tolerance);
    let near = e.reference.is_none() || diff.is_some_and(|d| d.abs() <= allowed);
    let above = e.at_least.is_none_or(|lo| value.is_some_and(|v| v >= lo));
    let below = e.at_most.is_none_or(|hi| value.is_some_and(|v| v <= hi));
    let passed = value.is_some() && near && above && below;
    Check {
        quantity: e.quantity.clone(),
        value,
        reference: e.reference,
        relative_difference: relative,
        tolerance: e.tolerance,
        absolute_tolerance: e.absolute_tolerance,
        at_least: e.at_least,
        at_most: e.at_most,
        passed,
        source: e.source.clone(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn expect(reference: f64, tolerance: f64, absolute_tolerance: f64) -> Expect {
        Expect {
            quantity: "tip.displacement.z".into(),
            reference: Some(reference),
            tolerance,
            absolute_tolerance,
            at_least: None,
            at_most: None,
            source: String::new(),
        }
    }

    fn last(v: f64) -> BTreeMap<String, Option<f64>> {
        BTreeMap::from([("tip.displacement.z".to_string(), Some(v))])
    }

    #[test]
    fn relative_tolerance_is_of_the_reference() {
        let c = checks(&[expect(-0.04, 0.01, 0.0)], &last(-0.0397));
        assert!(c[0].passed);
        assert!((c[0].relative_difference.unwrap() - -0.0075).abs() < 1e-12);
        let c = checks(&[expect(-0.04, 0.01, 0.0)], &last(-0.0395));
        assert!(!c[0].passed);
    }

    #[test]
    fn a_zero_reference_needs_the_absolute_tolerance() {
        let c = checks(&[expect(0.0, 0.01, 1e-9)], &last(1e-12));
        assert!(c[0].passed);
        assert_eq!(c[0].relative_difference, None);
        assert!(!checks(&[expect(0.0, 0.01, 0.0)], &last(1e-12))[0].passed);
    }

    #[test]
    fn a_missing_value_fails() {
        let c = checks(&[expect(1.0, 0.5, 0.0)], &BTreeMap::new());
        assert!(!c[0].passed);
        assert_eq!(c[0].value, None);
    }

    #[test]
    fn bounds_judge_a_qualitative_outcome() {
        let bounded = |at_least, at_most| Expect { reference: None, at_least, at_most, ..expect(0.0, 0.01, 0.0) };
        let passed = |e: Expect, v: f64| checks(&[e], &last(v))[0].passed;
        assert!(passed(bounded(Some(0.15), None), 0.3));
        assert!(!passed(bounded(Some(0.15), None), 0.1));
        assert!(passed(bounded(None, Some(-0.15)), -0.2));
        assert!(!passed(bounded(Some(-1.0), Some(-0.15)), -0.1));
        assert!(!checks(&[bounded(Some(0.0), None)], &BTreeMap::new())[0].passed, "missing value");
        // A reference and a bound: both must hold.
        let both = Expect { at_most: Some(-0.0396), ..expect(-0.04, 0.01, 0.0) };
        assert!(passed(both.clone(), -0.0397));
        assert!(!passed(both, -0.0395));
        assert_eq!(checks(&[bounded(Some(0.15), None)], &last(0.3))[0].reference, None);
    }
}
