//! Drop-cutter: the lowest tool-tip z at which a flat, ball or bull-nose end
//! mill, its axis vertical through (x, y), touches a triangle mesh without any
//! triangle entering it. The finisher of the modelled surface S2
//! ([`crate::surface`]) drops the tool along its passes with this.
//!
//! # The tool and the problem
//!
//! A [`Cutter`] has radius r and corner radius rc (flat 0, ball r, bull
//! 0 < rc < r); write a = r − rc for the radius of its flat bottom. Its lower
//! surface, at horizontal distance ρ from the axis and with the tip at z = t, is
//! t + p(ρ) where
//!
//! ```text
//! p(ρ) = 0                                 for 0 ≤ ρ ≤ a,
//! p(ρ) = rc − sqrt(rc² − (ρ − a)²)          for a < ρ ≤ r,
//! ```
//!
//! and above p(r) = rc the tool is a vertical cylinder of radius r (the shank is
//! taken as infinitely long). The solid tool is {(q, z) : |q − c| ≤ r,
//! z ≥ t + p(|q − c|)}, c the axis. A part point P = (q, z) with ρ = |q − c| ≤ r
//! is outside the tool's interior iff z ≤ t + p(ρ), i.e. t ≥ z − p(ρ); points with
//! ρ > r never meet the tool. So the drop against a point set S is
//!
//! ```text
//! t*(S) = max { f(P) : P ∈ S, ρ(P) ≤ r },   f(P) = z(P) − p(ρ(P)),
//! ```
//!
//! and against a mesh it is the max over its triangles. Every number returned
//! here is f at a point of a triangle inside the footprint (up to rounding), so
//! it never lies above the true drop; the three tests below together reach the
//! maximum, so it never lies below it (by more than the stated tolerances).
//!
//! # Why vertices, edges and the facet suffice
//!
//! p is convex and non-decreasing on [0, r] (p = 0 up to a, then p′ = s/√(rc² − s²)
//! ≥ 0, p″ = rc²/(rc² − s²)^{3/2} > 0 with s = ρ − a, and p′(a⁺) = 0), and
//! q ↦ |q − c| is convex, so q ↦ p(|q − c|) is convex (a convex non-decreasing
//! function of a convex function). On a triangle T, z is affine in q, so f is
//! **concave** on the XY projection of T ∩ disc. Its maximum over the compact
//! convex set T ∩ D (D the footprint disc) lies
//!
//! * in the relative interior of T: then it is the maximum of f over the whole
//!   plane of T within D (concavity), found by the **facet test**;
//! * on an edge of T (relative interior or end): the **edge test** maximises f
//!   along the edge clipped to D; the ends of the edge are its vertices, the
//!   **vertex test**.
//!
//! A maximum in the interior of T on the footprint's rim ρ = r needs no test of
//! its own: for rc > 0, p′(ρ) → ∞ as ρ → r, so moving inwards raises f and the
//! rim is never a maximum unless T is vertical, and then T's interior points lie
//! below points of its edges on the same vertical; for rc = 0, f = z is affine
//! and its maximum over D is the facet test's rim point.
//!
//! # The three tests (derivations)
//!
//! Coordinates are taken relative to the axis (c = 0) for the whole test, so a
//! translation of mesh and axis together changes nothing but rounding.
//!
//! **Vertex** V with ρ = |V_xy| ≤ r: t = V_z − p(ρ).
//!
//! **Facet.** Let n = (n_x, n_y, n_z) be T's unit normal with n_z > 0 and
//! n_xy = |(n_x, n_y)| = sin θ, n_z = cos θ, θ the tilt. In XY the plane is
//! z = z₀ + g·q with g = −(n_x, n_y)/n_z, |g| = tan θ. A critical point of the
//! concave f = z₀ + g·q − p(|q|) has g = p′(ρ) q/ρ: q points along
//! u = −(n_x, n_y)/n_xy (uphill) and p′(ρ) = tan θ, i.e. with s = ρ − a,
//! s/√(rc² − s²) = tan θ, s = rc sin θ. So the contact is at
//!
//! ```text
//! ρ_c = a + rc·n_xy,   q_c = ρ_c·u,   p(ρ_c) = rc − rc·cos θ = rc·(1 − n_z),
//! ```
//!
//! which is also the point of the tool's surface whose normal is parallel to n.
//! (Flat: ρ_c = r, the rim point uphill, the maximum of an affine function over
//! the disc. Horizontal facet, n_xy = 0: any point of the flat bottom; q_c = 0.)
//! The contact's height Z on the plane n·X = n·V₀ is
//! Z = (n·V₀ − n_x q_x − n_y q_y)/n_z and the tip is t = Z − rc·(1 − n_z).
//! For a ball (a = 0, rc = r) on a plane tilted by θ whose height under the axis
//! is z_c this gives t = z_c + ρ_c tan θ − r(1 − cos θ) = z_c + r(1/cos θ − 1).
//! The contact counts only if X = (q_c, Z) lies in T, tested in 3-D with the
//! signs of n·((V_{i+1} − V_i) × (X − V_i)), so the test does not degrade on
//! steep facets whose XY projection is a sliver.
//!
//! **Edge** A→B, d = B − A, L = |d_xy| > 0 (a vertical edge's best point is its
//! top vertex), ê = d_xy/L. The XY line lies at distance δ = |A_xy × ê| from the
//! axis; σ = q·ê measures along it from the foot of the perpendicular, so
//! ρ(σ) = √(δ² + σ²), and the edge is σ ∈ [σ_A, σ_A + L], σ_A = A_xy·ê. Inside
//! the footprint |σ| ≤ H = √(r² − δ²) (no contact if δ > r). Along the edge
//! z(σ) = A_z + m(σ − σ_A), m = d_z/L, and h(σ) = z(σ) − p(ρ(σ)) is concave
//! (as above) on the clipped interval [lo, hi] = [max(−H, σ_A), min(H, σ_A + L)].
//!
//! * Flat: h = z is affine; its maximum is at lo or hi, whichever is higher.
//! * Ball: in the vertical plane of the edge the sphere's section is a circle of
//!   radius H about the foot, h(σ) = z(σ) − r + √(H² − σ²); h′ = 0 at
//!   σ* = H·m/√(1 + m²) = H·d_z/|d|, where √(H² − σ*²) = H·L/|d|, so
//!   t = z(σ*) + H·L/|d| − r. If σ* is outside [lo, hi], concavity puts the
//!   maximum at the nearer end.
//! * Bull nose: the torus–line contact is a quartic with no simple closed form.
//!   h′(σ) = m − p′(ρ)·σ/ρ is non-increasing (concavity), so the maximum is found
//!   by bisection on the sign of h′ over [lo, hi]. For a bracket [l, u] with
//!   h′(l) ≥ 0 ≥ h′(u), concavity gives max h ≤ h(l) + h′(l)(u − l) and
//!   max h ≤ h(u) − h′(u)(u − l), so the error of max(h(l), h(u)) is at most
//!   min(h′(l), −h′(u))·(u − l); bisection stops when that is ≤ [`EDGE_TOL`]
//!   (1e-10 mm) or after [`EDGE_MAX_ITER`] steps. Near the optimum the bound
//!   shrinks as h″·(u − l)², so ~35–45 steps are typical.
//!
//! # Numerics
//!
//! * Facets with n_z < [`NZ_MIN`] (1e-12) skip the facet test: there the
//!   contact's height is 1/n_z times as sensitive as the axis position, an
//!   ill-conditioned question. Such a triangle's XY projection is a strip
//!   narrower than diam(T)·n_z/n_xy < diam(T)·1e-12, so it is dropped on as
//!   the vertical triangle it is within that distance of (whose drop the edge
//!   and vertex tests give exactly: on a vertical triangle the highest point
//!   above any XY point is on its boundary).
//! * Slivers with |N| ≤ [`SLIVER`]·ℓ² (N the cross product of the two shorter
//!   edges, ℓ the longest edge) skip the facet test: their normal's direction
//!   is only known to ~1e-16/[`SLIVER`] rad, and every point of them lies within
//!   |N|/ℓ ≤ 1e-8·ℓ of the longest edge, so they are dropped on as the segment
//!   they nearly are.
//!
//! # Against a mesh
//!
//! [`MeshIndex`] buckets triangles on a uniform XY grid by their bounding
//! boxes; a drop visits each triangle whose box meets the footprint's square
//! once (see `for_each_near`), and keeps those whose box lies within r of the
//! axis and whose z_max − p(distance to their box) beats the best tip so far.
//! Each cell keeps the box round its triangles' boxes and their highest
//! corner, so a whole cell is skipped on the same bound, and an upper plane
//! over its triangles' corners, so a cell is also skipped when that plane's
//! own facet contact (the most any point under the plane can lift the
//! cutter) does not beat the best tip; its triangles are
//! sorted by highest corner, so the scan of a cell stops at the first one
//! that cannot win even at the cell's distance. The cells are visited ring
//! by ring from the axis's cell outwards, the nearest first.
//!
//! A first pass computes each kept triangle's facet contact: the maximum of
//! f over its whole plane (concavity), so a plane whose contact does not beat
//! the best tip ends the triangle; it runs the vertex tests (a vertex not
//! above the best tip cannot beat it, p ≥ 0); and a facet contact inside the
//! triangle is the triangle's answer. The triangles left (contact outside)
//! get their edge tests in a second pass, highest plane first, each skipped
//! when its box bound or its plane no longer beats the best tip, each edge
//! on its own bound. Near the axis the first pass usually finds the facet
//! contact that is the answer, so the second pass tests few edges.
//!
//! The bounds only skip what cannot win, and the visiting order only
//! changes which bounds are met, so the result is the max over all
//! triangles, to rounding (a shared edge tested from its two triangles may
//! differ by an ulp; `dropcutter_pruned_drop_equals_the_brute_force_drop_
//! over_all_triangles` checks it against every triangle with no bound).
//!
//! A search may start from a level instead of −∞ ([`Cutter::drop_above`]):
//! everything that cannot lift the cutter above it is skipped from the start,
//! and what can is tested as before, so the answer, when above the level, is
//! the same to the last bit. The finisher starts its tip drops a little under
//! the height the contact geometry predicts ([`Cutter::drop_hinted`], which
//! searches again from −∞ when nothing lies above) and its chord tests at the
//! height that matters to them.

use rayon::prelude::*;

/// How far under the floor a cell's upper-plane bound must fall before the
/// cell is skipped, mm (the bound's rounding, with coordinates of metres, is
/// under 1e-9 mm).
pub(crate) const CELL_PLANE_MARGIN: f64 = 1e-6;

/// Most grid cells a [`MeshIndex`] builds; a finer requested cell is coarsened
/// (doubled) until the grid fits. 4 million cells is 32 MB of offsets, and the
/// finisher's cells (about the tool radius) over any stock a GRBL machine can
/// hold stay far below it.
pub(crate) const MAX_CELLS: usize = 4_000_000;

/// Cells per side of a block ([`MeshIndex`]'s second, coarser level).
pub(crate) const BLOCK: usize = 4;

/// Most blocks a drop judges before its cells (a footprint of up to about
/// 7 × 7 blocks; a wider one goes cell by cell).
const BLOCKS_NEAR: usize = 64;

/// Bucket entries allowed per triangle on average (plus [`MAX_CELLS`]) before
/// the cell is coarsened: a cell much smaller than the triangles would store
/// each triangle many times and gain nothing.
pub(crate) const MAX_ENTRIES_PER_TRIANGLE: usize = 16;

/// Most triangles a [`MeshIndex`] holds (2³⁰: an index and a 2-bit rank share
/// a u32 per bucket entry; a billion triangles would need over 130 GB:
/// 72 bytes of corners, 24 of normal, 20 of box and the entries).
pub(crate) const MAX_TRIANGLES: usize = 1 << 30;

/// Bull-nose edge test: the bisection stops once the error of the value it
/// returns is proven ≤ this, mm (well below the 1e-7 mm the finisher needs, and
/// above what rounding lets a bracket of width ~1e-15·r prove).
pub(crate) const EDGE_TOL: f64 = 1e-10;

/// Bull-nose edge test: most bisection steps. The bracket starts ≤ 2r wide and
/// halves each step; 100 steps take it below 2r·1e-30, past double precision,
/// so the cap only guards against a NaN or an unforeseen stall.
pub(crate) const EDGE_MAX_ITER: u32 = 100;

/// Facets with n_z at least this may be skipped on their plane's bound (see
/// `triangle_edges_facet`): there the facet contact's rounding is below
/// 1e-16·(coordinates)/n_z, far below [`PLANE_BOUND_MARGIN`].
pub(crate) const PLANE_BOUND_NZ: f64 = 1e-3;

/// The plane bound must fall this far below the best tip (mm) before a
/// triangle is skipped on it.
pub(crate) const PLANE_BOUND_MARGIN: f64 = 1e-9;

/// Facets whose unit normal has n_z below this are treated as vertical (no
/// facet test, see the module notes).
pub(crate) const NZ_MIN: f64 = 1e-12;

/// Relative area below which a triangle is a sliver and gets no facet test:
/// |N| ≤ SLIVER·ℓ². 1e-8 = √(machine ε) balances the two errors (normal
/// direction ~ε/SLIVER, distance to the longest edge ≤ SLIVER·ℓ).
pub(crate) const SLIVER: f64 = 1e-8;

