//! Building the MFS problem (2.1)/(2.5) for a shape: collocation points on every
//! contour, singularities inside the material, an outer circle with u = 0, a sink
//! with u = 0 inside every counter, and the check points.

use super::mfs::{Condition, Problem};
use super::FieldError;
use crate::geometry::{polygon_winding_number, Contour, DistanceIndex, Sample, Vec2};
use std::f64::consts::TAU;

/// Turning angle (radians) above which a join is a corner for the check points.
pub const CORNER_TURN: f64 = 0.05;

/// Turning angle (radians) above which a convex corner of the material gets a
/// cluster of singularities: there the domain angle α = π + turn exceeds π and
/// u − 1 ~ r^(π/α) is singular in its gradient.
pub const SINGULAR_TURN: f64 = 0.15;

/// Outer singularities sit on a circle of this many times the outer radius R: far
/// enough that the ring's own aliasing term, (1/3)^8 / 8 ≈ 2e-5 of its charge for
/// eight charges, stays well under the errors we aim for.
pub const OUTER_CHARGE_FACTOR: f64 = 3.0;

/// Turning angle (radians) to the right above which a join is a notch of the
/// void (a concave corner of the material, the void's wedge narrower than
/// π − 0.5): the refined layout ([`Refinement`]) clusters charges at it too.
/// The field is smooth in the wedge, u − 1 ~ r^(π/α) with π/α > 1, but its
/// continuation into the material branches at the tip, and uniform charges
/// sit too far from it: DejaVu Serif "B" at 50 mm and N = 2 000 erred 3.3e-4
/// without notch clusters and 5.9e-6 with them (docs/method.md §3d).
pub const NOTCH_TURN: f64 = 0.5;

/// Number of singularities on the outer circle (u = 0 there). The field at radius R
/// is a monopole plus multipoles decaying like (glyph size / R)^k, so few suffice.
pub const OUTER_CHARGES: usize = 8;

/// Fewest and most singularities on the outer circle of a paired layout
/// (`Layout::pairs`): a ring of n charges at 3R leaves an aliasing error near
/// 3⁻ⁿ; 8 left a floor of 4.7e-6 on a 10 × 40 rectangle, 16 leave 2e-8. The ring
/// takes one charge in 32 of N within these bounds.
pub const PAIRED_OUTER_CHARGES: (usize, usize) = (8, 16);

/// Singularities inside each counter's sink circle in a paired layout: the
/// ring's aliasing term, about (1/4)ⁿ/n, left a floor of 9.0e-4 on the paper's
/// letter A with 6 (the same figure from N = 396 to 1 000); with 12 the term
/// is (1/4)¹²/12 ≈ 4e-9 and A reaches 9.3e-6 at N = 1 000.
pub const PAIRED_SINK_CHARGES: usize = 12;

/// Corner charges of a paired layout sit in pairs at ± this angle (radians)
/// about the corner's bisector. Near a convex corner
/// u − 1 = Σₖ aₖ r^(kπ/α) sin(kπθ/α): the odd terms are symmetric about the
/// bisector, the even ones antisymmetric, and charges on the bisector alone can
/// make only the symmetric ones, which stalls the fit near 1e-4
/// (../shared/design/FIELD-NOTES.md). Halved for a corner whose material wedge
/// is narrower than twice this.
pub const PAIR_ANGLE: f64 = 0.3;

/// Fewest charges per corner laid out in pairs; below it they go on the
/// bisector (with one or two per corner, pairs doubled the error of the letter
/// I: the symmetric terms, which carry most of the field, got half the charges).
pub const PAIR_MIN: usize = 6;

/// Check points between neighbouring collocation points: 4 in the plain layout,
/// 10 in the paired one (the "at least 10 per collocation interval").
pub const CHECKS_PER_INTERVAL: (usize, usize) = (4, 10);

/// Number of singularities inside each counter's sink circle.
pub const SINK_CHARGES: usize = 6;

/// The sink's charges sit on a circle of this fraction of its radius. Their ring
/// has an aliasing term of about factor⁶/6 of its charge on the sink circle: at
/// one half that was a floor of 2.9e-3 on the max boundary error (measured on the
/// cavity's inverse problems); at one quarter it is about 4e-5.
pub const SINK_CHARGE_FACTOR: f64 = 0.25;

/// Exponential clustering of corner charges, δⱼ = δ_max exp(−σ(√n − √j)), j = 1..n
/// (the tapered spacing of Gopal & Trefethen's lightning solvers, σ = 4 there).
pub const CLUSTER_SIGMA: f64 = 4.0;

/// The innermost corner charge stays at least this fraction of the cluster's
/// depth from the corner: the tapered distances δ₁ = δ_max·exp(−σ(√n − 1))
/// fall below a double's resolution of the corner's coordinates by n ≈ 90
/// (DejaVu Serif "e" at N = 2 000 put a charge exactly on its corner, and the
/// field was NaN there). [`cluster_cap`] is the largest n that keeps δ₁ above
/// this; the charges past it go to the pseudo-boundary.
pub const CLUSTER_FLOOR: f64 = 1e-10;

