//! The corner pass: where the foot of a wall is a concave bend tighter than
//! the cutter's corner (the steep walls of a letter's counter), the cutter
//! cannot follow S2 into it. Passes whose contact lies in the bend all leave
//! the cutter sitting on the floor somewhat short of the wall, and the one
//! position that removes most of the bend's material, the cutter on the
//! floor and touching the wall, is met only by chance: a few hundredths of a
//! millimetre short of it, the steep side of a ball leaves several
//! hundredths standing over the floor. The corner pass puts the axis there
//! on purpose: from each point of the foot Γ(s_foot) outwards along the
//! field's downhill direction, the nearest axis position at which the
//! drop-cutter's tip rests on the floor (within [`SETTLE`]), found by
//! bisection on the drop height.

use super::FinishParams;
use crate::field::Field;
use crate::geometry::Vec2;
use crate::toolpath::dropcutter::MeshIndex;

/// How close to the floor the tip must come, mm.
pub const SETTLE: f64 = 1e-3;

/// A foot loop's corner pass.
pub struct Corner {
    /// The axis positions, as contact points of a pass over the floor.
    pub axes: Vec<Vec2>,
}
/// How finely the axis position is found, mm.
const STEP: f64 = 2e-3;

/// The corner pass's axis positions for the foot loop `foot`, as the
/// contact points of a pass over the floor (which puts the axis r − rc out
/// from them); `None` when the corner lies within `near` of the foot's own
/// axes everywhere on the loop (the foot's pass and the floor's, a pass
/// width apart, pass by it). `floor_z` is the floor's height, `reach` the
/// farthest the search goes from the foot, mm.
pub fn corner_axes(
    foot: &[Vec2],
    field: &Field,
    p: &FinishParams,
    mesh: &MeshIndex,
    floor_z: f64,
    (near, reach): (f64, f64),
) -> Option<Corner> {
    let away = if p.cavity { 1.0 } else { -1.0 };
    // A flat pass puts the axis (r − rc) out from its contact point.
    let shift = p.cutter.radius - p.cutter.corner;
    let settled = |q: Vec2| {
        p.cutter
            .drop(mesh, q.x, q.y)
            .is_some_and(|z| z <= floor_z + SETTLE)
    };
    let mut moved = false;
    let pts: Vec<Vec2> = foot
        .iter()
        .map(|&q| {
            let d = field.grad(q).normalized() * away;
            if settled(q + d * shift) {
                return q;
            }
            // settled(hi) holds, settled(lo) does not.
            let (mut lo, mut hi) = (0.0, reach);
            if !settled(q + d * (shift + hi)) {
                return q;
            }
            while hi - lo > STEP {
                let mid = 0.5 * (lo + hi);
                if settled(q + d * (shift + mid)) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            moved |= hi > near;
            q + d * hi
        })
        .collect();
    moved.then_some(Corner { axes: pts })
}