/// A cutter: radius r and corner radius rc (flat 0, ball r, bull 0 < rc < r),
/// mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cutter {
    /// Radius r, mm (half the diameter).
    pub radius: f64,
    /// Corner radius rc, mm: 0 for a flat end mill, r for a ball, in between for
    /// a bull nose.
    pub(crate) corner: f64,
}

/// A cutter that cannot be used.
#[derive(Debug, thiserror::Error, Clone, Copy, PartialEq)]
pub(crate) enum CutterError {
    /// The radius is not finite and positive.
    #[error("cutter radius {0} mm must be finite and > 0")]
    Radius(f64),
    /// The corner radius is outside [0, radius].
    #[error("cutter corner radius {corner} mm must lie in [0, {radius}] (the radius)")]
    Corner {
        /// corner radius, mm
        corner: f64,
        /// radius, mm
        radius: f64,
    },
}

/// One contact: the tip height and the part point that sets it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Contact {
    /// Tool-tip z, mm.
    pub(crate) tip: f64,
    /// The touching point, mm (absolute from [`Cutter::drop_contact`]; relative
    /// to the axis in XY inside the tests of one triangle).
    pub(crate) point: [f64; 3],
}

impl Contact {
    #[cfg(test)]
    fn better(a: Option<Contact>, b: Option<Contact>) -> Option<Contact> {
        match (a, b) {
            (Some(x), Some(y)) => Some(if y.tip > x.tip { y } else { x }),
            (x, None) => x,
            (None, y) => y,
        }
    }
}

impl Cutter {
    /// A flat end mill of radius `r`.
    #[cfg(test)]
    pub(crate) fn flat(r: f64) -> Cutter {
        Cutter {
            radius: r,
            corner: 0.0,
        }
    }

    /// A ball end mill of radius `r`.
    pub fn ball(r: f64) -> Cutter {
        Cutter {
            radius: r,
            corner: r,
        }
    }

    /// A bull-nose end mill of radius `r` and corner radius `rc`.
    #[cfg(test)]
    pub(crate) fn bull(r: f64, rc: f64) -> Cutter {
        Cutter {
            radius: r,
            corner: rc,
        }
    }

    /// Ok when r is finite and > 0 and 0 ≤ rc ≤ r. [`Cutter::drop`] returns
    /// None for a cutter that fails this; check it where the cutter is read.
    pub(crate) fn validate(&self) -> Result<(), CutterError> {
        let (r, rc) = (self.radius, self.corner);
        if !(r.is_finite() && r > 0.0) {
            return Err(CutterError::Radius(r));
        }
        if !(rc.is_finite() && (0.0..=r).contains(&rc)) {
            return Err(CutterError::Corner {
                corner: rc,
                radius: r,
            });
        }
        Ok(())
    }

    /// Radius of the flat bottom, a = r − rc, mm.
    fn flat_radius(&self) -> f64 {
        self.radius - self.corner
    }

    /// Height p(ρ) of the lower surface above the tip at horizontal distance ρ
    /// from the axis, mm (see the module notes); ρ beyond r gives p(r) = rc.
    pub(crate) fn profile(&self, rho: f64) -> f64 {
        let rc = self.corner;
        let s = rho - self.flat_radius();
        if s <= 0.0 {
            return 0.0;
        }
        let s = s.min(rc);
        // (rc − s)(rc + s) rather than rc² − s²: no cancellation near the rim.
        rc - ((rc - s) * (rc + s)).sqrt()
    }

    /// Whether something with highest corner `zmax` at squared XY distance
    /// `d2` from the axis may lift the tip above `floor`: z_max − p(ρ) >
    /// floor, ρ = √d2. With δ = z_max − floor and p(ρ) = rc − √(rc² − (ρ −
    /// a)²) (a = r − rc), p(ρ) < δ for every ρ when δ > rc (p ≤ rc), and
    /// otherwise iff (ρ − a)⁺ < √q, q = δ(2rc − δ). The test is looser, so
    /// that rounding never skips what could win (it only decides what is
    /// tested): ρ < a + √q + ε with ε = 1e-6·r for a bull nose; for a ball
    /// (a = 0) without a root, d2 < q(1 + 1e-6) + 1e-12·r², which holds
    /// whenever ρ < √q + 1e-9·r (2·√q·ε ≤ 1e-6·q + 1e6·ε²).
    #[inline]
    fn may_beat(&self, zmax: f64, d2: f64, floor: f64) -> bool {
        let delta = zmax - floor;
        if delta.is_nan() || delta <= 0.0 {
            return false;
        }
        let rc = self.corner;
        if delta >= rc {
            return true;
        }
        let q = delta * (2.0 * rc - delta);
        let r = self.radius;
        let a = self.flat_radius();
        if a == 0.0 {
            return d2 < q * (1.0 + 1e-6) + 1e-12 * r * r;
        }
        let reach = a + (q * (1.0 + 1e-6)).sqrt() + 1e-6 * r;
        d2 < reach * reach
    }

    /// Whether the triangles under upper plane `pl` (of a cell or block
    /// whose lower-left corner is `m`) may lift the tip (axis through `c`)
    /// above `floor`, judged by that plane
    /// z ≤ A + g·(q − m) ([`CellPlane`]): every point of those triangles lies
    /// on or under it, so f = z − p(ρ) on them is at most the plane's own
    /// drop, its facet contact (module notes) with tan θ = |g|: ρ_c = a +
    /// rc·sin θ uphill, tip = A + g·(c − m) + |g|·ρ_c − rc(1 − cos θ). Only
    /// trusted for |g| ≤ 1000 (cos θ ≥ 1e-3) and only when it falls short
    /// by more than [`CELL_PLANE_MARGIN`], far above the rounding.
    #[inline]
    fn plane_may_beat(&self, (pl, m): (&CellPlane, [f64; 2]), c: [f64; 2], floor: f64) -> bool {
        let (gx, gy) = (f64::from(pl.g[0]), f64::from(pl.g[1]));
        let t = norm(gx, gy);
        if t.is_nan() || t > 1000.0 {
            return true;
        }
        let sec = (1.0 + t * t).sqrt();
        let rho = self.flat_radius() + self.corner * (t / sec);
        let z = f64::from(pl.a) + gx * (c[0] - m[0]) + gy * (c[1] - m[1]) + t * rho;
        let tip = z - self.corner * (1.0 - 1.0 / sec);
        tip.is_nan() || tip + CELL_PLANE_MARGIN > floor
    }

    /// The lowest tip z at which the cutter, axis vertical through (x, y),
    /// touches a triangle of `mesh` without any triangle entering it; None when
    /// no triangle lies under the cutter's footprint (or the cutter fails
    /// [`Cutter::validate`], or x or y is not finite).
    pub fn drop(&self, mesh: &MeshIndex, x: f64, y: f64) -> Option<f64> {
        self.drop_contact(mesh, x, y).map(|k| k.tip)
    }

    /// [`Cutter::drop`] with the part point that sets the tip (one of them
    /// when several touch at once).
    pub(crate) fn drop_contact(&self, mesh: &MeshIndex, x: f64, y: f64) -> Option<Contact> {
        self.contact_above(mesh, x, y, f64::NEG_INFINITY)
    }

    /// [`Cutter::drop`] when it lies above `level`, else None: the same
    /// height to the last bit, found faster, because a triangle that cannot
    /// lift the cutter above `level` is skipped from the start. (Every
    /// triangle that can is tested exactly as by [`Cutter::drop`], and the
    /// drop height is their maximum.)
    pub(crate) fn drop_above(&self, mesh: &MeshIndex, x: f64, y: f64, level: f64) -> Option<f64> {
        self.contact_above(mesh, x, y, level).map(|k| k.tip)
    }

    /// [`Cutter::drop`], faster when `hint` is a little under the answer: a
    /// first search above `hint`, and the whole search only when nothing lies
    /// above it. The result does not depend on `hint`.
    pub(crate) fn drop_hinted(&self, mesh: &MeshIndex, x: f64, y: f64, hint: f64) -> Option<f64> {
        if !hint.is_finite() {
            return self.drop(mesh, x, y);
        }
        self.drop_above(mesh, x, y, hint)
            .or_else(|| self.drop(mesh, x, y))
    }

    /// The contact of the drop when its tip lies above `floor` (−∞: always).
    fn contact_above(&self, mesh: &MeshIndex, x: f64, y: f64, floor: f64) -> Option<Contact> {
        crate::count::drop();
        if self.validate().is_err() || !(x.is_finite() && y.is_finite()) || floor.is_nan() {
            return None;
        }
        let r = self.radius;
        let range = mesh.cell_range(x - r, x + r, y - r, y + r)?;
        let c = [x, y];
        // Pass 1, on every triangle the grid's bounds keep: its plane's
        // contact (the facet test), which bounds the whole triangle; its
        // vertices; and when the contact lies inside it, that contact (the
        // triangle's maximum). It raises the floor fast, so that the
        // triangles left for pass 2 are few.
        let mut best: Option<Contact> = None;
        let floor_cell = std::cell::Cell::new(floor);
        let mut near: Vec<Near> = Vec::with_capacity(64);
        // A cell is skipped on the same bound: its triangles' highest corner
        // at the distance to the box round all of them.
        let may_win = |b: &Bounds, d2: f64| self.may_beat(b.top(), d2, floor_cell.get());
        // ... and on its upper plane's contact.
        let cell_may_win = |plane: (&CellPlane, [f64; 2]), b: &Bounds, d2: f64| {
            may_win(b, d2) && self.plane_may_beat(plane, c, floor_cell.get())
        };
        mesh.for_each_near(c, r, range, cell_may_win, may_win, |ti, b, d2| {
            let mut floor = floor_cell.get();
            let t = &mesh.tri(ti);
            let rel = t.relative(c);
            let plane = self.plane_contact(t, &rel);
            if plane.is_some_and(|k| plane_rules_out(t, k.tip, floor)) {
                return;
            }
            for v in rel {
                // The tip v_z − p(ρ) is not above v_z (p ≥ 0, and rounding
                // of a difference keeps its order).
                // The same test without its root first ([`Cutter::may_beat`]).
                if v[2] > floor && self.may_beat(v[2], v[0] * v[0] + v[1] * v[1], floor) {
                    if let Some(k) = self.vertex(v) {
                        raise(&mut best, &mut floor, k);
                    }
                }
            }
            match plane {
                Some(k) if self.inside(t, &rel, k.point) => raise(&mut best, &mut floor, k),
                _ => near.push(Near {
                    ti,
                    zmax: b.top(),
                    d2,
                    plane: plane.map_or(f64::INFINITY, |k| k.tip),
                }),
            }
            floor_cell.set(floor);
        });
        let mut floor = floor_cell.get();
        // Pass 2: the edges of the triangles whose plane's contact lies
        // outside them, the highest planes first (only speed depends on the
        // order: each is tested unless its bound rules it out).
        near.sort_unstable_by(|a, b| b.plane.total_cmp(&a.plane));
        for n in near {
            if !self.may_beat(n.zmax, n.d2, floor) {
                continue;
            }
            let t = &mesh.tri(n.ti);
            if n.plane.is_finite() && plane_rules_out(t, n.plane, floor) {
                continue;
            }
            if let Some(k) = self.edges(&t.relative(c), floor) {
                if k.tip > floor {
                    floor = k.tip;
                    best = Some(k);
                }
            }
        }
        best.map(|k| Contact {
            tip: k.tip,
            point: [k.point[0] + x, k.point[1] + y, k.point[2]],
        })
    }

    /// [`Cutter::drop`] at every point, in parallel (rayon), in order.
    pub fn drop_many(&self, mesh: &MeshIndex, pts: &[(f64, f64)]) -> Vec<Option<f64>> {
        pts.par_iter()
            .map(|&(x, y)| self.drop(mesh, x, y))
            .collect()
    }

    /// [`Cutter::drop_above`] at every point (x, y, level), in parallel, in
    /// order.
    pub(crate) fn drop_many_above(
        &self,
        mesh: &MeshIndex,
        pts: &[(f64, f64, f64)],
    ) -> Vec<Option<f64>> {
        pts.par_iter()
            .map(|&(x, y, level)| self.drop_above(mesh, x, y, level))
            .collect()
    }

    /// [`Cutter::drop_hinted`] at every point (x, y, hint), in parallel, in
    /// order.
    pub(crate) fn drop_many_hinted(
        &self,
        mesh: &MeshIndex,
        pts: &[(f64, f64, f64)],
    ) -> Vec<Option<f64>> {
        pts.par_iter()
            .map(|&(x, y, hint)| self.drop_hinted(mesh, x, y, hint))
            .collect()
    }

    /// The drop against one triangle (all three tests), with the contact;
    /// None when the triangle does not meet the footprint.
    #[cfg(test)]
    fn drop_triangle(&self, t: &Tri, x: f64, y: f64) -> Option<Contact> {
        let rel = t.relative([x, y]);
        let mut best = None;
        for v in &rel {
            best = Contact::better(best, self.vertex(*v));
        }
        let floor = best.map_or(f64::NEG_INFINITY, |k| k.tip);
        Contact::better(best, self.triangle_edges_facet(t, &rel, floor))
    }