/// The innermost charge of a refined layout's cluster stays at least this
/// fraction of the cluster's depth from its corner (at most a few mm, so
/// some 1e-11 mm: a thousand times a double's resolution of coordinates of
/// a few hundred mm). Past [`refined_cap`] pairs a cluster fills the range
/// more densely instead of reaching deeper (`floored_distances`). A convex
/// corner needs it: u − 1 ~ r^(π/α) with π/α near 1/2 at an acute material
/// corner, so a field good to 1e-6 must follow it to about 1e-11 of its
/// scale (DejaVu Sans "A" at its feet stopped at 2.5e-6 with 45 pairs down
/// to 1e-10, docs/method.md §3d).
pub const REFINED_FLOOR: f64 = 1e-12;

/// No charge of the material is closer than this fraction of the outer
/// radius to any collocation or check point ([`separate`] moves one that is,
/// and the solve reports it): the kernel is −log 0 there.
pub const MIN_SEPARATION: f64 = 1e-15;

/// Charges of a refined layout closer than this fraction of the outer radius
/// are one ([`Prepared::drop_coincident`] keeps the first).
pub const COINCIDENT: f64 = 1e-9;

/// The generating boundary of a field: contours with the material on their left
/// (outlines counter-clockwise, counters clockwise), u = `value` on each.
#[derive(Clone, Debug)]
pub struct Boundary {
    /// The contours, material on the left.
    pub contours: Vec<Contour>,
    /// For each contour, true when it is a counter (a hole: gets a sink).
    pub is_counter: Vec<bool>,
    /// Centre of the outer circle (u = 0 there).
    pub centre: Vec2,
    /// Radius of the outer circle.
    pub radius: f64,
    /// Flattening tolerance for geometric queries (ray casts, sinks).
    pub flat_tol: f64,
}

impl Boundary {
    /// The contours (`is_counter` flags the holes) inside the outer circle
    /// (`centre`, `radius`), flattened to `flat_tol` for geometric queries.
    pub fn new(
        contours: Vec<Contour>,
        is_counter: Vec<bool>,
        centre: Vec2,
        radius: f64,
        flat_tol: f64,
    ) -> Boundary {
        Boundary {
            contours,
            is_counter,
            centre,
            radius,
            flat_tol,
        }
    }

    /// As [`Boundary::new`] with the outer circle about the material's area
    /// centroid ([`super::centroid`] of the contours flattened to `flat_tol`).
    pub fn about_centroid(
        contours: Vec<Contour>,
        is_counter: Vec<bool>,
        radius: f64,
        flat_tol: f64,
    ) -> Boundary {
        let centre = super::centroid(&contours, flat_tol);
        Boundary::new(contours, is_counter, centre, radius, flat_tol)
    }
}

/// How singularities are laid out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layout {
    /// Total singularities N (outer, sinks, corners and pseudo-boundary).
    pub n_total: usize,
    /// Pseudo-boundary distance d: uniform singularities sit d inside the material
    /// (less where the material is thinner, see `Prepared::inward_charge`).
    pub distance: f64,
    /// Cluster singularities toward convex corners of the material.
    pub corner_clusters: bool,
    /// Fraction of the free singularities (after outer and sinks) given to corner clusters.
    pub corner_fraction: f64,
    /// The accurate layout: corner charges in pairs about the bisector
    /// (`PAIR_ANGLE`), a larger outer ring (`PAIRED_OUTER_CHARGES`) and
    /// `CHECKS_PER_INTERVAL.1` check points per interval.
    pub pairs: bool,
}

impl Layout {
    /// N charges in the default layout: clustered toward convex corners
    /// ([`super::DEFAULT_CORNER_FRACTION`] of them), unpaired, at a placeholder
    /// distance of 1 for [`super::solve_with`] to choose.
    pub fn auto(n_total: usize) -> Layout {
        Layout {
            n_total,
            distance: 1.0,
            corner_clusters: true,
            corner_fraction: super::DEFAULT_CORNER_FRACTION,
            pairs: false,
        }
    }
}

/// A sink inside a counter: u = 0 on the circle (centre, radius).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sink {
    /// Centre.
    pub centre: Vec2,
    /// Radius.
    pub radius: f64,
}

