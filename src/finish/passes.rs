//! The finishing passes: the level curves Γ(s_k) of the shape's field that the
//! finisher follows, spaced so that the cutter's scallop stays under the bound.
//!
//! Contact points on neighbouring passes lie on S2 along the field's gradient:
//! between Γ(s) and Γ(s + Δs) the horizontal step is Δs/|∇u| and the vertical
//! one φ'(s)·Δs, so their distance on the surface is Δs·√(1/|∇u|² + φ'(s)²).
//! The passes are Δs = w / max over Γ(s) of that root apart (the widest place
//! sets the step), where w is the cutter's pass width for the scallop bound
//! ([`pass_width`]). Past the foot of the wall (where the roughing left
//! `stock_to_leave` on the floor) the foot's loops are offset over the flat
//! floor, w apart, until `leave` + w/2 is covered.

use crate::field::isolines::Grid;
use crate::field::Field;
use crate::geometry::Vec2;
use crate::levels::plan::curves;
use crate::levels::DepthProfile;

/// Most passes of one program (a bound on work and file size; the job's
/// `machine.max_hours` and `machine.max_file_mb` usually stop it first).
pub const MAX_PASSES: usize = 2000;

/// Distance between neighbouring contact points for a scallop of height `h`
/// under a cutter corner of radius `rc`, mm: a circle of radius rc stepped w
/// along a flat leaves h = rc − √(rc² − w²/4), so w = 2√(2·rc·h − h²). A flat
/// end mill (rc = 0) leaves a stair whose corner stands w·sinθ·cosθ ≤ w/2 off
/// the surface: w = 2h.
pub fn pass_width(rc: f64, h: f64) -> f64 {
    if rc <= 0.0 {
        2.0 * h
    } else {
        2.0 * (2.0 * rc * h - h * h).max(0.0).sqrt()
    }
}

/// dφ/ds by central differences (one-sided at the ends of φ's range, 0
/// outside it, where φ is flat).
pub fn dphi_ds(profile: &DepthProfile, s: f64) -> f64 {
    let (lo, hi) = profile.s_range();
    if s < lo || s > hi {
        return 0.0;
    }
    let e = 1e-7 * (hi - lo);
    let (a, b) = ((s - e).max(lo), (s + e).min(hi));
    (profile.z(b) - profile.z(a)) / (b - a)
}

/// The curves Γ(s) of a field, from one grid (`levels::plan::curves`, as the
/// level planner extracts them).
pub struct Curves<'a> {
    /// The field.
    pub field: &'a Field,
    /// u sampled over the part.
    pub grid: Grid,
    /// The glyphs (the material where u is pinned to 1).
    pub glyphs: &'a [Vec<Vec2>],
    /// Grid spacing, mm.
    pub h: f64,
    /// Chord tolerance, mm.
    pub tol: f64,
}

impl Curves<'_> {
    /// Γ(s) as closed polygons (the first point is not repeated).
    pub fn at(&self, s: f64) -> Vec<Vec<Vec2>> {
        curves(&self.grid, self.field, self.glyphs, s, self.h, self.tol)
    }

    /// The smallest |∇u| over the points of `loops` (where the passes are
    /// farthest apart), or `None` if there are none or ∇u vanishes.
    fn min_grad(&self, loops: &[Vec<Vec2>]) -> Option<f64> {
        let mut m = f64::INFINITY;
        for &p in loops.iter().flatten() {
            let g = self.field.grad(p).norm();
            if !(g > 0.0 && g.is_finite()) {
                return None;
            }
            m = m.min(g);
        }
        m.is_finite().then_some(m)
    }
}

/// Distance on S2 per unit of s where |∇u| = g and φ' = dphi, mm.
fn spread(g: f64, dphi: f64) -> f64 {
    (1.0 / (g * g) + dphi * dphi).sqrt()
}

/// One pass: its s and the loops of Γ(s).
pub type Pass = (f64, Vec<Vec<Vec2>>);

