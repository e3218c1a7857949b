//! The top envelope of the solid over a rectangle, as a height field a
//! 3-axis mill can cut: h(x, y) = max(base, highest z ≤ `start` with
//! T₁(x, y, z) ≤ 0), the part being the block under h.
//!
//! Direct rays ([`super::Envelope`]) cost 50–90 exact T₁ evaluations each;
//! a job samples h on a 0.2 mm grid (10⁵ rays). Here:
//!
//! 1. T₁ is the [`FastField`] (the box part interpolated, the loads exact).
//! 2. A coarse grid of full rays, `coarse` mm apart, marches down from
//!    `start` every `step` and brackets the first sign change, then regula
//!    falsi (`field::isolines::root_in_unit`) finds the zero.
//! 3. h anywhere else starts from the largest height of its cell's four
//!    coarse corners that hit: it marches down (T₁ > 0 there) or up
//!    (T₁ ≤ 0) every `step` to the first sign change, then the same root. A
//!    cell none of whose corners hit but with a hit within one more coarse
//!    ring marches the full ray; farther from any hit, h = base.
//!
//! So h is a zero of the fast T₁ to about 1e-12 of a step wherever it is
//! above base. What it can miss: a piece of the solid thinner than `step` in
//! z, or whose shadow falls between coarse nodes more than one cell from any
//! hit (narrower than `coarse`), or a second layer above the first crossing
//! found from a cell's start. The test checks h against direct rays on the
//! exact field.

use super::error::{invalid, PolyError};
use super::fast::FastField;
use super::fault::PolyFault;
use crate::field::isolines::root_in_unit;
use nalgebra::Vector3;

/// |T₁| below which a point counts as on the zero (root_in_unit's own
/// stopping value).
const ZERO: f64 = 1e-12;

/// Most coarse rays.
pub(crate) const MAX_COARSE: usize = 1_000_000;

/// The rectangle and the ray settings of a relief, mm (the points' unit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReliefSpec {
    /// Lower-left corner of the rectangle.
    pub origin: [f64; 2],
    /// Its size [X, Y].
    pub size: [f64; 2],
    /// The lowest height: h = base where the solid is below it or absent.
    pub base: f64,
    /// Where the rays start (above the solid).
    pub start: f64,
    /// Marching step along a ray (> 0).
    pub step: f64,
    /// Coarse grid spacing (> 0).
    pub coarse: f64,
}

/// A relief: its spec, the fast field and the coarse rays.
#[derive(Debug, Clone)]
pub struct Relief {
    spec: ReliefSpec,
    field: FastField,
    nx: usize,
    ny: usize,
    hx: f64,
    hy: f64,
    /// The coarse rays' heights, `None` where no solid is above base.
    coarse: Vec<Option<f64>>,
}

impl Relief {
    /// Samples the coarse rays over `field`'s region. Errors: a step or
    /// spacing not finite and > 0, or too many rays (`shape.size`), the
    /// solid reaching `start` (`shape.box`: raise the box top).
    pub fn new(field: FastField, spec: ReliefSpec) -> Result<Self, PolyError> {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        if !(ok(spec.step) && ok(spec.coarse) && spec.start > spec.base) {
            return Err(invalid("shape.size", PolyFault::RaySettings));
        }
        let [sx, sy] = spec.size;
        let nx = ((sx / spec.coarse).ceil().max(1.0)) as usize + 1;
        let ny = ((sy / spec.coarse).ceil().max(1.0)) as usize + 1;
        if (nx as f64) * (ny as f64) > MAX_COARSE as f64
            || (spec.start - spec.base) / spec.step > 1e5
        {
            return Err(invalid("shape.size", PolyFault::TooManyRays));
        }
        let (hx, hy) = (sx / (nx - 1) as f64, sy / (ny - 1) as f64);
        let mut r = Relief {
            spec,
            field,
            nx,
            ny,
            hx,
            hy,
            coarse: Vec::new(),
        };
        use rayon::prelude::*;
        let rays: Vec<(Option<f64>, bool)> = (0..nx * ny)
            .into_par_iter()
            .map(|k| {
                let (x, y) = ((k % nx) as f64 * hx, (k / nx) as f64 * hy);
                let top = r.t(x, y, spec.start);
                (r.full_ray(x, y), top <= 0.0)
            })
            .collect();
        if let Some(k) = rays.iter().position(|r| r.1) {
            return Err(invalid(
                "shape.box",
                PolyFault::ReachesStart {
                    z: spec.start,
                    x: spec.origin[0] + (k % nx) as f64 * hx,
                    y: spec.origin[1] + (k / nx) as f64 * hy,
                },
            ));
        }
        r.coarse = rays.into_iter().map(|r| r.0).collect();
        Ok(r)
    }