/// Geometry precomputed once per boundary and reused for every layout.
#[derive(Clone, Debug)]
pub struct Prepared {
    /// The boundary.
    pub boundary: Boundary,
    polys: Vec<Vec<Vec2>>,
    index: DistanceIndex,
    lengths: Vec<f64>,
    /// Convex corners of the material.
    corners: Vec<Corner>,
    /// The refined layout's clusters: the convex corners, then the notches
    /// of the void (concave material corners past [`NOTCH_TURN`]).
    refined: Vec<Corner>,
    /// All corners (for check points and charges at corners): (contour, arc
    /// length, tangent in, tangent out).
    all_corners: Vec<(usize, f64, Vec2, Vec2)>,
    /// Sinks, one per counter.
    pub sinks: Vec<Sink>,
    /// Whether the outer circle (u = 0, the paper's ∂Ω_E) is part of the problem:
    /// true for the direct problem, false for the inverse problem of Section 4,
    /// whose only zero boundaries are the sinks inside the shape.
    pub outer: bool,
}

/// A convex corner of the material, where u − 1 ~ r^(π/α) with α > π.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Corner {
    /// Contour index.
    ci: usize,
    /// Arc length of the corner on its contour.
    s: f64,
    /// The corner.
    p: Vec2,
    /// Unit bisector into the material.
    bisector: Vec2,
    /// Largest charge distance from the corner along the bisector.
    depth: f64,
    /// Half the material's wedge angle, (π − turn)/2.
    half_wedge: f64,
}

/// A problem's points by role (the paper's sets of Section 4): the material's
/// singularities with the collocation and check points of u = 1 on its boundary
/// (Q_I and P_I, or R_I and P_I for an inverse problem), the outer circle
/// (Q_E, P_E) and each sink (R_O, P_O), all with u = 0.
#[derive(Clone, Debug, Default)]
pub struct Groups {
    /// Singularities in the material, collocation and check points on its boundary.
    pub material: Problem,
    /// The outer circle, when the problem has one.
    pub outer: Option<Problem>,
    /// The sinks, each with its points.
    pub sinks: Vec<(Sink, Problem)>,
}

impl Groups {
    /// All points in one problem: material, outer circle, sinks (this order).
    pub fn concat(&self) -> Problem {
        let mut pr = self.material.clone();
        for g in self.outer.iter().chain(self.sinks.iter().map(|(_, p)| p)) {
            pr.charges.extend_from_slice(&g.charges);
            pr.colloc.extend_from_slice(&g.colloc);
            pr.checks.extend_from_slice(&g.checks);
        }
        pr
    }
}

/// Distance from `p` along unit direction `dir` to the first crossing of any polygon
/// edge (ignoring crossings closer than `skip`).
fn ray_cast(polys: &[Vec<Vec2>], p: Vec2, dir: Vec2, skip: f64) -> f64 {
    let mut best = f64::INFINITY;
    for poly in polys {
        let n = poly.len();
        for i in 0..n {
            let a = poly[i];
            let b = poly[(i + 1) % n];
            let e = b - a;
            let den = dir.cross(e);
            if den.abs() < 1e-300 {
                continue;
            }
            let ap = a - p;
            let t = ap.cross(e) / den;
            let u = ap.cross(dir) / den;
            if t > skip && (0.0..=1.0).contains(&u) && t < best {
                best = t;
            }
        }
    }
    best
}

impl Prepared {
    /// Precompute flattenings, the distance index, corners and sinks.
    pub fn new(boundary: Boundary) -> Result<Prepared, FieldError> {
        if boundary.contours.is_empty() {
            return Err(FieldError::NoContours);
        }
        let polys: Vec<Vec<Vec2>> = boundary
            .contours
            .iter()
            .map(|c| c.flatten(boundary.flat_tol))
            .collect();
        let index = DistanceIndex::new(&polys);
        let lengths: Vec<f64> = boundary.contours.iter().map(Contour::length).collect();
        let mut corners = Vec::new();
        let mut notches = Vec::new();
        let mut all_corners = Vec::new();
        for (ci, c) in boundary.contours.iter().enumerate() {
            for k in c.corners(CORNER_TURN) {
                all_corners.push((ci, k.s, k.t_in, k.t_out));
                // A cluster on the corner's bisector into the material,
                // half the way across the material along it.
                let cluster = |b: Vec2| Corner {
                    ci,
                    s: k.s,
                    p: k.p,
                    bisector: b,
                    depth: 0.5
                        * ray_cast(&polys, k.p, b, 1e-9 * boundary.radius).min(lengths[ci] / 4.0),
                    half_wedge: 0.5 * (std::f64::consts::PI - k.turn),
                };
                if k.turn < -NOTCH_TURN {
                    // The material's bisector points away from the void's wedge.
                    let b = (k.t_in - k.t_out).normalized();
                    if b.norm2() > 0.5 {
                        notches.push(cluster(b));
                    }
                }
                if k.turn > SINGULAR_TURN {
                    let b = (k.t_out - k.t_in).normalized();
                    let b = if b.norm2() > 0.5 { b } else { k.t_in.perp() };
                    corners.push(cluster(b));
                }
            }
        }
        stop_crossing(&mut corners);
        // The refined layout's clusters: the convex corners, then the notches,
        // kept short of each other's bisectors as one set.
        let mut refined = corners.clone();
        refined.append(&mut notches);
        stop_crossing(&mut refined);
        let mut sinks = Vec::new();
        for (ci, poly) in polys.iter().enumerate() {
            if boundary.is_counter[ci] {
                sinks.push(sink_for(poly, &index)?);
            }
        }
        Ok(Prepared {
            boundary,
            polys,
            index,
            lengths,
            corners,
            refined,
            all_corners,
            sinks,
            outer: true,
        })
    }

