//! The fictitious box and its constant elements (Ochiai §3, Fig. 6(a)).
//!
//! Each of the six faces of the box [lo, hi] is cut into `per_edge` ×
//! `per_edge` equal rectangles; an element carries its centre (the collocation
//! point), its outward unit normal n, two unit tangents u, v and its half
//! sides a (along u), b (along v). On a cube the elements are squares of side
//! h = (hi − lo)/per_edge.
//!
//! Self-integrals over a flat rectangle [−a, a] × [−b, b] from its centre, in
//! polar coordinates over the two triangles the diagonal cuts each quarter
//! into (d = √(a² + b²); ∫sec θ = ln(sec θ + tan θ), ∫sec³θ = ½(sec θ tan θ +
//! ln(sec θ + tan θ))):
//!
//! ```text
//! ∫ dA / r = 4 [a ln((d + b)/a) + b ln((d + a)/b)]                 (square: 4h ln(1 + √2))
//! ∫ r dA   = 4 [abd/3 + (a³ ln((d + b)/a) + b³ ln((d + a)/b))/6]  (square: (h³/6)(√2 + ln(1 + √2)))
//! ```
//!
//! and ∫ ∂T*/∂n dA = 0 over the element's own plane (d·n = 0).

use super::error::{invalid, PolyError};
use super::fault::PolyFault;
use nalgebra::Vector3;

/// Most elements per face edge: 6·20² = 2400 elements make a dense system of
/// 4800 + M unknowns (about 190 MB), the most a job should ask of a desk.
pub(crate) const MAX_PER_EDGE: usize = 20;

/// One constant element: a flat rectangle on a face of the box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Element {
    /// Centre, the collocation point.
    pub centre: Vector3<f64>,
    /// Outward unit normal of the box face.
    pub normal: Vector3<f64>,
    /// First unit tangent.
    pub(crate) u: Vector3<f64>,
    /// Second unit tangent.
    pub(crate) v: Vector3<f64>,
    /// Half side along u.
    pub a: f64,
    /// Half side along v.
    pub(crate) b: f64,
}

impl Element {
    /// Area 4ab.
    pub fn area(&self) -> f64 {
        4.0 * self.a * self.b
    }
}

/// The fictitious box [lo, hi] and its 6·per_edge² elements.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxMesh {
    /// Lowest corner.
    pub(crate) lo: Vector3<f64>,
    /// Highest corner.
    pub(crate) hi: Vector3<f64>,
    /// Elements per face edge.
    pub(crate) per_edge: usize,
    /// The elements, face by face (−x, +x, −y, +y, −z, +z), row by row.
    pub elements: Vec<Element>,
}

impl BoxMesh {
    /// The mesh of the box [lo, hi] with `per_edge` elements along each face
    /// edge. Errors: a corner not finite or lo ≥ hi on an axis (`box`),
    /// `per_edge` outside 1..=[`MAX_PER_EDGE`] (`elements`).
    pub fn new(lo: Vector3<f64>, hi: Vector3<f64>, per_edge: usize) -> Result<Self, PolyError> {
        if !(lo.iter().chain(hi.iter()).all(|c| c.is_finite())) || (0..3).any(|k| lo[k] >= hi[k]) {
            return Err(invalid("box", PolyFault::BadBox { lo, hi }));
        }
        if !(1..=MAX_PER_EDGE).contains(&per_edge) {
            return Err(invalid("elements", PolyFault::PerEdge { per_edge }));
        }
        let n = per_edge as f64;
        let mut elements = Vec::with_capacity(6 * per_edge * per_edge);
        for axis in 0..3 {
            let (iu, iv) = ((axis + 1) % 3, (axis + 2) % 3);
            let (su, sv) = ((hi[iu] - lo[iu]) / n, (hi[iv] - lo[iv]) / n);
            for (sign, plane) in [(-1.0, lo[axis]), (1.0, hi[axis])] {
                let mut normal = Vector3::zeros();
                normal[axis] = sign;
                for i in 0..per_edge {
                    for j in 0..per_edge {
                        let mut c = Vector3::zeros();
                        c[axis] = plane;
                        c[iu] = lo[iu] + (i as f64 + 0.5) * su;
                        c[iv] = lo[iv] + (j as f64 + 0.5) * sv;
                        elements.push(Element {
                            centre: c,
                            normal,
                            u: Vector3::ith(iu, 1.0),
                            v: Vector3::ith(iv, 1.0),
                            a: 0.5 * su,
                            b: 0.5 * sv,
                        });
                    }
                }
            }
        }
        Ok(BoxMesh {
            lo,
            hi,
            per_edge,
            elements,
        })
    }

    /// Whether `x` lies strictly inside the box.
    pub(crate) fn contains(&self, x: Vector3<f64>) -> bool {
        (0..3).all(|k| x[k] > self.lo[k] && x[k] < self.hi[k])
    }

    /// The largest edge of the box (the length scale of tolerances).
    pub(crate) fn size(&self) -> f64 {
        (self.hi - self.lo).max()
    }
}

/// ∫ dA / r over [−a, a] × [−b, b] from its centre.
pub(crate) fn self_inv_r(a: f64, b: f64) -> f64 {
    let d = a.hypot(b);
    4.0 * (a * ((d + b) / a).ln() + b * ((d + a) / b).ln())
}

/// ∫ r dA over [−a, a] × [−b, b] from its centre.
pub(crate) fn self_r(a: f64, b: f64) -> f64 {
    let d = a.hypot(b);
    4.0 * (a * b * d / 3.0
        + (a.powi(3) * ((d + b) / a).ln() + b.powi(3) * ((d + a) / b).ln()) / 6.0)
}