    /// Edge and facet tests of one triangle (vertices relative to the axis),
    /// skipping any edge that cannot give more than `floor`.
    ///
    /// The facet test's contact is the maximum of f over the whole plane of
    /// the triangle within the footprint (concavity). So when it lies inside
    /// the triangle it is the answer and the edges need no test, and when it
    /// does not beat `floor` ([`plane_rules_out`]) nothing of the triangle
    /// can.
    #[cfg(test)]
    fn triangle_edges_facet(&self, t: &Tri, rel: &[[f64; 3]; 3], floor: f64) -> Option<Contact> {
        if let Some(k) = self.plane_contact(t, rel) {
            if self.inside(t, rel, k.point) {
                return Some(k);
            }
            if plane_rules_out(t, k.tip, floor) {
                return None;
            }
        }
        self.edges(rel, floor)
    }

    /// Edge tests of one triangle (vertices relative to the axis), skipping
    /// any edge that cannot give more than `floor`.
    fn edges(&self, rel: &[[f64; 3]; 3], mut floor: f64) -> Option<Contact> {
        let mut best = None;
        for i in 0..3 {
            if let Some(k) = self.edge(rel[i], rel[(i + 1) % 3], floor) {
                if k.tip > floor {
                    floor = k.tip;
                    best = Some(k);
                }
            }
        }
        best
    }

    /// Vertex test: t = V_z − p(ρ) when ρ ≤ r.
    fn vertex(&self, v: [f64; 3]) -> Option<Contact> {
        let rho = norm(v[0], v[1]);
        (rho <= self.radius).then(|| Contact {
            tip: v[2] - self.profile(rho),
            point: v,
        })
    }

    /// Facet test (module notes): the contact at ρ_c = a + rc·n_xy uphill on
    /// the triangle's plane, the maximum of f over the plane within the
    /// footprint; None for a triangle without a facet test (near vertical,
    /// sliver). Whether it lies in the triangle is [`Cutter::inside`].
    fn plane_contact(&self, t: &Tri, rel: &[[f64; 3]; 3]) -> Option<Contact> {
        if t.orient == 0.0 {
            return None;
        }
        let [nx, ny, nz] = t.n;
        let nxy = norm(nx, ny);
        let (qx, qy) = if nxy > 0.0 {
            let rho = self.flat_radius() + self.corner * nxy;
            (-nx / nxy * rho, -ny / nxy * rho)
        } else {
            (0.0, 0.0)
        };
        let v0 = rel[0];
        let zc = (nx * v0[0] + ny * v0[1] + nz * v0[2] - nx * qx - ny * qy) / nz;
        let tip = zc - self.corner * (1.0 - nz);
        tip.is_finite().then_some(Contact {
            tip,
            point: [qx, qy, zc],
        })
    }

    /// Whether the point x (relative to the axis, on the triangle's plane)
    /// lies in the triangle: the signs of n·((V_{i+1} − V_i) × (x − V_i)),
    /// in 3-D so that steep facets do not degrade. A NaN side counts as
    /// outside.
    fn inside(&self, t: &Tri, rel: &[[f64; 3]; 3], x: [f64; 3]) -> bool {
        (0..3).all(|i| {
            let a = rel[i];
            let b = rel[(i + 1) % 3];
            let e = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let w = [x[0] - a[0], x[1] - a[1], x[2] - a[2]];
            t.orient * dot(t.n, cross(e, w)) >= 0.0
        })
    }

    /// Edge test (module notes) for the segment a→b relative to the axis;
    /// None when it misses the footprint, is vertical, or cannot give more than
    /// `floor`.
    fn edge(&self, a: [f64; 3], b: [f64; 3], floor: f64) -> Option<Contact> {
        // Every point of the edge lies at least the segment's XY distance
        // from the axis and at most max(a_z, b_z) high: the bound below
        // without its roots, on the same terms as a triangle's box.
        if !self.may_beat(a[2].max(b[2]), segment_dist2(a, b), floor) {
            return None;
        }
        let s = EdgeFrame::new(a, b, self.radius)?;
        // Upper bound for pruning: the higher clipped end's z minus p at the
        // smallest ρ on [lo, hi] (p is non-decreasing).
        let sig_min = 0.0f64.clamp(s.lo, s.hi);
        let bound = s.z(s.lo).max(s.z(s.hi)) - self.profile(norm(s.delta, sig_min));
        if bound <= floor {
            return None;
        }
        if self.corner == 0.0 {
            let sig = if s.dz > 0.0 { s.hi } else { s.lo };
            return Some(s.contact(sig, s.z(sig)));
        }
        if self.flat_radius() == 0.0 {
            let d3 = norm(s.len, s.dz);
            let sig = s.h * s.dz / d3;
            if (s.lo..=s.hi).contains(&sig) {
                let tip = s.z(sig) + s.h * s.len / d3 - self.radius;
                return Some(Contact {
                    tip,
                    point: s.point(sig),
                });
            }
            let sig = sig.clamp(s.lo, s.hi);
            return Some(s.contact(sig, self.h(&s, sig)));
        }
        Some(self.edge_search(&s).0)
    }

    /// h(σ) = z(σ) − p(ρ(σ)) along an edge.
    fn h(&self, s: &EdgeFrame, sig: f64) -> f64 {
        s.z(sig) - self.profile(norm(s.delta, sig))
    }

    /// h′(σ) = m − p′(ρ)·σ/ρ along an edge (±∞ on the rim).
    fn dh(&self, s: &EdgeFrame, sig: f64) -> f64 {
        let m = s.dz / s.len;
        let rho = norm(s.delta, sig);
        let rc = self.corner;
        let q = rho - self.flat_radius();
        if q <= 0.0 {
            return m;
        }
        let q = q.min(rc);
        let w = ((rc - q) * (rc + q)).sqrt();
        if w > 0.0 {
            m - q * sig / (rho * w)
        } else if sig > 0.0 {
            f64::NEG_INFINITY
        } else {
            f64::INFINITY
        }
    }

    /// Bisection on the sign of h′ over [lo, hi] (module notes). Returns the
    /// contact, the proven bound on its error (mm) and the steps taken.
    fn edge_search(&self, s: &EdgeFrame) -> (Contact, f64, u32) {
        let (mut l, mut u) = (s.lo, s.hi);
        let mut dl = self.dh(s, l);
        let mut du = self.dh(s, u);
        if dl.is_nan() || dl <= 0.0 {
            return (s.contact(l, self.h(s, l)), 0.0, 0);
        }
        if du.is_nan() || du >= 0.0 {
            return (s.contact(u, self.h(s, u)), 0.0, 0);
        }
        let mut steps = 0;
        let mut bound = dl.min(-du) * (u - l);
        while bound > EDGE_TOL && steps < EDGE_MAX_ITER {
            let mid = 0.5 * (l + u);
            if mid <= l || mid >= u {
                break;
            }
            steps += 1;
            let dm = self.dh(s, mid);
            if dm > 0.0 {
                (l, dl) = (mid, dm);
            } else if dm < 0.0 {
                (u, du) = (mid, dm);
            } else {
                (l, u, dl, du) = (mid, mid, 0.0, 0.0);
            }
            bound = dl.min(-du) * (u - l);
            if u == l {
                bound = 0.0;
            }
        }
        let (hl, hu) = (self.h(s, l), self.h(s, u));
        let k = if hu > hl {
            s.contact(u, hu)
        } else {
            s.contact(l, hl)
        };
        (k, bound, steps)
    }
}

/// Whether a triangle's plane, whose facet contact gives `tip`, rules the
/// whole triangle out against `floor`: the contact is the maximum of f over
/// the plane within the footprint, so no point of the triangle gives more;
/// trusted on facets with n_z ≥ [`PLANE_BOUND_NZ`] and only when it falls
/// [`PLANE_BOUND_MARGIN`] short, far more than the rounding there.
fn plane_rules_out(t: &Tri, tip: f64, floor: f64) -> bool {
    t.n[2] >= PLANE_BOUND_NZ && tip + PLANE_BOUND_MARGIN <= floor
}

/// Keeps contact `k` as the best when it beats `floor`, and raises the
/// floor to it.
fn raise(best: &mut Option<Contact>, floor: &mut f64, k: Contact) {
    if k.tip > *floor {
        *floor = k.tip;
        *best = Some(k);
    }
}

/// A triangle left for the edge pass of a drop: its index, highest corner,
/// squared XY distance from the axis to its box, and its plane's contact
/// tip (+∞ without a facet test).
struct Near {
    ti: u32,
    zmax: f64,
    d2: f64,
    plane: f64,
}

/// An edge in the frame of the edge test: σ along the XY line from the foot of
/// the perpendicular from the axis, the clipped interval [lo, hi].
#[derive(Clone, Copy, Debug)]
struct EdgeFrame {
    a: [f64; 3],
    d: [f64; 3],
    /// |d_xy|
    len: f64,
    dz: f64,
    /// σ of a
    sig_a: f64,
    /// XY distance from the axis to the line
    delta: f64,
    /// half chord √(r² − δ²)
    h: f64,
    lo: f64,
    hi: f64,
}

impl EdgeFrame {
    fn new(a: [f64; 3], b: [f64; 3], r: f64) -> Option<EdgeFrame> {
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let len = norm(d[0], d[1]);
        if len.is_nan() || len <= 0.0 {
            return None;
        }
        let (ex, ey) = (d[0] / len, d[1] / len);
        let delta = (a[0] * ey - a[1] * ex).abs();
        if delta.is_nan() || delta > r {
            return None;
        }
        let h = ((r - delta) * (r + delta)).sqrt();
        let sig_a = a[0] * ex + a[1] * ey;
        let lo = (-h).max(sig_a);
        let hi = h.min(sig_a + len);
        if lo.is_nan() || hi.is_nan() || lo > hi {
            return None;
        }
        Some(EdgeFrame {
            a,
            d,
            len,
            dz: d[2],
            sig_a,
            delta,
            h,
            lo,
            hi,
        })
    }

    /// Edge parameter t ∈ [0, 1] of σ.
    fn t(&self, sig: f64) -> f64 {
        ((sig - self.sig_a) / self.len).clamp(0.0, 1.0)
    }

    fn z(&self, sig: f64) -> f64 {
        self.a[2] + self.t(sig) * self.dz
    }

    fn point(&self, sig: f64) -> [f64; 3] {
        let t = self.t(sig);
        [
            self.a[0] + t * self.d[0],
            self.a[1] + t * self.d[1],
            self.a[2] + t * self.d[2],
        ]
    }

    fn contact(&self, sig: f64, tip: f64) -> Contact {
        Contact {
            tip,
            point: self.point(sig),
        }
    }
}