    /// As `new`, with the given sinks in place of one per counter (the inverse
    /// problem of a long pocket needs several, see `toolpath::zlevel`).
    pub fn with_sinks(boundary: Boundary, sinks: Vec<Sink>) -> Result<Prepared, FieldError> {
        let mut b = boundary;
        let flags = std::mem::take(&mut b.is_counter);
        b.is_counter = vec![false; flags.len()];
        let mut p = Prepared::new(b)?;
        p.boundary.is_counter = flags;
        p.sinks = sinks;
        Ok(p)
    }

    /// Total length of the glyph contours.
    pub fn perimeter(&self) -> f64 {
        self.lengths.iter().sum()
    }

    /// Number of convex material corners (each gets a cluster when enabled).
    pub fn singular_corners(&self) -> usize {
        self.corners.len()
    }

    /// The flattened contours.
    pub fn polygons(&self) -> &[Vec<Vec2>] {
        &self.polys
    }

    /// Point `d` inside the material from sample `s` on contour `ci`, pulled back
    /// where the material is thin so the charge stays at most 45 % of the way
    /// across it and at least half its depth away from every other boundary part.
    fn inward_charge(&self, s: &Sample, d: f64, pairs: bool) -> Vec2 {
        let n = s.t.perp();
        // The sample is on the curve, the polygons within flat_tol of it: a
        // crossing closer than that is the sample's own chord, not the far side
        // (the plain layout keeps its old skip, which the golden samples use).
        let skip = if pairs {
            (4.0 * self.boundary.flat_tol).max(1e-9 * self.boundary.radius)
        } else {
            1e-9 * self.boundary.radius
        };
        let across = ray_cast(&self.polys, s.p, n, skip);
        let mut depth = d.min(0.45 * across);
        for _ in 0..12 {
            let q = s.p + n * depth;
            if self.index.distance(q) >= 0.5 * depth {
                return q;
            }
            depth *= 0.7;
        }
        s.p + n * depth
    }

    /// True when `p` lies in the material (inside an outline, outside its counters).
    pub fn in_material(&self, p: Vec2) -> bool {
        self.polys
            .iter()
            .map(|poly| polygon_winding_number(poly, p))
            .sum::<i32>()
            > 0
    }

    /// Build the discrete problem for a layout: M = 2N collocation points.
    pub fn problem(&self, layout: &Layout) -> Result<Problem, FieldError> {
        let pr = self.groups(layout)?.concat();
        debug_assert_eq!(pr.charges.len(), layout.n_total);
        debug_assert_eq!(pr.colloc.len(), 2 * layout.n_total);
        Ok(pr)
    }

    /// The problem for a layout, its points kept apart by role.
    pub fn groups(&self, layout: &Layout) -> Result<Groups, FieldError> {
        let n = self.counts(layout)?;
        let mut pr = Problem::default();
        let shares = self.shares(n.pb);
        let distances = vec![layout.distance; shares.len()];
        let mut colloc_s = self.contour_charges(&mut pr, &shares, &distances, layout.pairs);
        self.corner_clusters(&mut pr, &mut colloc_s, n.pairs, n.single);
        self.check_points(&mut pr, &colloc_s, n.checks);
        pr.moved = self.separate(&mut pr);
        // Circles: outer (u = 0) and sinks (u = 0).
        let (outer, sinks) = self.circles(n.outer, n.sink_charges, n.checks);
        Ok(Groups {
            material: pr,
            outer,
            sinks,
        })
    }

