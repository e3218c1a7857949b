//! Points moved onto a level Γ(s) = {u = s} of a field.
//!
//! Newton's method on u − s along the gradient: one step from q is
//!
//! q ← q − (u(q) − s) ∇u(q) / |∇u(q)|²,
//!
//! the point where the linear model u(q) + ∇u(q)·(x − q) reaches s nearest to
//! q. Where u is smooth on the scale of the step the error |u − s| squares at
//! every step. [`Limits`] says when to stop and when to give up: near a
//! saddle of u (∇u small) a step can throw the point far off, and a point
//! that lands far from where it started is on another stretch of Γ(s).

use super::Field;
use crate::geometry::Vec2;

/// When a Newton projection stops, and when it gives up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Limits {
    /// The most steps taken.
    pub steps: usize,
    /// Stop, before a step, once |u − s| ≤ this (0: never early on the
    /// residual).
    pub eps: f64,
    /// Stop after a step shorter than this, mm (0: never).
    pub min_step: f64,
    /// A step longer than this is shortened to it, along the same direction,
    /// mm (∞: never).
    pub max_step: f64,
    /// The farthest the result may lie from the start, mm; farther (or not a
    /// number) gives `None`.
    pub reach: f64,
    /// Give up as soon as a step is longer than `reach` or an iterate lies
    /// farther than `reach` from the start, not only at the end.
    pub leash: bool,
}

impl Limits {
    /// At most `steps` steps, the result within `reach` of the start, no
    /// other stop or bound.
    pub(crate) const fn steps(steps: usize, reach: f64) -> Limits {
        Limits {
            steps,
            eps: 0.0,
            min_step: 0.0,
            max_step: f64::INFINITY,
            reach,
            leash: false,
        }
    }
}

/// `p` moved onto Γ(s) by Newton steps along ∇u (see the module docs) within
/// `limits`; `None` when ∇u vanishes on the way or the result (or, with a
/// leash, any step or iterate) strays beyond `limits.reach`.
pub(crate) fn project(field: &Field, p: Vec2, s: f64, limits: &Limits) -> Option<Vec2> {
    let mut q = p;
    for _ in 0..limits.steps {
        let (u, g) = field.value_grad(q);
        let r = u - s;
        if r.abs() <= limits.eps {
            break;
        }
        let g2 = g.norm2();
        if g2 == 0.0 {
            return None;
        }
        let step = shortened(g * (r / g2), limits.max_step);
        q -= step;
        if limits.leash && !(step.norm() <= limits.reach && q.dist(p) <= limits.reach) {
            return None;
        }
        if step.norm() < limits.min_step {
            break;
        }
    }
    (q.dist(p) <= limits.reach).then_some(q)
}

/// `step` scaled down to length `max` when it is longer.
fn shortened(step: Vec2, max: f64) -> Vec2 {
    let l = step.norm();
    if l > max {
        step * (max / l)
    } else {
        step
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    /// Two unit charges 2a apart: ∇u turns along the way, so the Newton path
    /// is not a straight line and Γ(s) is no circle (Cassini ovals).
    fn two_charges() -> Field {
        Field::new(
            vec![Vec2::new(-2.0, 0.0), Vec2::new(2.0, 0.0)],
            vec![1.0, 1.0],
        )
    }

    /// Points on a spiral around the charges, none of them a charge.
    fn probes() -> Vec<Vec2> {
        (0..40)
            .map(|k| {
                let t = 0.37 * k as f64 + 0.1;
                Vec2::new(t.cos(), t.sin()) * (3.0 + 0.15 * k as f64)
            })
            .collect()
    }

    /// ∇u by central differences of u, step `d`.
    fn grad_fd(f: &Field, p: Vec2, d: f64) -> Vec2 {
        let (dx, dy) = (Vec2::new(d, 0.0), Vec2::new(0.0, d));
        Vec2::new(
            (f.value(p + dx) - f.value(p - dx)) / (2.0 * d),
            (f.value(p + dy) - f.value(p - dy)) / (2.0 * d),
        )
    }

    #[test]
    fn projected_points_lie_on_their_level() {
        let f = two_charges();
        let lim = Limits {
            eps: 1e-13,
            ..Limits::steps(20, 10.0)
        };
        for p in probes() {
            // A level a few tenths of a millimetre from p, either side.
            for ds in [-0.02, 0.01, 0.03] {
                let s = f.value(p) + ds;
                let q = project(&f, p, s, &lim).expect("converges");
                let e = (f.value(q) - s).abs();
                assert!(e < 1e-12, "p {p:?}, s {s}: |u - s| = {e:e}");
            }
        }
    }

    #[test]
    fn one_step_moves_along_the_gradient_by_the_newton_length() {
        let f = two_charges();
        for p in probes() {
            let s = f.value(p) + 0.01;
            let q = project(&f, p, s, &Limits::steps(1, 10.0)).expect("one step");
            let g = grad_fd(&f, p, 1e-5);
            // The step is −(u − s) ∇u / |∇u|²: along ∇u, toward higher u here.
            let want = p + g * ((s - f.value(p)) / g.norm2());
            assert!(
                q.dist(want) < 1e-8 * (1.0 + want.dist(p)),
                "{q:?} vs {want:?}"
            );
            let d = q - p;
            let sin = (d.x * g.y - d.y * g.x) / (d.norm() * g.norm());
            assert!(sin.abs() < 1e-7 && d.x * g.x + d.y * g.y > 0.0, "sin {sin}");
        }
    }

    #[test]
    fn a_single_charge_projects_radially_onto_its_circle() {
        // u = −(1/2π) ln r: Γ(s) is the circle r = exp(−2πs), ∇u radial.
        let f = Field::new(vec![Vec2::ZERO], vec![1.0]);
        let r0: f64 = 4.0;
        let s = -r0.ln() / TAU;
        for p in probes() {
            let q = project(&f, p, s, &Limits::steps(30, 100.0)).expect("converges");
            assert!((q.norm() - r0).abs() < 1e-10, "{}", q.norm());
            assert!(q.normalized().dist(p.normalized()) < 1e-12);
        }
    }

    #[test]
    fn limits_shorten_steps_and_refuse_far_results() {
        let f = Field::new(vec![Vec2::ZERO], vec![1.0]);
        let p = Vec2::new(3.0, 0.0);
        let s = -(4.0f64).ln() / TAU;
        // One step of at most 0.25 mm: exactly 0.25 mm outward.
        let short = Limits {
            max_step: 0.25,
            ..Limits::steps(1, 1.0)
        };
        let q = project(&f, p, s, &short).expect("within reach");
        assert!((q.x - 3.25).abs() < 1e-15 && q.y == 0.0, "{q:?}");
        // The circle is 1 mm away: out of a 0.5 mm reach, with or without a leash.
        assert_eq!(project(&f, p, s, &Limits::steps(30, 0.5)), None);
        let leash = Limits {
            leash: true,
            ..Limits::steps(30, 0.5)
        };
        assert_eq!(project(&f, p, s, &leash), None);
        // Where ∇u vanishes (midway between equal charges) there is no step.
        assert_eq!(
            project(&two_charges(), Vec2::ZERO, 0.0, &Limits::steps(6, 9.0)),
            None
        );
    }
}