/// The pass levels from the floor up: s_k in the order the finisher cuts
/// them (ascending z), each with Γ(s_k). `cavity` mirrors the profile (its
/// floor is at the high end of s). Errors name what failed.
pub fn pass_levels(
    curves: &Curves,
    profile: &DepthProfile,
    cavity: bool,
    w: f64,
    leave: f64,
) -> Result<Vec<Pass>, String> {
    let (lo, hi) = profile.s_range();
    // Towards the top: +1 in s for a boss, −1 for a cavity.
    let up = if cavity { -1.0 } else { 1.0 };
    let (foot, top) = if cavity { (hi, lo) } else { (lo, hi) };
    let foot_loops = curves.at(foot);
    if foot_loops.is_empty() {
        return Err(format!("the foot of the wall Γ({foot:.4}) has no curve"));
    }
    // Over the floor, outwards from the foot: the foot's loops offset along
    // the field's downhill direction by k·w (k = 1, 2, ...) until leave + w/2
    // is covered. Equipotentials would be as far apart there as |∇u| varies
    // along the foot; the floor is flat, so plain offsets are the even
    // spacing (a loop of the foot is smooth, far rounder than these few
    // tenths of a millimetre). Their s lies just past φ's range: flat.
    let away = if cavity { 1.0 } else { -1.0 };
    let k_max = ((leave + 0.5 * w) / w).ceil() as usize;
    let s_floor = foot - up * 1e-9;
    let mut floor: Vec<Pass> = (1..=k_max)
        .rev()
        .map(|k| {
            let d = k as f64 * w;
            let loops = foot_loops
                .iter()
                .map(|l| {
                    l.iter()
                        .map(|&p| p + curves.field.grad(p).normalized() * (away * d))
                        .collect()
                })
                .collect();
            (s_floor, loops)
        })
        .collect();
    // Up the wall, from the foot to the top edge.
    let mut wall = vec![(foot, foot_loops)];
    let mut s = foot;
    while (top - s) * up > 1e-12 {
        if floor.len() + wall.len() >= MAX_PASSES {
            return Err(format!(
                "the wall needs more than {MAX_PASSES} finishing passes: raise finish.scallop or use a larger finishing tool"
            ));
        }
        let loops = &wall[wall.len() - 1].1;
        let g = curves
            .min_grad(loops)
            .ok_or_else(|| format!("∇u vanishes on Γ({s:.5})"))?;
        // The slope may steepen over the step: the larger spread of its ends.
        let m0 = spread(g, dphi_ds(profile, s));
        let trial = s + up * w / m0;
        let m1 = m0.max(spread(g, dphi_ds(profile, trial)));
        let mut next = s + up * w / m1;
        if (next - top) * up > -1e-9 {
            next = top;
        }
        let next_loops = curves.at(next);
        if next_loops.is_empty() {
            break;
        }
        wall.push((next, next_loops));
        s = next;
    }
    floor.extend(wall);
    Ok(floor)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pass_width_gives_the_scallop_back() {
        for (rc, h) in [(1.5875, 0.01), (3.0, 0.002), (0.5, 0.05)] {
            let w = pass_width(rc, h);
            // Two circles of radius rc, w apart: the cusp between them.
            let cusp = rc - (rc * rc - 0.25 * w * w).sqrt();
            assert!((cusp - h).abs() < 1e-12, "{rc} {h}: {cusp}");
        }
        assert_eq!(pass_width(0.0, 0.01), 0.02);
    }

    #[test]
    fn the_profile_slope_matches_its_finite_difference_and_is_zero_outside() {
        let p = DepthProfile::Sigmoid {
            s1: 0.97,
            s2: 0.9,
            steepness: 6.0,
            depth: 3.0,
        };
        for s in [0.91, 0.93, 0.95, 0.965] {
            let e = 1e-5;
            let fd = (p.z(s + e) - p.z(s - e)) / (2.0 * e);
            assert!((dphi_ds(&p, s) - fd).abs() < 1e-4 * fd.abs(), "{s}");
        }
        assert_eq!(dphi_ds(&p, 0.85), 0.0);
        assert_eq!(dphi_ds(&p, 0.99), 0.0);
    }
}