    /// The problem of a refined layout ([`super::refine`]), its points kept
    /// apart by role: `r.contour[ci]` uniform charges on contour ci at
    /// [`super::adaptive::DISTANCE_PER_SPACING`] times their own spacing,
    /// `r.pairs[k]` pairs at the k-th of [`Prepared::refined_corners`], the
    /// paired layout's outer ring (when the problem has one) and sinks.
    /// Also returns the contour of each of the material's check points.
    pub(crate) fn groups_refined(&self, r: &super::refine::Refinement) -> (Groups, Vec<usize>) {
        let mut pr = Problem::default();
        let distances: Vec<f64> = self
            .lengths
            .iter()
            .zip(&r.contour)
            .map(|(l, &n)| super::adaptive::DISTANCE_PER_SPACING * l / n.max(1) as f64)
            .collect();
        let mut colloc_s = self.contour_charges(&mut pr, &r.contour, &distances, true);
        for (k, &n) in self.refined.iter().zip(&r.pairs) {
            let deltas = floored_distances(k.depth, n, REFINED_FLOOR);
            self.cluster(k, &deltas, &mut pr, &mut colloc_s, true);
        }
        let checks = CHECKS_PER_INTERVAL.1;
        self.check_points(&mut pr, &colloc_s, checks);
        // check_points' order: each contour's intervals, then every corner.
        let owner: Vec<usize> = colloc_s
            .iter()
            .enumerate()
            .flat_map(|(ci, ss)| std::iter::repeat_n(ci, ss.len() * checks))
            .chain(self.all_corners.iter().map(|k| k.0))
            .collect();
        debug_assert_eq!(owner.len(), pr.checks.len());
        pr.moved = self.separate(&mut pr);
        self.drop_coincident(&mut pr);
        let (outer, sinks) = self.circles(r.outer, r.sink, checks);
        (
            Groups {
                material: pr,
                outer,
                sinks,
            },
            owner,
        )
    }

    /// The outer circle (when the problem has one and `outer` > 0 charges)
    /// and every sink (`sink` charges each), `checks` check points between
    /// neighbouring collocation points.
    #[allow(clippy::type_complexity)]
    fn circles(
        &self,
        outer: usize,
        sink: usize,
        checks: usize,
    ) -> (Option<Problem>, Vec<(Sink, Problem)>) {
        let b = &self.boundary;
        let ring = (self.outer && outer > 0).then(|| {
            circle(
                b.centre,
                b.radius,
                b.radius * OUTER_CHARGE_FACTOR,
                outer,
                checks,
            )
        });
        let sinks = self
            .sinks
            .iter()
            .map(|s| {
                let g = circle(
                    s.centre,
                    s.radius,
                    s.radius * SINK_CHARGE_FACTOR,
                    sink,
                    checks,
                );
                (*s, g)
            })
            .collect();
        (ring, sinks)
    }