/// √(x² + y²). Not `f64::hypot`, which guards against overflow and
/// underflow at several times the cost (it was a third of a drop's time);
/// lengths here are mm, nowhere near 1e±154.
/// Squared XY distance from the axis (the origin) to the segment a→b.
fn segment_dist2(a: [f64; 3], b: [f64; 3]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (-(a[0] * dx + a[1] * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (px, py) = (a[0] + t * dx, a[1] + t * dy);
    px * px + py * py
}

fn norm(x: f64, y: f64) -> f64 {
    (x * x + y * y).sqrt()
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// A triangle's XY bounding box and highest z in single precision, rounded
/// outwards (lo down, hi and z_max up), so that the box still holds the
/// triangle and z_max is not below its highest corner: the bounds only
/// decide what is tested, so rounding them outwards keeps every drop
/// exact. 20 bytes, so the scan of a cell reads little.
#[derive(Clone, Copy, Debug)]
struct Bounds {
    lo: [f32; 2],
    hi: [f32; 2],
    zmax: f32,
}

impl Bounds {
    /// The box round `all` and their highest corner; an empty box (lo = +∞,
    /// hi = −∞, zmax = −∞) when there are none.
    fn union<'a>(all: impl Iterator<Item = &'a Bounds>) -> Bounds {
        let empty = Bounds {
            lo: [f32::INFINITY; 2],
            hi: [f32::NEG_INFINITY; 2],
            zmax: f32::NEG_INFINITY,
        };
        all.fold(empty, |u, b| Bounds {
            lo: [u.lo[0].min(b.lo[0]), u.lo[1].min(b.lo[1])],
            hi: [u.hi[0].max(b.hi[0]), u.hi[1].max(b.hi[1])],
            zmax: u.zmax.max(b.zmax),
        })
    }

    fn new(v: &[[f64; 3]; 3]) -> Bounds {
        Bounds {
            lo: [
                f32_down(v[0][0].min(v[1][0]).min(v[2][0])),
                f32_down(v[0][1].min(v[1][1]).min(v[2][1])),
            ],
            hi: [
                f32_up(v[0][0].max(v[1][0]).max(v[2][0])),
                f32_up(v[0][1].max(v[1][1]).max(v[2][1])),
            ],
            zmax: f32_up(v[0][2].max(v[1][2]).max(v[2][2])),
        }
    }

    /// Highest corner, mm.
    fn top(&self) -> f64 {
        f64::from(self.zmax)
    }
}

/// The largest f32 not above x (x not NaN; below −f32::MAX, −∞).
fn f32_down(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) <= x {
        f
    } else if f == 0.0 {
        -f32::from_bits(1)
    } else if f > 0.0 {
        f32::from_bits(f.to_bits() - 1)
    } else {
        f32::from_bits(f.to_bits() + 1)
    }
}

/// The smallest f32 not below x (x not NaN; above f32::MAX, +∞).
fn f32_up(x: f64) -> f32 {
    -f32_down(-x)
}

/// A triangle with what every drop needs precomputed (assembled from a
/// [`MeshIndex`]'s corners and packed normal when a drop visits it).
#[derive(Clone, Copy, Debug)]
struct Tri {
    v: [[f64; 3]; 3],
    /// Unit normal with n_z ≥ 0.
    n: [f64; 3],
    /// +1 or −1: the sign of n·((v1 − v0) × (v2 − v0)); 0 when the triangle
    /// gets no facet test (near vertical or a sliver).
    orient: f64,
}

impl Tri {
    fn new(v: [[f64; 3]; 3]) -> Tri {
        // The cross product of the two edges at the corner opposite the longest
        // edge (the two shorter ones) is the most accurate.
        let e = [sub(v[2], v[1]), sub(v[0], v[2]), sub(v[1], v[0])];
        let l2 = e.map(|x| dot(x, x));
        let k = if l2[0] >= l2[1] && l2[0] >= l2[2] {
            0
        } else if l2[1] >= l2[2] {
            1
        } else {
            2
        };
        // Edge e[k] is opposite corner k; the cross product at corner k has
        // the same orientation as (v1 − v0) × (v2 − v0).
        let a = sub(v[(k + 1) % 3], v[k]);
        let b = sub(v[(k + 2) % 3], v[k]);
        let nn = cross(a, b);
        let len = dot(nn, nn).sqrt();
        let lmax2 = l2[k];
        let mut n = [0.0, 0.0, 1.0];
        let mut orient = 0.0;
        if len > SLIVER * lmax2 && len.is_finite() {
            let s = if nn[2] < 0.0 { -1.0 } else { 1.0 };
            n = nn.map(|c| s * c / len);
            if n[2] >= NZ_MIN {
                orient = s;
            }
        }
        Tri { v, n, orient }
    }

    /// The normal times the orientation, or 0 without a facet test: one
    /// vector holds both (n_z ≥ [`NZ_MIN`] > 0 when there is a facet test, so
    /// the sign of the z component is the orientation; negation is exact).
    fn packed_normal(&self) -> [f64; 3] {
        if self.orient == 0.0 {
            [0.0; 3]
        } else {
            self.n.map(|c| self.orient * c)
        }
    }

    /// The triangle of corners `v` and [`Tri::packed_normal`] `p`.
    fn unpack(v: [[f64; 3]; 3], p: [f64; 3]) -> Tri {
        if p[2] > 0.0 {
            Tri {
                v,
                n: p,
                orient: 1.0,
            }
        } else if p[2] < 0.0 {
            Tri {
                v,
                n: p.map(|c| -c),
                orient: -1.0,
            }
        } else {
            Tri {
                v,
                n: [0.0, 0.0, 1.0],
                orient: 0.0,
            }
        }
    }

    /// Corners with XY relative to `c`.
    fn relative(&self, c: [f64; 2]) -> [[f64; 3]; 3] {
        self.v.map(|p| [p[0] - c[0], p[1] - c[1], p[2]])
    }
}

/// Triangles bucketed on a uniform XY grid (each triangle in every cell its XY
/// bounding box, grown by nothing, touches).
#[derive(Clone, Debug)]
pub struct MeshIndex {
    /// The corners of each triangle, mm.
    tris: Vec<[[f64; 3]; 3]>,
    /// `normals[i]` is `tris[i]`'s [`Tri::packed_normal`] (what [`Tri`]
    /// adds to the corners, kept apart so that the corners are the caller's
    /// own buffer, not a copy).
    normals: Vec<[f64; 3]>,
    /// `bounds[i]` is `tris[i]`'s.
    bounds: Vec<Bounds>,
    /// Lower-left corner of the grid, mm.
    origin: [f64; 2],
    /// Cell side, mm.
    cell: f64,
    nx: usize,
    ny: usize,
    /// Cell k = j·nx + i holds `items[start[k]..start[k + 1]]`, each item a
    /// triangle index shifted left by 2 with its [`rank`] in the low bits,
    /// sorted by rank within the cell.
    start: Vec<usize>,
    /// Where ranks 1, 2 and 3 begin in cell k's items (offsets from
    /// `start[k]`), so that a drop takes a cell's ranks without searching.
    rank_at: Vec<[u32; 3]>,
    items: Vec<u32>,
    /// Cell k's box round the boxes of all its triangles, and their highest
    /// corner (empty: an inverted box at −∞).
    cells: Vec<Bounds>,
    /// Cell k's upper plane ([`CellPlane`]).
    planes: Vec<CellPlane>,
    /// Blocks of [`BLOCK`] × [`BLOCK`] cells, row by row (`bnx` a row):
    /// block b's box round all its cells' triangles and their highest
    /// corner, and its upper plane, so that a drop rules out a block's
    /// cells with one test where the block lies out of reach or under the
    /// floor.
    bnx: usize,
    blocks: Vec<Bounds>,
    block_planes: Vec<CellPlane>,
    skipped: usize,
}

impl MeshIndex {
    /// Bucket `triangles` on a grid of square cells of side `cell` mm. A cell
    /// that is not finite and positive is replaced by twice the mean XY extent
    /// of the triangles (so a triangle touches about four cells); any cell is
    /// doubled until the grid has at most [`MAX_CELLS`] cells and at most
    /// [`MAX_ENTRIES_PER_TRIANGLE`]·n + [`MAX_CELLS`] entries. For drops a cell
    /// near the tool radius is a good choice. Triangles with a coordinate that
    /// is not finite, and any beyond the first [`MAX_TRIANGLES`], are left out
    /// and counted ([`MeshIndex::skipped`]): a caller that must not lose
    /// part of its surface refuses such an index.
    pub fn new(triangles: Vec<[[f64; 3]; 3]>, cell: f64) -> MeshIndex {
        let total = triangles.len();
        // In place: the caller's buffer becomes the index's corners.
        let mut tris = triangles;
        tris.retain(|t| t.iter().flatten().all(|c| c.is_finite()));
        tris.truncate(MAX_TRIANGLES);
        tris.shrink_to_fit();
        let normals: Vec<[f64; 3]> = tris
            .par_iter()
            .map(|&v| Tri::new(v).packed_normal())
            .collect();
        let bounds: Vec<Bounds> = tris.par_iter().map(Bounds::new).collect();
        let mut index = MeshIndex {
            tris: Vec::new(),
            normals: Vec::new(),
            bounds: Vec::new(),
            origin: [0.0, 0.0],
            cell: 1.0,
            nx: 0,
            ny: 0,
            start: vec![0],
            rank_at: Vec::new(),
            items: Vec::new(),
            cells: Vec::new(),
            planes: Vec::new(),
            bnx: 0,
            blocks: Vec::new(),
            block_planes: Vec::new(),
            skipped: total - tris.len(),
        };
        if tris.is_empty() {
            return index;
        }
        index.size_grid(&bounds, cell);
        let (count, mut items) = index.bucket(&bounds);
        sort_cells(&mut items, &count, &bounds);
        index.cells = cell_bounds(&items, &count, &bounds);
        index.planes = cell_planes(&index, &items, &count, &tris, &normals);
        (index.bnx, index.blocks, index.block_planes) =
            blocks(&index, &items, &count, &tris, &normals);
        index.rank_at = rank_offsets(&items, &count);
        index.start = count;
        index.items = items;
        index.tris = tris;
        index.normals = normals;
        index.bounds = bounds;
        index
    }

    /// Choose the grid for `bounds`: origin at their low corner, cells of
    /// side `cell` (or twice the mean extent where `cell` is not finite and
    /// positive), doubled until the grid keeps within [`MAX_CELLS`] cells and
    /// [`MAX_ENTRIES_PER_TRIANGLE`]·n + [`MAX_CELLS`] entries.
    fn size_grid(&mut self, bounds: &[Bounds], cell: f64) {
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        let mut extent = 0.0;
        for t in bounds {
            let (tlo, thi) = (t.lo.map(f64::from), t.hi.map(f64::from));
            for k in 0..2 {
                lo[k] = lo[k].min(tlo[k]);
                hi[k] = hi[k].max(thi[k]);
            }
            extent += (thi[0] - tlo[0]).max(thi[1] - tlo[1]);
        }
        let span = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        let mut cell = if cell.is_finite() && cell > 0.0 {
            cell
        } else {
            2.0 * extent / bounds.len() as f64
        };
        // A mesh of points (all extents 0) or a cell below rounding of the
        // coordinates: take a cell the grid can still resolve.
        let floor =
            (span * 1e-9).max(lo.iter().chain(&hi).fold(0.0f64, |m, c| m.max(c.abs())) * 1e-12);
        cell = cell.max(floor).max(f64::MIN_POSITIVE);
        let cells_along = |w: f64, cell: f64| (w / cell).floor() + 1.0;
        let n = bounds.len();
        let entry_cap = MAX_ENTRIES_PER_TRIANGLE * n + MAX_CELLS;
        loop {
            let nxf = cells_along(hi[0] - lo[0], cell);
            let nyf = cells_along(hi[1] - lo[1], cell);
            if nxf * nyf > MAX_CELLS as f64 {
                cell *= 2.0;
                continue;
            }
            self.origin = lo;
            self.cell = cell;
            self.nx = nxf as usize;
            self.ny = nyf as usize;
            let entries: usize = bounds
                .iter()
                .map(|t| {
                    let (i0, i1, j0, j1) = self.cells_of(t);
                    (i1 - i0 + 1) * (j1 - j0 + 1)
                })
                .sum();
            if entries <= entry_cap || (self.nx == 1 && self.ny == 1) {
                break;
            }
            cell *= 2.0;
        }
    }

    /// Each triangle's index in every cell its box meets, by counting sort:
    /// cell k's items are `items[count[k]..count[k + 1]]`, each the triangle
    /// times 4 plus its rank in the cell.
    fn bucket(&self, bounds: &[Bounds]) -> (Vec<usize>, Vec<u32>) {
        // Counting sort into the cells, then each cell's items by rank.
        let mut count = vec![0usize; self.nx * self.ny + 1];
        for t in bounds {
            let (i0, i1, j0, j1) = self.cells_of(t);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    count[j * self.nx + i + 1] += 1;
                }
            }
        }
        for k in 1..count.len() {
            count[k] += count[k - 1];
        }
        let mut fill = count.clone();
        let mut items = vec![0u32; count[count.len() - 1]];
        for (ti, t) in bounds.iter().enumerate() {
            let (i0, i1, j0, j1) = self.cells_of(t);
            // ti < MAX_TRIANGLES = 2³⁰, so ti·4 + rank fits in a u32.
            let base = (ti as u32) << 2;
            for j in j0..=j1 {
                for i in i0..=i1 {
                    let k = j * self.nx + i;
                    items[fill[k]] = base | rank(i > i0, j > j0);
                    fill[k] += 1;
                }
            }
        }
        (count, items)
    }

    /// Triangle `ti` with its normal.
    fn tri(&self, ti: u32) -> Tri {
        let i = ti as usize;
        Tri::unpack(self.tris[i], self.normals[i])
    }

    /// Number of triangles indexed.
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.tris.len()
    }

    /// Triangles left out: a coordinate was not finite, or they came after
    /// the first [`MAX_TRIANGLES`].
    pub(crate) fn skipped(&self) -> usize {
        self.skipped
    }

    /// Lower-left corner of cell k = j·nx + i, mm.
    fn cell_corner(&self, k: usize) -> [f64; 2] {
        let (i, j) = (k % self.nx, k / self.nx);
        [
            self.origin[0] + i as f64 * self.cell,
            self.origin[1] + j as f64 * self.cell,
        ]
    }

    /// Lower-left corner of block (bi, bj) ([`BLOCK`] cells a side), mm:
    /// that of its first cell.
    fn block_corner(&self, bi: usize, bj: usize) -> [f64; 2] {
        self.cell_corner(bj * BLOCK * self.nx + bi * BLOCK)
    }

    /// The cells (i0, i1, j0, j1) a triangle's box spans, clamped to the grid.
    fn cells_of(&self, t: &Bounds) -> (usize, usize, usize, usize) {
        (
            self.cell_x(t.lo[0].into()),
            self.cell_x(t.hi[0].into()),
            self.cell_y(t.lo[1].into()),
            self.cell_y(t.hi[1].into()),
        )
    }

    fn cell_x(&self, x: f64) -> usize {
        (((x - self.origin[0]) / self.cell).floor().max(0.0) as usize).min(self.nx - 1)
    }

    fn cell_y(&self, y: f64) -> usize {
        (((y - self.origin[1]) / self.cell).floor().max(0.0) as usize).min(self.ny - 1)
    }

    /// The cells a box [x0, x1] × [y0, y1] touches, or None when it misses the
    /// grid.
    fn cell_range(
        &self,
        x0: f64,
        x1: f64,
        y0: f64,
        y1: f64,
    ) -> Option<(usize, usize, usize, usize)> {
        if self.tris.is_empty() {
            return None;
        }
        let gx1 = self.origin[0] + self.nx as f64 * self.cell;
        let gy1 = self.origin[1] + self.ny as f64 * self.cell;
        if x1 < self.origin[0] || y1 < self.origin[1] || x0 > gx1 || y0 > gy1 {
            return None;
        }
        Some((
            self.cell_x(x0),
            self.cell_x(x1),
            self.cell_y(y0),
            self.cell_y(y1),
        ))
    }

    /// Calls `f(index, bounds, squared distance from c to the bounding box)`
    /// once for every triangle in the cells `range` whose bounding box comes
    /// within `r` of `c` and that `tri_may_win(bounds, squared distance)`
    /// keeps, skipping the cells `cell_may_win` rules out (asked with the
    /// box round the cell's triangles).
    ///
    /// A triangle in several cells is visited only in the first cell, in each
    /// direction, that both it and the range cover: in cell (i, j) of a range
    /// starting at (i₀, j₀), a triangle whose own first cell is (a, b) is
    /// visited iff max(a, i₀) = i and max(b, j₀) = j. Inside the range
    /// (i > i₀, j > j₀) that means a = i and b = j, rank 1 only; on its first
    /// column b = j (ranks 0–1), on its first row a = i (ranks 1–2), in its
    /// first cell all. Those are contiguous in a cell sorted by rank, so a
    /// triangle that spans many cells costs nothing in the cells where it is
    /// not visited (the surface's bottom and walls are long slivers spanning
    /// hundreds of cells).
    fn for_each_near(
        &self,
        c: [f64; 2],
        r: f64,
        (i0, i1, j0, j1): (usize, usize, usize, usize),
        cell_may_win: impl Fn((&CellPlane, [f64; 2]), &Bounds, f64) -> bool,
        tri_may_win: impl Fn(&Bounds, f64) -> bool,
        mut f: impl FnMut(u32, &Bounds, f64),
    ) {
        // Slack: the tests measure ρ their own way; rounding must not make this
        // filter stricter than they are.
        let r2 = r * r * (1.0 + 1e-9);
        let box_dist2 = |t: &Bounds| {
            let (lo, hi) = (t.lo.map(f64::from), t.hi.map(f64::from));
            let dx = (lo[0] - c[0]).max(c[0] - hi[0]).max(0.0);
            let dy = (lo[1] - c[1]).max(c[1] - hi[1]).max(0.0);
            dx * dx + dy * dy
        };
        // The blocks the range touches, each judged the first time one of
        // its cells comes up (at the floor of that moment): 0 not yet, 1 in,
        // 2 out. A range over more than BLOCKS_NEAR blocks judges none.
        let (bi0, bj0) = (i0 / BLOCK, j0 / BLOCK);
        let bw = i1 / BLOCK - bi0 + 1;
        let judge_blocks = bw * (j1 / BLOCK - bj0 + 1) <= BLOCKS_NEAR;
        let mut judged = [0u8; BLOCKS_NEAR];
        let mut visit = |i: usize, j: usize| {
            if judge_blocks {
                let (bi, bj) = (i / BLOCK, j / BLOCK);
                let slot = &mut judged[(bj - bj0) * bw + bi - bi0];
                if *slot == 0 {
                    let b = bj * self.bnx + bi;
                    let corner = self.block_corner(bi, bj);
                    let d2 = box_dist2(&self.blocks[b]);
                    let may = d2 <= r2
                        && cell_may_win((&self.block_planes[b], corner), &self.blocks[b], d2);
                    *slot = if may { 1 } else { 2 };
                }
                if *slot == 2 {
                    return;
                }
            }
            let k = j * self.nx + i;
            // A cell's box holds every triangle's box listed in it, so a
            // cell out of reach, or one the caller's bound rules out,
            // holds nothing to visit, whichever cell would visit them (and
            // the same for a block and its cells).
            let d2 = box_dist2(&self.cells[k]);
            if d2 > r2 || !cell_may_win((&self.planes[k], self.cell_corner(k)), &self.cells[k], d2)
            {
                return;
            }
            let cell = &self.items[self.start[k]..self.start[k + 1]];
            let [o1, o2, o3] = self.rank_at[k].map(|o| o as usize);
            let (mut at, end) = match (i > i0, j > j0) {
                (true, true) => (o1, o2),
                (false, true) => (0, o2),
                (true, false) => (o1, o3),
                (false, false) => (0, cell.len()),
            };
            while at < end {
                let it = cell[at];
                let ti = it >> 2;
                let t = &self.bounds[ti as usize];
                // Within a rank, highest corner first: once one cannot
                // win even at the cell's distance, no later one can.
                if !tri_may_win(t, d2) {
                    let rank = it & 3;
                    at += cell[at..end].partition_point(|&it| it & 3 == rank);
                    continue;
                }
                at += 1;
                let d2 = box_dist2(t);
                if d2 <= r2 && tri_may_win(t, d2) {
                    f(ti, t, d2);
                }
            }
        };
        // The cells ring by ring round the axis's cell, so that the nearest
        // triangles, which set a high floor, come first (only speed depends
        // on the order: every triangle is visited once in its own cell).
        let ic = self.cell_x(c[0]).clamp(i0, i1);
        let jc = self.cell_y(c[1]).clamp(j0, j1);
        let rings = (ic - i0).max(i1 - ic).max(jc - j0).max(j1 - jc);
        for d in 0..=rings {
            for_ring((ic, jc), d, (i0, i1, j0, j1), &mut visit);
        }
    }
}

