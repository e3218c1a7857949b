//! The top envelope h(x, y): the highest z with T₁(x, y, z) ≤ 0, the part a
//! 3-axis mill cuts from above (overhangs filled).
//!
//! Down the vertical ray through (x, y) from just under the box top to just
//! above its floor, T₁ is sampled every `step`; at the first sample with
//! T₁ ≤ 0, the crossing between it and the sample above (where T₁ > 0) is
//! bisected on the sign of T₁ until the bracket is shorter than `tol`, and h is
//! its upper end (a point where T₁ > 0 within `tol` of the solid; the bracket
//! always holds a sign change, so the result is within `tol` of a zero of T₁).
//! A solid piece thinner than `step` in z can fall between two samples and be
//! missed: `step` is the thinnest feature the envelope promises to see.

use super::error::{invalid, PolyError};
use super::fault::PolyFault;
use super::system::Solution;
use nalgebra::Vector3;

/// Most samples down one ray: (box height)/step is capped so one ray's work
/// is bounded.
pub(crate) const MAX_SAMPLES: usize = 100_000;

/// The envelope's settings, in the points' length unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Envelope {
    /// Marching step down the ray (> 0).
    pub step: f64,
    /// Bisection tolerance on z (> 0).
    pub tol: f64,
}

impl Envelope {
    /// Checks `step` and `tol` against the box of `sol` (`envelope`).
    pub fn validated(self, sol: &Solution) -> Result<Self, PolyError> {
        let height = sol.mesh().hi.z - sol.mesh().lo.z;
        if !(self.step.is_finite() && self.step > 0.0 && self.tol.is_finite() && self.tol > 0.0) {
            return Err(invalid(
                "envelope",
                PolyFault::EnvelopeSettings {
                    step: self.step,
                    tol: self.tol,
                },
            ));
        }
        if height / self.step > MAX_SAMPLES as f64 {
            return Err(invalid(
                "envelope",
                PolyFault::EnvelopeSamples { step: self.step },
            ));
        }
        Ok(self)
    }

    /// h(x, y), or None where the ray misses the solid or (x, y) is not
    /// strictly inside the box's footprint. `self` must be [`validated`]
    /// (otherwise the loop is still bounded by [`MAX_SAMPLES`]).
    ///
    /// [`validated`]: Envelope::validated
    pub fn height(&self, sol: &Solution, x: f64, y: f64) -> Option<f64> {
        let (lo, hi) = (sol.mesh().lo.z, sol.mesh().hi.z);
        // Half a step in from the box faces, where T₁ = 1 is held.
        let top = hi - 0.5 * self.step.min(0.5 * (hi - lo));
        let t = |z: f64| sol.value(Vector3::new(x, y, z));
        let mut above = top;
        if t(above)? <= 0.0 {
            return Some(above);
        }
        for k in 1..=MAX_SAMPLES {
            let z = top - k as f64 * self.step;
            if z <= lo {
                return None;
            }
            if t(z)? <= 0.0 {
                return Some(self.bisect(&t, z, above));
            }
            above = z;
        }
        None
    }

    /// Bisects [below, above] (T₁(below) ≤ 0 < T₁(above)) to `tol`; returns the
    /// upper end. At most 200 halvings (f64 runs out well before).
    fn bisect(&self, t: &impl Fn(f64) -> Option<f64>, mut below: f64, mut above: f64) -> f64 {
        for _ in 0..200 {
            if above - below <= self.tol {
                break;
            }
            let mid = 0.5 * (below + above);
            match t(mid) {
                Some(v) if v <= 0.0 => below = mid,
                _ => above = mid,
            }
        }
        above
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sources::polyharmonic::system::{solve, tests::sphere_model_for_envelope};

    /// The sphere of 40 points: h ≈ √(1 − x² − y²) within 0.01 where the
    /// ray hits it, None beyond radius 1.02 and outside the box.
    #[test]
    fn the_envelope_of_the_sphere_is_its_upper_half() {
        let sol = solve(&sphere_model_for_envelope()).unwrap();
        let env = Envelope {
            step: 0.05,
            tol: 1e-6,
        }
        .validated(&sol)
        .unwrap();
        let mut worst: f64 = 0.0;
        for i in 0..=16 {
            for j in 0..=16 {
                let (x, y) = (-1.2 + 0.15 * i as f64, -1.2 + 0.15 * j as f64);
                let rho = x.hypot(y);
                let h = env.height(&sol, x, y);
                if rho < 0.95 {
                    let h = h.expect("a hit inside the sphere's shadow");
                    worst = worst.max((h - (1.0 - rho * rho).sqrt()).abs());
                } else if rho > 1.02 {
                    assert_eq!(h, None, "({x}, {y}) is outside the sphere's shadow");
                }
            }
        }
        // Near the rim h is steep in ρ: a radius error ε moves h by ε/cos θ,
        // about 3ε at ρ = 0.95 (the radius error is 0.003 here).
        assert!(worst < 0.01, "max |h − √(1 − ρ²)| = {worst:.4}");
        assert_eq!(env.height(&sol, 2.5, 0.0), None);
        assert_eq!(env.height(&sol, 0.0, -2.0), None);
    }

    #[test]
    fn bad_settings_are_typed_errors() {
        let sol = solve(&sphere_model_for_envelope()).unwrap();
        for (step, tol) in [(0.0, 1e-6), (0.05, 0.0), (f64::NAN, 1e-6), (1e-6, 1e-6)] {
            let e = Envelope { step, tol }.validated(&sol).unwrap_err();
            assert!(e.to_string().starts_with("envelope:"), "{e}");
        }
    }
}