    /// The refined layout's clusters: (contour, corner point), the convex
    /// corners first, then the notches.
    pub(crate) fn refined_corners(&self) -> impl Iterator<Item = (usize, Vec2)> + '_ {
        self.refined.iter().map(|k| (k.ci, k.p))
    }

    /// The glyph contours' lengths.
    pub(crate) fn lengths(&self) -> &[f64] {
        &self.lengths
    }

    /// How `layout.n_total` singularities are shared out: the outer circle's
    /// and each sink's (fixed), the corner clusters' (`corner_fraction` of the
    /// rest, per corner in pairs about the bisector once there are enough for
    /// pairs to pay, else on the bisector), and the uniform ones on the
    /// contours (the rest); an error when too few are left for four per
    /// contour.
    fn counts(&self, layout: &Layout) -> Result<Counts, FieldError> {
        let sink_charges = if layout.pairs {
            PAIRED_SINK_CHARGES
        } else {
            SINK_CHARGES
        };
        let n_sinks = self.sinks.len() * sink_charges;
        let outer = match (self.outer, layout.pairs) {
            (false, _) => 0,
            (true, false) => OUTER_CHARGES,
            (true, true) => {
                (layout.n_total / 32).clamp(PAIRED_OUTER_CHARGES.0, PAIRED_OUTER_CHARGES.1)
            }
        };
        let checks = if layout.pairs {
            CHECKS_PER_INTERVAL.1
        } else {
            CHECKS_PER_INTERVAL.0
        };
        let fixed = outer + n_sinks;
        let contours = self.boundary.contours.len();
        if layout.n_total < fixed + 4 * contours {
            return Err(FieldError::TooFewSingularities {
                n: layout.n_total,
                needed: fixed + 4 * contours,
            });
        }
        let free = layout.n_total - fixed;
        let n_corner_each = if layout.corner_clusters && !self.corners.is_empty() {
            ((layout.corner_fraction * free as f64) / self.corners.len() as f64).floor() as usize
        } else {
            0
        };
        let (pairs, single) = if layout.pairs && n_corner_each >= PAIR_MIN {
            ((n_corner_each / 2).min(cluster_cap()), 0)
        } else {
            (0, n_corner_each.min(cluster_cap()))
        };
        let n_corner_total = (2 * pairs + single) * self.corners.len();
        Ok(Counts {
            sink_charges,
            outer,
            checks,
            pairs,
            single,
            pb: free - n_corner_total,
        })
    }

    /// `n_pb` uniform charges shared out among the contours by length (at
    /// least two each), the remainder handed to the longest so Σ = n_pb.
    fn shares(&self, n_pb: usize) -> Vec<usize> {
        let total_len = self.perimeter();
        let mut shares: Vec<usize> = self
            .lengths
            .iter()
            .map(|l| ((l / total_len) * n_pb as f64).floor().max(2.0) as usize)
            .collect();
        let mut assigned: usize = shares.iter().sum();
        let mut order: Vec<usize> = (0..shares.len()).collect();
        order.sort_by(|&i, &j| self.lengths[j].total_cmp(&self.lengths[i]));
        let mut k = 0;
        while assigned < n_pb {
            shares[order[k % order.len()]] += 1;
            assigned += 1;
            k += 1;
        }
        while assigned > n_pb {
            let i = order[k % order.len()];
            if shares[i] > 2 {
                shares[i] -= 1;
                assigned -= 1;
            }
            k += 1;
        }
        shares
    }

    /// Uniform charges and collocation on every contour (`shares[ci]` charges
    /// at `distances[ci]` inside the material, twice as many collocation
    /// points between them); returns each contour's collocation arc lengths.
    fn contour_charges(
        &self,
        pr: &mut Problem,
        shares: &[usize],
        distances: &[f64],
        pairs: bool,
    ) -> Vec<Vec<f64>> {
        let b = &self.boundary;
        let mut colloc_s: Vec<Vec<f64>> = vec![Vec::new(); b.contours.len()];
        for (ci, c) in b.contours.iter().enumerate() {
            let nc = shares[ci];
            let h = self.lengths[ci] / nc as f64;
            let l = self.lengths[ci];
            for mut s in c.sample_uniform(nc, 0.0) {
                // A sample on a corner: the one-sided normal runs along the other
                // edge and would put the charge on the boundary; take the bisector.
                let at_corner = self.all_corners.iter().find(|k| {
                    let gap = (k.1 - s.s).abs();
                    k.0 == ci && gap.min(l - gap) < 1e-9 * l
                });
                if let Some(&(_, _, t_in, t_out)) = at_corner {
                    let n = (t_in.perp() + t_out.perp()).normalized();
                    if n.norm2() > 0.5 {
                        s.t = Vec2::new(n.y, -n.x);
                    }
                }
                pr.charges
                    .push(self.inward_charge(&s, distances[ci], pairs));
            }
            let cum = c.cumulative_lengths();
            for j in 0..2 * nc {
                let s = (j as f64 + 0.5) * h / 2.0;
                pr.colloc.push(Condition {
                    p: c.sample_at(&cum, s).p,
                    value: 1.0,
                });
                colloc_s[ci].push(s);
            }
        }
        colloc_s
    }

    /// Corner clusters at tapered distances: on the bisector, two collocation
    /// points per charge, one each side of the corner at the charge's
    /// distance; or in pairs about the bisector, four collocation points per
    /// pair, two each side, at the pair's distance and halfway (geometrically)
    /// to the next pair out.
    fn corner_clusters(
        &self,
        pr: &mut Problem,
        colloc_s: &mut [Vec<f64>],
        n_pairs: usize,
        n_single: usize,
    ) {
        if n_pairs + n_single == 0 {
            return;
        }
        for k in &self.corners {
            let deltas = cluster_distances(k.depth, n_pairs.max(n_single));
            self.cluster(k, &deltas, pr, colloc_s, n_pairs > 0);
        }
    }

    /// One corner's cluster at the distances `deltas` (see
    /// [`Prepared::corner_clusters`]), in pairs or on the bisector.
    fn cluster(
        &self,
        k: &Corner,
        deltas: &[f64],
        pr: &mut Problem,
        colloc_s: &mut [Vec<f64>],
        pairs: bool,
    ) {
        let c = &self.boundary.contours[k.ci];
        let cum = c.cumulative_lengths();
        let angle = PAIR_ANGLE.min(0.5 * k.half_wedge);
        for (j, &delta) in deltas.iter().enumerate() {
            let outer = deltas.get(j + 1).copied().unwrap_or(2.0 * delta);
            let pair = [delta, (delta * outer).sqrt()];
            let alongs: &[f64] = if pairs {
                for side in [-1.0, 1.0] {
                    pr.charges
                        .push(k.p + rotate(k.bisector, side * angle) * delta);
                }
                &pair
            } else {
                pr.charges.push(k.p + k.bisector * delta);
                &pair[..1]
            };
            for &along in alongs {
                for side in [-1.0, 1.0] {
                    let s = (k.s + side * along).rem_euclid(self.lengths[k.ci]);
                    pr.colloc.push(Condition {
                        p: c.sample_at(&cum, s).p,
                        value: 1.0,
                    });
                    colloc_s[k.ci].push(s);
                }
            }
        }
    }

    /// Check points: `checks` between every pair of neighbouring collocation
    /// points on each contour, plus every corner.
    fn check_points(&self, pr: &mut Problem, colloc_s: &[Vec<f64>], checks: usize) {
        let b = &self.boundary;
        for (ci, c) in b.contours.iter().enumerate() {
            let cum = c.cumulative_lengths();
            let mut ss = colloc_s[ci].clone();
            ss.sort_by(f64::total_cmp);
            let l = self.lengths[ci];
            for w in 0..ss.len() {
                let a = ss[w];
                let bnext = if w + 1 < ss.len() {
                    ss[w + 1]
                } else {
                    ss[0] + l
                };
                for q in 1..=checks {
                    let s = a + (bnext - a) * q as f64 / (checks + 1) as f64;
                    pr.checks.push(Condition {
                        p: c.sample_at(&cum, s).p,
                        value: 1.0,
                    });
                }
            }
        }
        for &(ci, s, _, _) in &self.all_corners {
            let c = &b.contours[ci];
            let cum = c.cumulative_lengths();
            pr.checks.push(Condition {
                p: c.sample_at(&cum, s).p,
                value: 1.0,
            });
        }
    }
}