/// Calls `visit(i, j)` for every cell of `range` at Chebyshev distance `d`
/// from `centre` (the centre itself for d = 0).
fn for_ring(
    (ic, jc): (usize, usize),
    d: usize,
    (i0, i1, j0, j1): (usize, usize, usize, usize),
    visit: &mut impl FnMut(usize, usize),
) {
    let (ilo, ihi) = (ic.saturating_sub(d).max(i0), (ic + d).min(i1));
    let (jlo, jhi) = (jc.saturating_sub(d).max(j0), (jc + d).min(j1));
    if d == 0 {
        visit(ic, jc);
        return;
    }
    // The bottom and top rows, when in range, whole.
    if jc >= d && jc - d >= j0 {
        (ilo..=ihi).for_each(|i| visit(i, jc - d));
    }
    if jc + d <= j1 {
        (ilo..=ihi).for_each(|i| visit(i, jc + d));
    }
    // The left and right columns between them.
    let (rlo, rhi) = ((jc + 1).saturating_sub(d).max(jlo), (jc + d - 1).min(jhi));
    for j in rlo..=rhi {
        if ic >= d && ic - d >= i0 {
            visit(ic - d, j);
        }
        if ic + d <= i1 {
            visit(ic + d, j);
        }
    }
}

/// Each cell's items (`items[count[k]..count[k + 1]]`) sorted by their
/// [`rank`], and within a rank by their triangle's highest corner,
/// highest first; the cells in parallel.
fn sort_cells(items: &mut [u32], count: &[usize], bounds: &[Bounds]) {
    let mut rest: &mut [u32] = items;
    let mut cells: Vec<&mut [u32]> = Vec::with_capacity(count.len().saturating_sub(1));
    for k in 0..count.len().saturating_sub(1) {
        let (cell, tail) = std::mem::take(&mut rest).split_at_mut(count[k + 1] - count[k]);
        cells.push(cell);
        rest = tail;
    }
    cells.into_par_iter().for_each(|c| {
        c.sort_unstable_by(|&a, &b| {
            let z = |it: u32| bounds[(it >> 2) as usize].zmax;
            (a & 3).cmp(&(b & 3)).then(z(b).total_cmp(&z(a)))
        })
    });
}

/// An upper plane over a cell's triangles: every corner of every triangle
/// the cell lists has z ≤ A + g·(q − m), m the cell's lower-left corner
/// ([`MeshIndex::cell_corner`]). g is the slope of the mean of the
/// triangles' normals (0 when they are near vertical on average); A is the
/// largest z − g·(q − m) over the corners, computed with the single
/// precision g and rounded up. A cell with no triangles has A = −∞. Since
/// z − g·(q − m) is affine, its maximum over a triangle is at a corner, so
/// the plane lies over every point of every triangle of the cell.
#[derive(Clone, Copy, Debug)]
struct CellPlane {
    a: f32,
    g: [f32; 2],
}

/// The upper plane ([`CellPlane`]) of each cell; the cells in parallel.
fn cell_planes(
    index: &MeshIndex,
    items: &[u32],
    count: &[usize],
    tris: &[[[f64; 3]; 3]],
    normals: &[[f64; 3]],
) -> Vec<CellPlane> {
    (0..count.len().saturating_sub(1))
        .into_par_iter()
        .map(|k| {
            let cell = &items[count[k]..count[k + 1]];
            upper_plane(cell, index.cell_corner(k), tris, normals)
        })
        .collect()
}

/// The upper plane ([`CellPlane`]) over the triangles of `items` (entries
/// as in a cell), referred to the corner `m`.
fn upper_plane(
    items: &[u32],
    m: [f64; 2],
    tris: &[[[f64; 3]; 3]],
    normals: &[[f64; 3]],
) -> CellPlane {
    let mut sum = [0.0f64; 3];
    for &it in items {
        let p = normals[(it >> 2) as usize];
        let s = if p[2] < 0.0 { -1.0 } else { 1.0 };
        sum = [sum[0] + s * p[0], sum[1] + s * p[1], sum[2] + s * p[2]];
    }
    let g = if sum[2] > 1e-3 * items.len() as f64 {
        [(-sum[0] / sum[2]) as f32, (-sum[1] / sum[2]) as f32]
    } else {
        [0.0, 0.0]
    };
    let g = if g.iter().all(|c| c.is_finite()) {
        g
    } else {
        [0.0, 0.0]
    };
    let (gx, gy) = (f64::from(g[0]), f64::from(g[1]));
    let mut a = f64::NEG_INFINITY;
    for &it in items {
        for v in &tris[(it >> 2) as usize] {
            a = a.max(v[2] - gx * (v[0] - m[0]) - gy * (v[1] - m[1]));
        }
    }
    CellPlane { a: f32_up(a), g }
}

/// The blocks of [`BLOCK`] × [`BLOCK`] cells of `index` (whose `cells` are
/// set): blocks along a row, and each block's bounds (the union of its
/// cells') and upper plane over every triangle its cells list, referred to
/// its lower-left corner; the blocks in parallel.
fn blocks(
    index: &MeshIndex,
    items: &[u32],
    count: &[usize],
    tris: &[[[f64; 3]; 3]],
    normals: &[[f64; 3]],
) -> (usize, Vec<Bounds>, Vec<CellPlane>) {
    let bnx = index.nx.div_ceil(BLOCK);
    let bny = index.ny.div_ceil(BLOCK);
    let (bounds, planes) = (0..bnx * bny)
        .into_par_iter()
        .map(|b| {
            let (bi, bj) = (b % bnx, b / bnx);
            let cells: Vec<usize> = (bj * BLOCK..((bj + 1) * BLOCK).min(index.ny))
                .flat_map(|j| {
                    (bi * BLOCK..((bi + 1) * BLOCK).min(index.nx)).map(move |i| j * index.nx + i)
                })
                .collect();
            let all: Vec<u32> = cells
                .iter()
                .flat_map(|&k| items[count[k]..count[k + 1]].iter().copied())
                .collect();
            let corner = index.block_corner(bi, bj);
            (
                Bounds::union(cells.iter().map(|&k| &index.cells[k])),
                upper_plane(&all, corner, tris, normals),
            )
        })
        .unzip();
    (bnx, bounds, planes)
}

/// For each cell (`items[count[k]..count[k + 1]]`, sorted by rank) the
/// offsets from its start at which ranks 1, 2 and 3 begin. A cell lists a
/// triangle at most once, so its length (at most [`MAX_TRIANGLES`]) fits a
/// u32.
fn rank_offsets(items: &[u32], count: &[usize]) -> Vec<[u32; 3]> {
    (0..count.len().saturating_sub(1))
        .into_par_iter()
        .map(|k| {
            let cell = &items[count[k]..count[k + 1]];
            [1, 2, 3].map(|q| cell.partition_point(|&it| it & 3 < q) as u32)
        })
        .collect()
}

/// Each cell's box round its triangles' boxes, and their highest corner.
fn cell_bounds(items: &[u32], count: &[usize], bounds: &[Bounds]) -> Vec<Bounds> {
    (0..count.len().saturating_sub(1))
        .into_par_iter()
        .map(|k| {
            Bounds::union(
                items[count[k]..count[k + 1]]
                    .iter()
                    .map(|&it| &bounds[(it >> 2) as usize]),
            )
        })
        .collect()
}