    /// T₁ at (x, y) relative to the origin, height z.
    fn t(&self, x: f64, y: f64, z: f64) -> f64 {
        let o = self.spec.origin;
        self.field.value(Vector3::new(o[0] + x, o[1] + y, z))
    }

    /// The zero of T₁ between z_in (T₁ ≤ 0) and z_out (T₁ > 0).
    fn root(&self, x: f64, y: f64, (z_in, f_in): (f64, f64), (z_out, f_out): (f64, f64)) -> f64 {
        // An end already on the zero (as at a coarse node, whose own root a
        // cell's search starts from): root_in_unit takes a 0 for the sign
        // of the other side.
        if f_in.abs() < ZERO {
            return z_in;
        }
        let t = root_in_unit(f_in, f_out, &|t| self.t(x, y, z_in + t * (z_out - z_in)));
        z_in + t * (z_out - z_in)
    }

    /// Marches down from (z, T₁ > 0 there) to the first crossing above base.
    fn march_down(&self, x: f64, y: f64, from: (f64, f64)) -> Option<f64> {
        let base = self.spec.base;
        let mut above = from;
        let steps = ((from.0 - base) / self.spec.step).ceil().max(0.0) as usize + 1;
        for k in 1..=steps {
            let z = (from.0 - k as f64 * self.spec.step).max(base);
            let f = self.t(x, y, z);
            if f <= 0.0 {
                return Some(self.root(x, y, (z, f), above));
            }
            if z <= base {
                return None;
            }
            above = (z, f);
        }
        None
    }

    /// Marches up from (z, T₁ ≤ 0 there) to the first crossing below start.
    fn march_up(&self, x: f64, y: f64, from: (f64, f64)) -> f64 {
        let start = self.spec.start;
        let mut below = from;
        let steps = ((start - from.0) / self.spec.step).ceil().max(0.0) as usize + 1;
        for k in 1..=steps {
            let z = (from.0 + k as f64 * self.spec.step).min(start);
            let f = self.t(x, y, z);
            if f > 0.0 {
                return self.root(x, y, below, (z, f));
            }
            if z >= start {
                return start;
            }
            below = (z, f);
        }
        start
    }

    /// The ray from `start` down: its first crossing above base.
    fn full_ray(&self, x: f64, y: f64) -> Option<f64> {
        let f = self.t(x, y, self.spec.start);
        if f <= 0.0 {
            return Some(self.spec.start);
        }
        self.march_down(x, y, (self.spec.start, f))
    }

    /// The coarse ray at node (i, j), clamped into the grid.
    fn node(&self, i: isize, j: isize) -> Option<f64> {
        let i = i.clamp(0, self.nx as isize - 1) as usize;
        let j = j.clamp(0, self.ny as isize - 1) as usize;
        self.coarse[j * self.nx + i]
    }

    /// h(x, y), (x, y) relative to the origin (module doc).
    pub fn height(&self, x: f64, y: f64) -> f64 {
        let base = self.spec.base;
        let i = ((x / self.hx).floor() as isize).clamp(0, self.nx as isize - 2);
        let j = ((y / self.hy).floor() as isize).clamp(0, self.ny as isize - 2);
        let corners = [(0, 0), (1, 0), (0, 1), (1, 1)]
            .iter()
            .filter_map(|&(a, b)| self.node(i + a, j + b))
            .fold(None, |m: Option<f64>, z| Some(m.map_or(z, |m| m.max(z))));
        let found = match corners {
            Some(zc) => {
                let z0 = zc.clamp(base, self.spec.start);
                let f0 = self.t(x, y, z0);
                if f0 > 0.0 {
                    self.march_down(x, y, (z0, f0))
                } else {
                    Some(self.march_up(x, y, (z0, f0)))
                }
            }
            None => {
                let near = (-1..=2).any(|a| (-1..=2).any(|b| self.node(i + a, j + b).is_some()));
                if near {
                    self.full_ray(x, y)
                } else {
                    None
                }
            }
        };
        found.map_or(base, |z| z.max(base))
    }

    /// ∇h at (x, y) where h = `h` (from [`Relief::height`]): −(∂T₁/∂x,
    /// ∂T₁/∂y)/(∂T₁/∂z) on the surface, 0 on the base.
    pub fn gradient_at(&self, x: f64, y: f64, h: f64) -> [f64; 2] {
        if h <= self.spec.base {
            return [0.0, 0.0];
        }
        let o = self.spec.origin;
        let g = self.field.gradient(Vector3::new(o[0] + x, o[1] + y, h));
        [-g.x / g.z, -g.y / g.z]
    }