impl Prepared {
    /// Move every charge closer than [`MIN_SEPARATION`] × R to a collocation
    /// or check point away from it, into the material (a backstop: the
    /// layout keeps them apart by construction, [`cluster_cap`]); returns how
    /// many were moved.
    fn separate(&self, pr: &mut Problem) -> usize {
        let tau = MIN_SEPARATION * self.boundary.radius;
        let points = PointSweep::new(pr.colloc.iter().chain(&pr.checks).map(|c| c.p));
        let mut moved = 0;
        for q in &mut pr.charges {
            let Some(p) = points.within(*q, tau) else {
                continue;
            };
            let away = (*q - p).normalized();
            let dirs = std::iter::once(away).chain((0..16).map(|k| {
                let a = TAU * k as f64 / 16.0;
                Vec2::new(a.cos(), a.sin())
            }));
            for d in dirs.filter(|d| d.norm2() > 0.5) {
                let cand = p + d * (4.0 * tau);
                if self.in_material(cand) && points.within(cand, tau).is_none() {
                    *q = cand;
                    moved += 1;
                    break;
                }
            }
        }
        moved
    }
}

impl Prepared {
    /// Drop every charge within [`COINCIDENT`] × R of an earlier one: its
    /// column would repeat the other's, and R of the QR would have a zero on
    /// its diagonal (DejaVu Serif "E" at 50 mm: two uniform charges pulled
    /// back onto the same point where the material is thin).
    fn drop_coincident(&self, pr: &mut Problem) {
        let tau = COINCIDENT * self.boundary.radius;
        let mut kept: Vec<Vec2> = Vec::with_capacity(pr.charges.len());
        let mut sweep = std::collections::BTreeMap::<i64, Vec<Vec2>>::new();
        let cell = |p: Vec2| (p.x / tau).floor() as i64;
        for &q in &pr.charges {
            let c = cell(q);
            let near = (c - 1..=c + 1)
                .filter_map(|k| sweep.get(&k))
                .flatten()
                .any(|p| p.dist(q) <= tau);
            if !near {
                kept.push(q);
                sweep.entry(c).or_default().push(q);
            }
        }
        pr.charges = kept;
    }
}

/// The least distance from a charge of `pr` to any of its collocation or
/// check points, looked for within `reach` (infinity when none is closer).
pub fn min_separation(pr: &Problem, reach: f64) -> f64 {
    PointSweep::new(pr.colloc.iter().chain(&pr.checks).map(|c| c.p))
        .min_distance(&pr.charges, reach)
}

/// Points sorted by x, for "is any within r of q" with r small.
pub(crate) struct PointSweep {
    pts: Vec<Vec2>,
}

impl PointSweep {
    /// Index the points (non-finite ones are left out).
    pub(crate) fn new(points: impl Iterator<Item = Vec2>) -> PointSweep {
        let mut pts: Vec<Vec2> = points
            .filter(|p| p.x.is_finite() && p.y.is_finite())
            .collect();
        pts.sort_by(|a, b| a.x.total_cmp(&b.x));
        PointSweep { pts }
    }

    /// The nearest indexed point within `r` of `q`, if any.
    pub(crate) fn within(&self, q: Vec2, r: f64) -> Option<Vec2> {
        let start = self.pts.partition_point(|p| p.x < q.x - r);
        self.pts[start..]
            .iter()
            .take_while(|p| p.x <= q.x + r)
            .filter(|p| p.dist(q) <= r)
            .min_by(|a, b| a.dist(q).total_cmp(&b.dist(q)))
            .copied()
    }

    /// The least distance from any of `qs` to an indexed point, looked for
    /// within `r` (infinity when none is that close).
    pub(crate) fn min_distance(&self, qs: &[Vec2], r: f64) -> f64 {
        qs.iter()
            .filter_map(|&q| self.within(q, r).map(|p| p.dist(q)))
            .fold(f64::INFINITY, f64::min)
    }
}

/// How a layout's singularities are shared out (see `Prepared::counts`).
struct Counts {
    /// Charges per sink.
    sink_charges: usize,
    /// Charges on the outer circle.
    outer: usize,
    /// Check points between neighbouring collocation points.
    checks: usize,
    /// Pairs per corner.
    pairs: usize,
    /// Single charges per corner (when not in pairs).
    single: usize,
    /// Uniform charges on the contours.
    pb: usize,
}