/// Rank of a triangle's entry in a cell, from whether the cell lies right of
/// and above the triangle's first cell: 0 right only (same first row), 1 the
/// first cell itself, 2 above only (same first column), 3 both (see
/// [`MeshIndex::for_each_near`]).
fn rank(right: bool, above: bool) -> u32 {
    match (right, above) {
        (true, false) => 0,
        (false, false) => 1,
        (false, true) => 2,
        (true, true) => 3,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fixed-seed generator (reproducible failures).
    use crate::num::testing::Lcg as Rng;

    /// A random unit vector (rejection from the cube's shell 0.1 < |v| ≤ 1).
    fn unit3(g: &mut Rng) -> [f64; 3] {
        loop {
            let v = [g.range(-1.0, 1.0), g.range(-1.0, 1.0), g.range(-1.0, 1.0)];
            let l = dot(v, v).sqrt();
            if l > 0.1 && l <= 1.0 {
                return v.map(|c| c / l);
            }
        }
    }

    fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
    }

    fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
        a.map(|c| c * s)
    }

    fn lerp(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
        add(a, scale(sub(b, a), t))
    }

    /// f(P) = z − p(ρ) when P is in the footprint.
    fn f_at(c: &Cutter, p: [f64; 3], x: f64, y: f64) -> Option<f64> {
        let rho = (p[0] - x).hypot(p[1] - y);
        (rho <= c.radius).then(|| p[2] - c.profile(rho))
    }

    /// The brute-force oracle of one triangle: `lo` is the max of f over
    /// samples (a barycentric grid of 2016 points plus 2000 points on each
    /// edge), a drop no exact answer may be below; `up` is a proven upper
    /// bound from the same grid's 3844 cells: on a cell, z ≤ its highest
    /// corner and ρ ≥ (its nearest corner's ρ) − (its XY diameter), so
    /// f ≤ z_max − p(that), p being non-decreasing. The gap up − lo is the
    /// sampling density's bound.
    fn oracle(c: &Cutter, t: [[f64; 3]; 3], x: f64, y: f64) -> (Option<f64>, Option<f64>) {
        const N: usize = 62;
        const E: usize = 2000;
        let mut lo: Option<f64> = None;
        let mut up: Option<f64> = None;
        let take = |v: Option<f64>, m: &mut Option<f64>| {
            if let Some(v) = v {
                *m = Some(m.map_or(v, |w| w.max(v)));
            }
        };
        let at = |i: usize, j: usize| {
            let (u, v) = (i as f64 / N as f64, j as f64 / N as f64);
            let w = 1.0 - u - v;
            [0, 1, 2].map(|k| w * t[0][k] + u * t[1][k] + v * t[2][k])
        };
        for i in 0..=N {
            for j in 0..=N - i {
                take(f_at(c, at(i, j), x, y), &mut lo);
            }
        }
        for k in 0..3 {
            for s in 0..=E {
                let p = lerp(t[k], t[(k + 1) % 3], s as f64 / E as f64);
                take(f_at(c, p, x, y), &mut lo);
            }
        }
        let mut cell = |p: [[f64; 3]; 3]| {
            let rho = p.map(|q| (q[0] - x).hypot(q[1] - y));
            let mut diam = 0.0f64;
            for a in 0..3 {
                let b = (a + 1) % 3;
                diam = diam.max((p[a][0] - p[b][0]).hypot(p[a][1] - p[b][1]));
            }
            let near = rho[0].min(rho[1]).min(rho[2]) - diam * (1.0 + 1e-9) - 1e-12;
            if near <= c.radius {
                let zmax = p[0][2].max(p[1][2]).max(p[2][2]);
                take(Some(zmax - c.profile(near.max(0.0))), &mut up);
            }
        };
        for i in 0..N {
            for j in 0..N - i {
                cell([at(i, j), at(i + 1, j), at(i, j + 1)]);
                if i + j + 1 < N {
                    cell([at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
                }
            }
        }
        (lo, up)
    }

    fn closest_on_segment(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        let d = sub(b, a);
        let dd = dot(d, d);
        let t = if dd > 0.0 {
            (dot(sub(p, a), d) / dd).clamp(0.0, 1.0)
        } else {
            0.0
        };
        lerp(a, b, t)
    }

    /// Distance from p to the triangle (3-D).
    fn dist_to_triangle(p: [f64; 3], t: [[f64; 3]; 3]) -> f64 {
        let mut best = f64::INFINITY;
        for k in 0..3 {
            let q = closest_on_segment(p, t[k], t[(k + 1) % 3]);
            best = best.min(dot(sub(p, q), sub(p, q)).sqrt());
        }
        let n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
        let nn = dot(n, n);
        if nn > 0.0 {
            let h = dot(sub(p, t[0]), n) / nn;
            let q = sub(p, scale(n, h));
            let inside =
                (0..3).all(|k| dot(n, cross(sub(t[(k + 1) % 3], t[k]), sub(q, t[k]))) >= 0.0);
            if inside {
                best = best.min(h.abs() * nn.sqrt());
            }
        }
        best
    }

    /// The contact is a point of the triangle within the footprint, and the
    /// tip is f there: so the tip is not above the true drop. The tolerance
    /// on f allows for p's steepness near the rim (a 1e-12 mm shift of ρ).
    fn check_witness(c: &Cutter, t: [[f64; 3]; 3], x: f64, y: f64, k: Contact, what: &str) {
        let p = [k.point[0] + x, k.point[1] + y, k.point[2]];
        let d = dist_to_triangle(p, t);
        assert!(d <= 1e-9, "{what}: contact {p:?} is {d:e} off the triangle");
        let rho = (p[0] - x).hypot(p[1] - y);
        assert!(rho <= c.radius + 1e-9, "{what}: contact at ρ {rho} > r");
        let f = p[2] - c.profile(rho);
        let sens = c.profile((rho + 1e-12).min(c.radius)) - c.profile((rho - 1e-12).max(0.0));
        assert!(
            (f - k.tip).abs() <= 1e-9 + sens,
            "{what}: tip {} but f at the contact is {f}",
            k.tip
        );
    }

    fn random_cutter(g: &mut Rng, shape: usize) -> Cutter {
        let r = g.range(0.5, 6.0);
        match shape {
            0 => Cutter::flat(r),
            1 => Cutter::ball(r),
            _ => Cutter::bull(r, r * g.range(0.05, 0.95)),
        }
    }

    /// Random triangles of every kind near the origin, at the scale of `r`.
    fn random_triangle(g: &mut Rng, kind: usize, r: f64) -> [[f64; 3]; 3] {
        let pt = |g: &mut Rng, zs: f64| {
            [
                g.range(-1.6 * r, 1.6 * r),
                g.range(-1.6 * r, 1.6 * r),
                g.range(-zs, zs),
            ]
        };
        match kind {
            // general
            0 => [pt(g, r), pt(g, r), pt(g, r)],
            // horizontal
            1 => {
                let z = g.range(-r, r);
                [0, 1, 2].map(|_| {
                    let mut p = pt(g, 0.0);
                    p[2] = z;
                    p
                })
            }
            // steep: slopes up to ~100
            2 => [pt(g, 80.0 * r), pt(g, 80.0 * r), pt(g, 80.0 * r)],
            // vertical-ish: a wall tilted by tan θ ∈ [100, 1000]
            3 => {
                let a = g.range(0.0, std::f64::consts::TAU);
                let (e, nrm) = ([a.cos(), a.sin()], [-a.sin(), a.cos()]);
                let cot = 1.0 / g.range(100.0, 1000.0);
                let base = [g.range(-r, r), g.range(-r, r)];
                let off = g.range(-r, r);
                [0, 1, 2].map(|_| {
                    let u = g.range(-1.5 * r, 1.5 * r);
                    let w = g.range(-2.0 * r, 2.0 * r);
                    let s = off + w * cot;
                    [
                        base[0] + u * e[0] + s * nrm[0],
                        base[1] + u * e[1] + s * nrm[1],
                        w,
                    ]
                })
            }
            // exactly vertical (n_z computes as 0)
            4 => {
                let (v0, v1) = (pt(g, r), pt(g, r));
                let v2 = [v1[0], v1[1], v1[2] + g.range(-2.0 * r, 2.0 * r)];
                [v0, v1, v2]
            }
            // cap sliver: three nearly collinear points
            5 => {
                let (v0, v1) = (pt(g, r), pt(g, r));
                let l = dot(sub(v1, v0), sub(v1, v0)).sqrt();
                let m = lerp(v0, v1, g.range(0.1, 0.9));
                let v2 = add(m, scale(unit3(g), l * 10f64.powf(g.range(-7.0, -3.0))));
                [v0, v1, v2]
            }
            // needle: one very short edge
            6 => {
                let v0 = pt(g, r);
                let v1 = add(v0, scale(unit3(g), r * 10f64.powf(g.range(-7.0, -3.0))));
                [v0, v1, pt(g, r)]
            }
            // degenerate: zero area (collinear, a repeated corner, a point)
            _ => {
                let (v0, v1) = (pt(g, r), pt(g, r));
                match g.next() {
                    q if q < 0.4 => [v0, v1, lerp(v0, v1, 0.5)],
                    q if q < 0.8 => [v0, v1, v0],
                    _ => [v0, v0, v0],
                }
            }
        }
    }

    const KINDS: usize = 8;

    #[test]
    fn dropcutter_matches_the_brute_force_oracle_on_random_triangles() {
        let mut g = Rng(0xd20c);
        let mut cases = [0usize; 3];
        let mut max_gap = [0.0f64; 3];
        for case in 0..3000 {
            let shape = case % 3;
            let kind = (case / 3) % KINDS;
            let c = random_cutter(&mut g, shape);
            let r = c.radius;
            let tri = random_triangle(&mut g, kind, r);
            // A third of the axes near a corner, the rest anywhere nearby.
            let (x, y) = if g.next() < 0.33 {
                let v = tri[(g.next() * 3.0) as usize % 3];
                (v[0] + g.range(-0.5, 0.5) * r, v[1] + g.range(-0.5, 0.5) * r)
            } else {
                (g.range(-2.0 * r, 2.0 * r), g.range(-2.0 * r, 2.0 * r))
            };
            let what = format!("case {case}: {c:?}, kind {kind}, {tri:?} at ({x}, {y})");
            let t = Tri::new(tri);
            let got = c.drop_triangle(&t, x, y);
            let (lo, up) = oracle(&c, tri, x, y);
            if let Some(lo) = lo {
                let k = got.unwrap_or_else(|| panic!("{what}: None, oracle {lo}"));
                assert!(k.tip >= lo - 1e-9, "{what}: {} gouges, oracle {lo}", k.tip);
                let up = up.unwrap();
                assert!(k.tip <= up + 1e-9, "{what}: {} above the bound {up}", k.tip);
                check_witness(&c, tri, x, y, k, &what);
                cases[shape] += 1;
                if kind < 2 {
                    max_gap[shape] = max_gap[shape].max((k.tip - lo) / r);
                }
            } else if let Some(k) = got {
                // The footprint meets the triangle between the samples.
                check_witness(&c, tri, x, y, k, &what);
            }
        }
        // Most cases must have met the triangle, or the test tests little.
        assert!(cases.iter().all(|&n| n > 500), "{cases:?}");
        // On the general and horizontal triangles (slopes ≲ 1), sampled at
        // ~r/20, the exact drop lies above the samples by a few hundredths of
        // r at most (steep ones are sampled far more coarsely in z; for them
        // `up` and the witness bound it from above).
        assert!(max_gap.iter().all(|&g| g < 0.05), "{max_gap:?}");
    }

    /// Every bull-nose edge search proves its error ≤ EDGE_TOL within the
    /// step cap, and the ball's closed form agrees with the search.
    #[test]
    fn dropcutter_edge_search_is_bounded_and_agrees_with_the_ball_closed_form() {
        let mut g = Rng(0xed9e);
        let mut searched = 0;
        let mut max_steps = 0;
        for case in 0..20000 {
            let shape = 1 + case % 2;
            let c = random_cutter(&mut g, shape);
            let r = c.radius;
            let tri = random_triangle(&mut g, [0, 2, 3][case % 3], r);
            let (a, b) = (tri[0], tri[1]);
            let Some(s) = EdgeFrame::new(a, b, r) else {
                continue;
            };
            let (k, bound, steps) = c.edge_search(&s);
            assert!(bound <= EDGE_TOL, "case {case}: bound {bound:e}");
            assert!(steps <= EDGE_MAX_ITER);
            max_steps = max_steps.max(steps);
            searched += 1;
            if shape == 1 {
                let closed = c.edge(a, b, f64::NEG_INFINITY).unwrap();
                assert!(
                    (closed.tip - k.tip).abs() <= 1e-9,
                    "case {case}: closed form {} search {}",
                    closed.tip,
                    k.tip
                );
            }
        }
        assert!(searched > 5000, "{searched}");
        assert!(max_steps <= 80, "{max_steps}");
    }

    fn one(t: [[f64; 3]; 3]) -> MeshIndex {
        MeshIndex::new(vec![t], 0.0)
    }

    const BIG: [[f64; 3]; 3] = [
        [-100.0, -100.0, 3.0],
        [100.0, -100.0, 3.0],
        [0.0, 100.0, 3.0],
    ];

    #[test]
    fn dropcutter_flat_cutter_on_a_horizontal_triangle() {
        let m = one(BIG);
        // Axis over the triangle: every shape rests on its flat part or tip.
        for c in [Cutter::flat(2.0), Cutter::ball(2.0), Cutter::bull(2.0, 0.5)] {
            assert_eq!(c.drop(&m, 0.0, 0.0), Some(3.0));
            assert_eq!(c.drop(&m, 10.0, -99.0), Some(3.0));
        }
        // Axis outside the triangle, the flat bottom still over it: 3.
        let flat = Cutter::flat(2.0);
        for y in [-101.0, -101.5, -101.999] {
            assert_eq!(flat.drop(&m, 0.0, y), Some(3.0));
        }
        let bull = Cutter::bull(2.0, 0.5);
        assert_eq!(bull.drop(&m, 0.0, -101.0), Some(3.0));
        // Ball with its axis 1 mm outside the edge y = −100: the edge touches
        // at ρ = 1, tip = 3 − (2 − √3).
        let ball = Cutter::ball(2.0);
        let t = ball.drop(&m, 0.0, -101.0).unwrap();
        assert!((t - (3.0 - 2.0 + 3f64.sqrt())).abs() < 1e-12, "{t}");
        // Footprint clear of the triangle.
        assert_eq!(flat.drop(&m, 0.0, -102.5), None);
        assert_eq!(flat.drop(&m, 500.0, 0.0), None);
    }

    /// A plane z = x·tan θ: a ball of radius r centred at distance r from it
    /// has its centre at x₀ tan θ + r/cos θ, so the tip is
    /// x₀ tan θ + r(1/cos θ − 1); a bull nose touches at ρ = a + rc sin θ
    /// uphill, tip x₀ tan θ + a tan θ + rc(1/cos θ − 1); a flat one at its rim,
    /// x₀ tan θ + r tan θ.
    #[test]
    fn dropcutter_on_a_tilted_plane() {
        for deg in [0.0f64, 5.0, 30.0, 45.0, 60.0, 85.0, 89.0] {
            let th = deg.to_radians();
            let tan = th.tan();
            let plane = |x: f64, y: f64| [x, y, x * tan];
            let m = one([plane(-50.0, -50.0), plane(50.0, -50.0), plane(0.0, 50.0)]);
            let (r, rc) = (3.0, 1.0);
            let a = r - rc;
            for x0 in [-2.0, 0.0, 1.5] {
                let z0 = x0 * tan;
                let ball = Cutter::ball(r).drop(&m, x0, 0.5).unwrap();
                let want = z0 + r * (1.0 / th.cos() - 1.0);
                assert!(
                    (ball - want).abs() < 1e-9 * (1.0 + tan),
                    "{deg}°: {ball} vs {want}"
                );
                let bull = Cutter::bull(r, rc).drop(&m, x0, 0.5).unwrap();
                let want = z0 + a * tan + rc * (1.0 / th.cos() - 1.0);
                assert!(
                    (bull - want).abs() < 1e-9 * (1.0 + tan),
                    "{deg}°: {bull} vs {want}"
                );
                let flat = Cutter::flat(r).drop(&m, x0, 0.5).unwrap();
                let want = z0 + r * tan;
                assert!(
                    (flat - want).abs() < 1e-9 * (1.0 + tan),
                    "{deg}°: {flat} vs {want}"
                );
            }
        }
    }

    /// A spike: the apex (0, 0, 5) with the triangle falling away at slope
    /// ≥ 100, so the cutter rests on the apex: tip = 5 − p(ρ).
    #[test]
    fn dropcutter_over_a_single_vertex() {
        let spike = [[0.0, 0.0, 5.0], [-3.0, 4.0, -500.0], [3.0, 4.0, -500.0]];
        let point = [[1.0, 1.0, 5.0]; 3];
        for c in [Cutter::flat(2.0), Cutter::ball(2.0), Cutter::bull(2.0, 0.7)] {
            for d in [0.0, 0.3, 1.0, 1.3, 1.9, 2.0] {
                let want = 5.0 - c.profile(d);
                // From below the apex, so the spike falls away from the axis.
                let got = c.drop(&one(spike), 0.0, -d).unwrap();
                assert!((got - want).abs() < 1e-12, "{c:?} d {d}: {got} vs {want}");
                // A triangle that is a single point.
                let got = c.drop(&one(point), 1.0 + d * 0.6, 1.0 - d * 0.8).unwrap();
                assert!((got - want).abs() < 1e-12, "{c:?} d {d}: {got} vs {want}");
            }
            assert_eq!(c.drop(&one(point), 1.0, 3.01), None);
        }
        // The ball's value by hand: 5 − 2 + √(4 − 1.3²).
        let got = Cutter::ball(2.0).drop(&one(spike), 0.0, -1.3).unwrap();
        assert!((got - (3.0 + (4.0f64 - 1.69).sqrt())).abs() < 1e-12);
    }

    /// A horizontal edge y = 1, z = 2, the triangle falling steeply away from
    /// the axis: the cutter rests on the edge at ρ = 1, tip = 2 − p(1), ball
    /// 2 − 3 + √(9 − 1).
    #[test]
    fn dropcutter_across_a_horizontal_edge() {
        let t = [[-20.0, 1.0, 2.0], [20.0, 1.0, 2.0], [0.0, 3.0, -400.0]];
        let m = one(t);
        let ball = Cutter::ball(3.0);
        for x in [-5.0, 0.0, 7.5] {
            let got = ball.drop(&m, x, 0.0).unwrap();
            assert!((got - (8f64.sqrt() - 1.0)).abs() < 1e-12, "{got}");
            for c in [
                Cutter::flat(3.0),
                Cutter::bull(3.0, 2.5),
                Cutter::bull(3.0, 1.0),
            ] {
                let got = c.drop(&m, x, 0.0).unwrap();
                assert!((got - (2.0 - c.profile(1.0))).abs() < 1e-9, "{c:?}: {got}");
            }
        }
    }

    /// A hemisphere of radius R meshed on a latitude–longitude grid (corners on
    /// the sphere). The mesh lies inside the sphere and outside the ball of
    /// radius R_in (the smallest distance from the centre to a triangle's
    /// plane), so the drop lies between the analytic offsets of those two
    /// spheres: with the axis at distance d, F(R′) = R′ for d ≤ a, else
    /// √((R′ + rc)² − (d − a)²) − rc (the corner circle's centre is R′ + rc
    /// from the sphere's centre).
    #[test]
    fn dropcutter_on_a_meshed_hemisphere() {
        let big_r = 10.0;
        let (nt, np) = (90usize, 180usize);
        let vtx = |i: usize, j: usize| {
            let th = std::f64::consts::FRAC_PI_2 * i as f64 / nt as f64;
            let ph = std::f64::consts::TAU * j as f64 / np as f64;
            [
                big_r * th.sin() * ph.cos(),
                big_r * th.sin() * ph.sin(),
                big_r * th.cos(),
            ]
        };
        let mut tris = Vec::new();
        for i in 0..nt {
            for j in 0..np {
                let (a, b) = (vtx(i, j), vtx(i, j + 1));
                let (c, d) = (vtx(i + 1, j), vtx(i + 1, j + 1));
                if i > 0 {
                    tris.push([a, c, b]);
                }
                tris.push([b, c, d]);
            }
        }
        let r_in = tris
            .iter()
            .map(|t| {
                let n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
                dot(n, t[0]).abs() / dot(n, n).sqrt()
            })
            .fold(f64::INFINITY, f64::min);
        assert!(big_r - r_in < 2e-3 && big_r - r_in > 0.0, "{r_in}");
        let m = MeshIndex::new(tris, 1.0);
        let mut g = Rng(0x5e5e);
        for c in [
            Cutter::flat(2.0),
            Cutter::ball(3.175 / 2.0),
            Cutter::bull(3.0, 1.0),
        ] {
            let a = c.flat_radius();
            let offset = |rr: f64, d: f64| {
                if d <= a {
                    rr
                } else {
                    ((rr + c.corner).powi(2) - (d - a).powi(2)).sqrt() - c.corner
                }
            };
            for k in 0..300 {
                let d = big_r * k as f64 / 300.0;
                let phi = g.range(0.0, std::f64::consts::TAU);
                let got = c.drop(&m, d * phi.cos(), d * phi.sin()).unwrap();
                let (lo, hi) = (offset(r_in, d), offset(big_r, d));
                assert!(
                    got >= lo - 1e-9 && got <= hi + 1e-9,
                    "{c:?} d {d}: {got} not in [{lo}, {hi}]"
                );
            }
        }
    }

    /// A small random terrain with slivers, walls and a few big triangles.
    fn random_mesh(g: &mut Rng, n: usize) -> Vec<[[f64; 3]; 3]> {
        let h = 1.0;
        let z: Vec<f64> = (0..(n + 1) * (n + 1)).map(|_| g.range(-0.6, 0.6)).collect();
        let p = |i: usize, j: usize| [i as f64 * h, j as f64 * h, z[j * (n + 1) + i]];
        let mut tris = Vec::new();
        for j in 0..n {
            for i in 0..n {
                tris.push([p(i, j), p(i + 1, j), p(i + 1, j + 1)]);
                tris.push([p(i, j), p(i + 1, j + 1), p(i, j + 1)]);
            }
        }
        for k in 0..40 {
            let t = random_triangle(g, k % KINDS, 2.0);
            tris.push(t.map(|v| [v[0] + n as f64 / 2.0, v[1] + n as f64 / 2.0, v[2]]));
        }
        tris
    }

    /// The grid (any cell size, coarsened or not) finds exactly what a scan
    /// of every triangle finds: the same maximum, to rounding.
    #[test]
    fn dropcutter_mesh_index_equals_a_scan_of_every_triangle() {
        let mut g = Rng(0x1dec);
        let tris = random_mesh(&mut g, 16);
        let all: Vec<Tri> = tris.iter().map(|&t| Tri::new(t)).collect();
        for cell in [0.0, f64::NAN, 1e-9, 0.3, 1.0, 2.5, 1e6] {
            let m = MeshIndex::new(tris.clone(), cell);
            assert_eq!(m.len(), tris.len());
            assert!(m.nx * m.ny <= MAX_CELLS);
            for shape in 0..3 {
                let c = random_cutter(&mut g, shape);
                for _ in 0..300 {
                    let (x, y) = (g.range(-3.0, 19.0), g.range(-3.0, 19.0));
                    let scan = all
                        .iter()
                        .filter_map(|t| c.drop_triangle(t, x, y))
                        .map(|k| k.tip)
                        .fold(None, |m: Option<f64>, t| Some(m.map_or(t, |m| m.max(t))));
                    let got = c.drop(&m, x, y);
                    // A shared edge, tested from both its triangles in opposite
                    // directions, may round differently: equal to 1e-12.
                    let same = match (got, scan) {
                        (Some(a), Some(b)) => (a - b).abs() <= 1e-12,
                        (a, b) => a == b,
                    };
                    assert!(
                        same,
                        "cell {cell}, {c:?} at ({x}, {y}): {got:?} vs {scan:?}"
                    );
                }
            }
        }
    }

    /// The single-precision bounds are rounded outwards: f32_down(x) ≤ x ≤
    /// f32_up(x), each the nearest f32 on its side (exact when x is one).
    #[test]
    fn dropcutter_cell_and_block_planes_lie_over_their_triangles_and_prune() {
        // Every corner of every triangle a cell lists lies on or under the
        // cell's upper plane, on a random mesh (rough, with loose
        // triangles) and on a smooth tilted one.
        let mut g = Rng(0x9a1e);
        let tilted: Vec<[[f64; 3]; 3]> = {
            let n = 40;
            let p = |i: usize, j: usize| {
                let (x, y) = (i as f64 * 0.1, j as f64 * 0.1);
                [x, y, 0.7 * x - 0.3 * y + 0.05 * (x * x + y * y)]
            };
            (0..n * n)
                .flat_map(|k| {
                    let (i, j) = (k % n, k / n);
                    [
                        [p(i, j), p(i + 1, j), p(i + 1, j + 1)],
                        [p(i, j), p(i + 1, j + 1), p(i, j + 1)],
                    ]
                })
                .collect()
        };
        for (tris, cell) in [(random_mesh(&mut g, 30), 1.3), (tilted.clone(), 0.4)] {
            let m = MeshIndex::new(tris, cell);
            for k in 0..m.nx * m.ny {
                let (pl, c) = (m.planes[k], m.cell_corner(k));
                let (gx, gy) = (f64::from(pl.g[0]), f64::from(pl.g[1]));
                // ... and under its block's plane, in its block's bounds.
                let (i, j) = (k % m.nx, k / m.nx);
                let b = (j / BLOCK) * m.bnx + i / BLOCK;
                let bc = m.block_corner(i / BLOCK, j / BLOCK);
                let bp = m.block_planes[b];
                let (bx, by) = (f64::from(bp.g[0]), f64::from(bp.g[1]));
                let (cb, bb) = (m.cells[k], m.blocks[b]);
                if cb.zmax > f32::NEG_INFINITY {
                    assert!(bb.zmax >= cb.zmax && bb.lo[0] <= cb.lo[0] && bb.lo[1] <= cb.lo[1]);
                    assert!(bb.hi[0] >= cb.hi[0] && bb.hi[1] >= cb.hi[1], "block {b}");
                }
                for &it in &m.items[m.start[k]..m.start[k + 1]] {
                    for v in m.tris[(it >> 2) as usize] {
                        let over = f64::from(pl.a) + gx * (v[0] - c[0]) + gy * (v[1] - c[1]);
                        assert!(v[2] <= over + 1e-12, "cell {k}: {v:?} above {over}");
                        let over = f64::from(bp.a) + bx * (v[0] - bc[0]) + by * (v[1] - bc[1]);
                        assert!(v[2] <= over + 1e-12, "block {b}: {v:?} above {over}");
                    }
                }
            }
        }
        // On the smooth mesh a ball resting on it leaves most cells within
        // its reach below the floor by their planes, though their highest
        // corners stand above it.
        let m = MeshIndex::new(tilted, 0.4);
        let c = Cutter::ball(1.5875);
        let (x, y) = (2.0, 2.0);
        let floor = c.drop(&m, x, y).unwrap();
        let range = m.cell_range(x - c.radius, x + c.radius, y - c.radius, y + c.radius);
        let (i0, i1, j0, j1) = range.unwrap();
        let (mut by_top, mut by_plane) = (0, 0);
        for j in j0..=j1 {
            for i in i0..=i1 {
                let k = j * m.nx + i;
                if m.cells[k].top() > floor {
                    by_top += 1;
                    let plane = (&m.planes[k], m.cell_corner(k));
                    by_plane += usize::from(!c.plane_may_beat(plane, [x, y], floor));
                }
            }
        }
        assert!(
            by_top >= 10 && 2 * by_plane > by_top,
            "{by_plane} of {by_top}"
        );
    }

    #[test]
    fn dropcutter_segment_dist2_is_the_least_over_the_segment() {
        // Against the distance to 20 001 points along the segment, and never
        // above it (the drop uses it as a lower bound).
        let mut g = Rng(0x5e9);
        for k in 0..2000 {
            let mut p = || [g.range(-3.0, 3.0), g.range(-3.0, 3.0), g.range(-1.0, 1.0)];
            let a = p();
            let b = if k % 50 == 0 { a } else { p() };
            let d2 = segment_dist2(a, b);
            let sampled = (0..=20_000)
                .map(|i| {
                    let t = i as f64 / 20_000.0;
                    let (x, y) = (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]));
                    x * x + y * y
                })
                .fold(f64::INFINITY, f64::min);
            assert!(
                d2 <= sampled * (1.0 + 1e-12) + 1e-300,
                "{a:?} {b:?}: {d2} > {sampled}"
            );
            assert!(sampled - d2 <= 1e-6, "{a:?} {b:?}: {d2} vs {sampled}");
        }
    }

    #[test]
    fn dropcutter_bounds_round_outwards() {
        let mut g = Rng(0xf32);
        let mut xs = vec![0.0, -0.0, 1e-50, -1e-50, 1e300, -1e300, 0.1, -0.1, 1.0];
        xs.extend((0..20000).map(|_| g.range(-1.0, 1.0) * 10f64.powf(g.range(-8.0, 6.0))));
        for x in xs {
            let (lo, hi) = (f32_down(x), f32_up(x));
            assert!(f64::from(lo) <= x && x <= f64::from(hi), "{x}: {lo} {hi}");
            if (x as f32) as f64 == x {
                assert!(lo as f64 == x && hi as f64 == x, "{x}");
            } else {
                // No f32 strictly between: they are neighbours.
                let step = |f: f32| {
                    if f.is_sign_positive() {
                        f.to_bits() as i64
                    } else {
                        -((-f).to_bits() as i64)
                    }
                };
                assert!(step(hi) - step(lo) <= 1, "{x}: {lo} {hi}");
            }
        }
    }

    /// The drop against one triangle with no bound at all: every vertex,
    /// the facet contact when it lies inside, else every edge from −∞.
    fn unpruned(c: &Cutter, t: &Tri, x: f64, y: f64) -> Option<f64> {
        let rel = t.relative([x, y]);
        let mut tips: Vec<f64> = rel
            .iter()
            .filter_map(|&v| c.vertex(v))
            .map(|k| k.tip)
            .collect();
        match c.plane_contact(t, &rel) {
            Some(k) if c.inside(t, &rel, k.point) => tips.push(k.tip),
            _ => tips.extend((0..3).filter_map(|i| {
                c.edge(rel[i], rel[(i + 1) % 3], f64::NEG_INFINITY)
                    .map(|k| k.tip)
            })),
        }
        tips.into_iter().reduce(f64::max)
    }

    /// The pruned search (grid bounds, plane bounds, the cells ring by ring,
    /// each cell's triangles by highest corner, the edge pass highest plane
    /// first) equals the max over every triangle of [`unpruned`]: on random
    /// terrain-like soups meshed finely against the tool as the finisher's (0.1 mm
    /// against r ≈ 1.6) and coarsely, with slivers and walls, for drop,
    /// drop_above at levels round the answer, and drop_hinted.
    #[test]
    fn dropcutter_pruned_drop_equals_the_brute_force_drop_over_all_triangles() {
        let mut g = Rng(0xb20f);
        let (mut some, mut none, mut exact, mut total) = (0, 0, 0, 0);
        for (n, h, cell) in [(40usize, 0.1, 0.4), (16, 1.0, 1.0), (60, 0.1, 0.1)] {
            let mut tris = random_mesh(&mut g, n);
            // The terrain at spacing h, the odd triangles at the same scale,
            // each corner's z stretched on its own (a soup: neighbours need
            // not share corners).
            for t in tris.iter_mut() {
                *t = t.map(|v| [v[0] * h, v[1] * h, v[2] * h * g.range(0.5, 3.0)]);
            }
            let all: Vec<Tri> = tris.iter().map(|&t| Tri::new(t)).collect();
            let m = MeshIndex::new(tris, cell);
            let span = n as f64 * h;
            for shape in 0..3 {
                let c = match shape {
                    0 => Cutter::ball(g.range(0.5, 2.0) * span / 8.0),
                    1 => Cutter::bull(span / 8.0, span / 8.0 * g.range(0.1, 0.9)),
                    _ => Cutter::flat(g.range(0.5, 2.0) * span / 8.0),
                };
                for _ in 0..300 {
                    let (x, y) = (g.range(-0.4, 1.4) * span, g.range(-0.4, 1.4) * span);
                    let brute = all
                        .iter()
                        .filter_map(|t| unpruned(&c, t, x, y))
                        .reduce(f64::max);
                    let got = c.drop(&m, x, y);
                    total += 1;
                    match (got, brute) {
                        (Some(a), Some(b)) => {
                            // Exact but for a shared edge tested from its two
                            // triangles in opposite directions (an ulp).
                            assert!((a - b).abs() <= 1e-12, "{c:?} ({x}, {y}): {a} vs {b}");
                            exact += usize::from(a == b);
                            some += 1;
                        }
                        (a, b) => {
                            assert_eq!(a, b, "{c:?} ({x}, {y})");
                            none += 1;
                        }
                    }
                    let t = got.unwrap_or(0.0);
                    for level in [t - 0.05 * span, t - 1e-9, t, t + 1e-3 * span] {
                        assert_above_and_hinted(&c, &m, (x, y), level, got);
                    }
                }
            }
        }
        // Both answers occur, and nearly every drop is exact to the bit (97 %
        // when written; the rest differ by an ulp or so, where an edge's bound
        // and its value round apart, as the scan's test allows).
        assert!(some > 1000 && none > 500, "{some} {none}");
        assert!(
            exact as f64 > 0.95 * some as f64,
            "{exact} of {some} of {total}"
        );
    }

    /// The root-free skip test keeps everything the bound z_max − p(ρ) >
    /// floor keeps (ρ measured exactly, for ball, bull and flat cutters, at
    /// distances and heights spread round the rim and the corner), and
    /// still skips most of what that bound skips.
    #[test]
    fn dropcutter_may_beat_keeps_whatever_the_bound_keeps() {
        let mut g = Rng(11);
        let (mut kept, mut skipped, mut bound_skips) = (0, 0, 0);
        for shape in 0..3 {
            let c = [
                Cutter::ball(1.5875),
                Cutter::bull(3.0, 1.0),
                Cutter::flat(2.0),
            ][shape];
            for _ in 0..200_000 {
                let rho = g.range(0.0, 1.05) * c.radius;
                let zmax = g.range(-1.0, 1.0);
                let floor = zmax - g.range(-0.2, 1.2) * c.corner.max(0.1);
                let exact = zmax - c.profile(rho) > floor;
                let fast = c.may_beat(zmax, rho * rho, floor);
                assert!(fast || !exact, "{shape}: ρ {rho} z {zmax} floor {floor}");
                kept += usize::from(fast);
                bound_skips += usize::from(!exact);
                skipped += usize::from(!fast);
            }
        }
        assert!(kept > 0 && bound_skips > 100_000);
        assert!(
            skipped as f64 > 0.99 * bound_skips as f64,
            "{skipped} of {bound_skips}"
        );
    }

    /// At (x, y): the drop above `level` is `drop` when that lies above the
    /// level, else nothing, and the drop hinted with `level` is `drop`.
    fn assert_above_and_hinted(
        c: &Cutter,
        m: &MeshIndex,
        (x, y): (f64, f64),
        level: f64,
        drop: Option<f64>,
    ) {
        let want = drop.filter(|&z| z > level);
        assert_eq!(
            c.drop_above(m, x, y, level),
            want,
            "{c:?} ({x}, {y}) {level}"
        );
        assert_eq!(
            c.drop_hinted(m, x, y, level),
            drop,
            "{c:?} ({x}, {y}) {level}"
        );
    }

    /// A drop above a level is the drop when it lies above it, to the last
    /// bit, and nothing otherwise; a hinted drop is the drop whatever the
    /// hint (under, at, over the answer, or not finite).
    #[test]
    fn dropcutter_drop_above_and_hinted_equal_the_plain_drop() {
        let mut g = Rng(0xab0e);
        let tris = random_mesh(&mut g, 12);
        let m = MeshIndex::new(tris, 1.0);
        let mut above = 0;
        for shape in 0..3 {
            let c = random_cutter(&mut g, shape);
            for _ in 0..300 {
                let (x, y) = (g.range(-3.0, 15.0), g.range(-3.0, 15.0));
                let d = c.drop(&m, x, y);
                let t = d.unwrap_or(0.0);
                for level in [
                    t - 0.3,
                    t - 1e-9,
                    t,
                    t + 1e-9,
                    t + 0.5,
                    f64::NEG_INFINITY,
                    f64::INFINITY,
                ] {
                    above += usize::from(d.is_some_and(|z| z > level));
                    assert_above_and_hinted(&c, &m, (x, y), level, d);
                }
                assert_eq!(c.drop_above(&m, x, y, f64::NAN), None);
                assert_eq!(c.drop_hinted(&m, x, y, f64::NAN), d);
            }
        }
        // Both answers occur: the test is not all "None" or all "Some".
        assert!(above > 1000 && above < 5000, "{above}");
    }

    #[test]
    fn dropcutter_translating_mesh_and_axis_translates_the_result() {
        let mut g = Rng(0x7a45);
        let tris = random_mesh(&mut g, 12);
        let (tx, ty, tz) = (1234.5, -678.25, 42.125);
        let moved: Vec<_> = tris
            .iter()
            .map(|t| t.map(|v| [v[0] + tx, v[1] + ty, v[2] + tz]))
            .collect();
        let (m0, m1) = (MeshIndex::new(tris, 1.5), MeshIndex::new(moved, 1.7));
        for shape in 0..3 {
            let c = random_cutter(&mut g, shape);
            for _ in 0..500 {
                let (x, y) = (g.range(-2.0, 14.0), g.range(-2.0, 14.0));
                let a = c.drop(&m0, x, y);
                let b = c.drop(&m1, x + tx, y + ty);
                match (a, b) {
                    (Some(a), Some(b)) => {
                        assert!((b - tz - a).abs() < 1e-9, "{c:?} ({x}, {y}): {a} vs {b}")
                    }
                    (None, None) => {}
                    _ => panic!("{c:?} ({x}, {y}): {a:?} vs {b:?}"),
                }
            }
        }
    }

    #[test]
    fn dropcutter_drop_many_is_drop_at_each_point() {
        let mut g = Rng(0x3a11);
        let m = MeshIndex::new(random_mesh(&mut g, 10), 0.0);
        let c = Cutter::bull(1.5, 0.5);
        let pts: Vec<(f64, f64)> = (0..400)
            .map(|_| (g.range(-3.0, 13.0), g.range(-3.0, 13.0)))
            .collect();
        let many = c.drop_many(&m, &pts);
        assert_eq!(many.len(), pts.len());
        for (k, &(x, y)) in pts.iter().enumerate() {
            assert_eq!(many[k], c.drop(&m, x, y));
        }
        assert!(many.iter().any(|d| d.is_none()) && many.iter().any(|d| d.is_some()));
    }

    #[test]
    fn dropcutter_bad_input_gives_none_not_a_panic() {
        let mut tris = vec![BIG];
        tris.push([[f64::NAN, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        let m = MeshIndex::new(tris, 1e-30);
        assert_eq!((m.len(), m.skipped()), (1, 1));
        assert!(m.nx * m.ny <= MAX_CELLS, "{} × {}", m.nx, m.ny);
        for c in [
            Cutter::flat(0.0),
            Cutter::bull(1.0, 2.0),
            Cutter::ball(f64::NAN),
        ] {
            assert!(c.validate().is_err());
            assert_eq!(c.drop(&m, 0.0, 0.0), None);
        }
        let c = Cutter::ball(1.0);
        assert!(c.validate().is_ok());
        assert_eq!(c.drop(&m, f64::NAN, 0.0), None);
        assert_eq!(c.drop(&m, 0.0, f64::INFINITY), None);
        assert_eq!(c.drop(&MeshIndex::new(Vec::new(), 1.0), 0.0, 0.0), None);
        // A huge radius over the whole mesh still works.
        assert_eq!(Cutter::flat(1e12).drop(&m, 0.0, 0.0), Some(3.0));
    }
}