    /// ∇h at (x, y) (a ray, then [`Relief::gradient_at`]).
    pub(crate) fn gradient(&self, x: f64, y: f64) -> [f64; 2] {
        self.gradient_at(x, y, self.height(x, y))
    }

    /// The coarse rays that hit: ((x, y) relative to the origin, h).
    pub(crate) fn coarse_rays(&self) -> Vec<([f64; 2], f64)> {
        (0..self.coarse.len())
            .filter_map(|k| {
                let p = [
                    (k % self.nx) as f64 * self.hx,
                    (k / self.nx) as f64 * self.hy,
                ];
                self.coarse[k].map(|h| (p, h))
            })
            .collect()
    }

    /// The spec.
    pub(crate) fn spec(&self) -> &ReliefSpec {
        &self.spec
    }

    /// The fast field.
    pub fn field(&self) -> &FastField {
        &self.field
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sources::polyharmonic::system::{solve, tests::sphere_model_for_envelope};
    use crate::sources::polyharmonic::Envelope;

    /// The sphere of 40 points (box [−2, 2]³, 4 elements a side, so the
    /// region comes within half an element of the box): the fast field is
    /// within 1e-6 of the exact one, and the relief within 1e-4 of direct
    /// rays on the exact field (step 0.02, tol 1e-10) at 120 points, away
    /// from the rim ρ = 1 where h jumps from 0 to the base.
    #[test]
    fn the_relief_matches_direct_rays_on_the_exact_field() {
        let sol = solve(&sphere_model_for_envelope()).unwrap();
        let (base, start) = (-0.5, 1.5);
        let lo = Vector3::new(-1.2, -1.2, base);
        let hi = Vector3::new(1.2, 1.2, start);
        let fast = FastField::new(sol.clone(), lo, hi, 0.2, 4).unwrap();
        let mut worst_t: f64 = 0.0;
        for k in 0..300 {
            let u = (k as f64 * 0.618_033_988_7).fract();
            let x = lo
                + (hi - lo).component_mul(&Vector3::new(u, (3.0 * u).fract(), (7.0 * u).fract()));
            worst_t = worst_t.max((fast.value(x) - sol.value(x).unwrap()).abs());
        }
        assert!(worst_t < 1e-4, "max |T₁ fast − exact| = {worst_t:.2e}");
        let spec = ReliefSpec {
            origin: [-1.2, -1.2],
            size: [2.4, 2.4],
            base,
            start,
            step: 0.1,
            coarse: 0.1,
        };
        let relief = Relief::new(fast, spec).unwrap();
        let env = Envelope {
            step: 0.02,
            tol: 1e-10,
        }
        .validated(&sol)
        .unwrap();
        let (mut worst, mut hits) = (0.0_f64, 0);
        // 80 points anywhere, then 40 on coarse nodes (where a cell's search
        // starts on a root: once returned a step above it).
        for k in 0..120 {
            let u = (k as f64 * 0.618_033_988_7).fract();
            let (x, y) = if k < 80 {
                (2.4 * u, 2.4 * (5.0 * u).fract())
            } else {
                (0.1 * (k % 24) as f64, 0.1 * ((7 * k) % 24) as f64)
            };
            let rho = (x - 1.2).hypot(y - 1.2);
            if (rho - 1.0).abs() < 0.03 {
                continue;
            }
            let direct = env
                .height(&sol, x - 1.2, y - 1.2)
                .map_or(base, |z| z.max(base));
            hits += usize::from(direct > base);
            worst = worst.max((relief.height(x, y) - direct).abs());
        }
        assert!(hits > 30, "{hits} hits");
        assert!(worst < 1e-4, "max |relief − direct| = {worst:.2e}");
    }

    #[test]
    fn bad_settings_name_their_key() {
        let sol = solve(&sphere_model_for_envelope()).unwrap();
        let lo = Vector3::new(-1.0, -1.0, -1.0);
        let fast = FastField::new(sol.clone(), lo, -lo, 0.2, 4).unwrap();
        let spec = ReliefSpec {
            origin: [-1.0, -1.0],
            size: [2.0, 2.0],
            base: -1.0,
            start: 1.0,
            step: 0.0,
            coarse: 0.1,
        };
        let e = Relief::new(fast.clone(), spec).unwrap_err();
        assert!(e.to_string().starts_with("shape.size:"), "{e}");
        // The sphere reaches z = 0.5: rays starting there are inside it.
        let low = ReliefSpec {
            step: 0.1,
            start: 0.5,
            ..spec
        };
        let e = Relief::new(fast, low).unwrap_err();
        assert!(e.to_string().starts_with("shape.box:"), "{e}");
        let far = FastField::new(sol, lo * 2.5, -lo, 0.2, 4).unwrap_err();
        assert!(far.to_string().starts_with("box:"), "{far}");
    }
}