/// A circle where u = 0 (the outer circle or a sink) of `radius` about
/// `centre`: `n` charges on the concentric circle of `charge_radius`, 2n
/// collocation points on it, `checks` check points between neighbours.
pub(crate) fn circle(
    centre: Vec2,
    radius: f64,
    charge_radius: f64,
    n: usize,
    checks: usize,
) -> Problem {
    let mut pr = Problem::default();
    for j in 0..n {
        let a = TAU * (j as f64 + 0.25) / n as f64;
        pr.charges
            .push(centre + Vec2::new(a.cos(), a.sin()) * charge_radius);
    }
    for j in 0..2 * n {
        let a = TAU * j as f64 / (2 * n) as f64;
        pr.colloc.push(Condition {
            p: centre + Vec2::new(a.cos(), a.sin()) * radius,
            value: 0.0,
        });
        for q in 1..=checks {
            let a = TAU * (j as f64 + q as f64 / (checks + 1) as f64) / (2 * n) as f64;
            pr.checks.push(Condition {
                p: centre + Vec2::new(a.cos(), a.sin()) * radius,
                value: 0.0,
            });
        }
    }
    pr
}

/// Two clusters whose bisectors cross within both their depths (the two ends
/// of a thin bar: a rectangle's corners meet on its mid-line) would share a
/// charge and make the system singular: stop both short of it.
fn stop_crossing(corners: &mut [Corner]) {
    for i in 0..corners.len() {
        for j in 0..i {
            let (pi, bi) = (corners[i].p, corners[i].bisector);
            let (pj, bj) = (corners[j].p, corners[j].bisector);
            let den = bi.cross(bj);
            if den.abs() < 1e-12 {
                continue;
            }
            let ti = (pj - pi).cross(bj) / den;
            let tj = (pj - pi).cross(bi) / den;
            if ti > 0.0 && tj > 0.0 && ti <= corners[i].depth && tj <= corners[j].depth {
                corners[i].depth = corners[i].depth.min(0.8 * ti);
                corners[j].depth = corners[j].depth.min(0.8 * tj);
            }
        }
    }
}

/// Tapered exponential distances δⱼ = δ_max·exp(−σ(√n − √j)), j = 1..n, from
/// the corner out (Gopal and Trefethen's spacing).
fn cluster_distances(depth: f64, n: usize) -> Vec<f64> {
    tapered(depth, n, CLUSTER_SIGMA)
}

/// δⱼ = `depth`·exp(−σ(√n − √j)), j = 1..n.
fn tapered(depth: f64, n: usize, sigma: f64) -> Vec<f64> {
    let nn = (n as f64).sqrt();
    (1..=n)
        .map(|j| depth * (-sigma * (nn - (j as f64).sqrt())).exp())
        .collect()
}

/// The pairs of a refined cluster whose innermost charge first reaches
/// [`REFINED_FLOOR`] at σ = [`CLUSTER_SIGMA`] (62).
pub fn refined_cap() -> usize {
    let root = 1.0 + (1.0 / REFINED_FLOOR).ln() / CLUSTER_SIGMA;
    (root * root).floor() as usize
}

/// As [`cluster_distances`], with σ lowered where need be so that the
/// innermost distance is at least `floor` of the depth: more charges then
/// fill the same range more densely instead of reaching deeper.
fn floored_distances(depth: f64, n: usize, floor: f64) -> Vec<f64> {
    let nn = (n as f64).sqrt();
    let sigma = if nn > 1.0 {
        CLUSTER_SIGMA.min((1.0 / floor).ln() / (nn - 1.0))
    } else {
        CLUSTER_SIGMA
    };
    tapered(depth, n, sigma)
}

/// The most tapered distances a corner cluster takes: the largest n with
/// exp(−σ(√n − 1)) ≥ [`CLUSTER_FLOOR`] (45 at σ = 4, 1e-10).
pub fn cluster_cap() -> usize {
    let root = 1.0 + (1.0 / CLUSTER_FLOOR).ln() / CLUSTER_SIGMA;
    (root * root).floor() as usize
}

/// `v` turned counter-clockwise by `angle` radians.
fn rotate(v: Vec2, angle: f64) -> Vec2 {
    let (s, c) = angle.sin_cos();
    Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

/// A sink for a counter: centred at the point of the counter farthest from its
/// boundary (`geometry::deepest_point`), radius a quarter of that distance.
fn sink_for(poly: &[Vec2], index: &DistanceIndex) -> Result<Sink, FieldError> {
    let (centre, room) = crate::geometry::deepest_point(poly, index);
    if room <= 0.0 {
        return Err(FieldError::EmptyCounter);
    }
    Ok(Sink {
        centre,
        radius: 0.25 * room,
    })
}
