//! The level curves Γ(s) = {u = s} of a field as closed polygons, and
//! points moved onto a level: the one service the level planner, compose,
//! the finishing and the surface take them from.
//!
//! A grid of u ([`Grid`]) is grown until Γ(s) closes inside it
//! ([`closing_grid`]); its rings ([`super::isolines`]) lose the slivers
//! ([`drop_slivers`]) and have their chords refined onto Γ(s) ([`refine`]);
//! [`curves`] is all of it for the job's glyphs.
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

use super::isolines::{isolines, Grid};
use super::Field;
use crate::geometry::{Ring, Vec2};
use rayon::prelude::*;

/// Chords of a level's contour stay within this fraction of the tolerance of
/// Γ(s): the rings are traced against the polygon, so a chord's sagitta inside
/// a convex stretch of Γ(s) is a gouge the level's own check cannot see (at a
/// quarter, one cell of the power-wall mfs-sign was 0.0104 mm deep against S2).
pub const CHORD_FRACTION: f64 = 0.1;

/// The first of the grids `sample(0)`, `sample(1)`, …, `sample(tries − 1)`,
/// sampled one after another and only as many as needed, whose border stays
/// below s, so that every ring of Γ(s) closes inside it; `None` when none
/// does.
pub(crate) fn closing_grid(
    s: f64,
    tries: usize,
    sample: impl FnMut(usize) -> Grid,
) -> Option<Grid> {
    (0..tries).map(sample).find(|g| g.border_max() < s)
}

/// The rings of a grid of spacing `h` without the slivers: a ring enclosing
/// 4h² or less (two cells by two) is marching squares' answer to u grazing s
/// between grid points, not a part of Γ(s) a tool could follow.
pub(crate) fn drop_slivers(rings: Vec<Ring>, h: f64) -> Vec<Ring> {
    rings
        .into_iter()
        .filter(|p| p.signed_area().abs() > 4.0 * h * h)
        .collect()
}

/// Γ(s) as rings (material on the left) from u sampled on `grid` (spacing
/// `h`), `glyphs` the material: the glyphs themselves at s = 1 (those that are
/// rings), else the rings of marching squares without the slivers, their
/// chords refined onto Γ(s) within [`CHORD_FRACTION`] of `tol`.
pub(crate) fn curves(
    grid: &Grid,
    f: &Field,
    glyphs: &[Vec<Vec2>],
    s: f64,
    h: f64,
    tol: f64,
) -> Vec<Ring> {
    if s >= 1.0 - 1e-12 {
        return glyphs.iter().cloned().filter_map(Ring::new).collect();
    }
    drop_slivers(isolines(grid, s, f, glyphs), h)
        .into_par_iter()
        .map(|p| refine(&p, f, s, CHORD_FRACTION * tol))
        .collect()
}

/// Insert vertices on Γ(s) where a chord of `ring` strays more than `tol`
/// from it (the chord's midpoint projected onto Γ(s), see [`onto_chord`]), up
/// to four halvings. The inserted vertices are finite (a projection that is
/// not gives none) and lie between the chord's ends, so the result is a ring;
/// should one coincide with an end, [`Ring::new`] drops the duplicate.
pub(crate) fn refine(ring: &Ring, field: &Field, s: f64, tol: f64) -> Ring {
    let mut out = Vec::with_capacity(ring.len() * 2);
    for (a, b) in ring.edges() {
        out.push(a);
        refine_edge(a, b, field, s, tol, 4, &mut out);
    }
    Ring::new(out).unwrap_or_else(|| ring.clone())
}

/// The vertices refining the chord a–b (`depth` halvings left), pushed in
/// order after a: the midpoint's projection q when it lies more than `tol`
/// from the midpoint, with the chords a–q and q–b refined in turn.
fn refine_edge(
    a: Vec2,
    b: Vec2,
    field: &Field,
    s: f64,
    tol: f64,
    depth: usize,
    out: &mut Vec<Vec2>,
) {
    if depth == 0 {
        return;
    }
    let m = a.lerp(b, 0.5);
    if let Some(q) = onto_chord(field, m, s, a.dist(b)) {
        if q.dist(m) > tol {
            refine_edge(a, q, field, s, tol, depth - 1, out);
            out.push(q);
            refine_edge(q, b, field, s, tol, depth - 1, out);
        }
    }
}

/// A chord's midpoint moved onto Γ(s) by at most six Newton steps, stopping
/// after one under 1e-10 mm, and only as far as the chord is long.
fn onto_chord(field: &Field, m: Vec2, s: f64, chord: f64) -> Option<Vec2> {
    let limits = Limits {
        min_step: 1e-10,
        ..Limits::steps(6, chord)
    };
    project(field, m, s, &limits)
}

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

    /// u = −(1/2π) ln r about the origin: Γ(s) is the circle r = exp(−2πs),
    /// u falls outward.
    fn falling() -> Field {
        Field::new(vec![Vec2::ZERO], vec![1.0])
    }

    #[test]
    fn the_grid_grows_until_the_level_closes_inside_it() {
        let f = falling();
        let r0: f64 = 10.0;
        let s = -r0.ln() / TAU;
        // Boxes of half-width 0.45 r0, 0.9 r0, 1.35 r0, ...: the border is
        // below s from the third on.
        let sample = |k: usize| {
            let d = Vec2::new(1.0, 1.0) * (0.45 * r0 * (k + 1) as f64);
            Grid::sample(&f, -d, d, 0.5, &[])
        };
        let g = closing_grid(s, 6, sample).expect("closes");
        assert!((g.origin.x + 13.5).abs() < 1e-12, "{:?}", g.origin);
        assert!(closing_grid(s, 2, sample).is_none());
    }

    #[test]
    fn curves_drop_slivers_and_refine_chords_onto_the_level() {
        let f = falling();
        let r0: f64 = 10.0;
        let s = -r0.ln() / TAU;
        let d = Vec2::new(15.0, 15.0);
        let grid = Grid::sample(&f, -d, d, 0.5, &[]);
        let tol = 0.01;
        let c = curves(&grid, &f, &[], s, 0.5, tol);
        assert_eq!(c.len(), 1);
        let ring = &c[0];
        let n = ring.len();
        for (k, (a, b)) in ring.edges().enumerate() {
            assert!((a.norm() - r0).abs() < 1e-9, "vertex {a:?}");
            let sag = r0 - a.lerp(b, 0.5).norm();
            assert!(sag <= CHORD_FRACTION * tol, "chord {k}: {sag}");
        }
        // More vertices than marching squares gave: chords were halved.
        assert!(n > isolines(&grid, s, &f, &[])[0].len());
        // At s = 1 the curves are the glyphs themselves.
        let sq = vec![vec![Vec2::ZERO, Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0)]];
        let top = curves(&grid, &f, &sq, 1.0, 0.5, tol);
        assert_eq!(top.len(), 1);
        assert_eq!(top[0].points(), &sq[0][..]);
        // A ring of area 4h² or less is a sliver.
        let tiny = Ring::new(vec![
            Vec2::ZERO,
            Vec2::new(0.9, 0.0),
            Vec2::new(0.9, 0.9),
            Vec2::new(0.0, 0.9),
        ])
        .expect("a square");
        let kept = drop_slivers(vec![tiny, ring.clone()], 0.5);
        assert_eq!(kept, vec![ring.clone()]);
    }
}
