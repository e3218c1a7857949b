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
pub(crate) const SETTLE: f64 = 1e-3;

/// A foot loop's corner pass.
pub(crate) struct Corner {
    /// The axis positions, as contact points of a pass over the floor.
    pub(crate) axes: Vec<Vec2>,
}
/// How finely the axis position is found, mm.
const STEP: f64 = 2e-3;

/// The corner pass's axis positions for the foot loop `foot`, as the
/// contact points of a pass over the floor (which puts the axis r − rc out
/// from them); `None` when the corner lies within `near` of the foot's own
/// axes everywhere on the loop (the foot's pass and the floor's, a pass
/// width apart, pass by it). `floor_z` is the floor's height, `reach` the
/// farthest the search goes from the foot, mm.
pub(crate) fn corner_axes(
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::levels::DepthProfile;

    /// A round boss: top disk of radius `rt` at z = 0, a conical wall down
    /// to the foot circle of radius `rf` at z = −3, the floor out to rf + 10
    /// mm, in `n` sectors.
    fn cone(rt: f64, rf: f64, n: usize) -> Vec<[[f64; 3]; 3]> {
        let at = |r: f64, k: usize, z: f64| {
            let t = k as f64 / n as f64 * std::f64::consts::TAU;
            [r * t.cos(), r * t.sin(), z]
        };
        let mut tris = Vec::new();
        for k in 0..n {
            let j = k + 1;
            tris.push([[0.0, 0.0, 0.0], at(rt, k, 0.0), at(rt, j, 0.0)]);
            for (r0, z0, r1, z1) in [(rt, 0.0, rf, -3.0), (rf, -3.0, rf + 10.0, -3.0)] {
                tris.push([at(r0, k, z0), at(r1, k, z1), at(r1, j, z1)]);
                tris.push([at(r0, k, z0), at(r1, j, z1), at(r0, j, z0)]);
            }
        }
        tris
    }

    use crate::finish::testing::params;

    /// Against the ball in the section through the axis of a round boss
    /// (the closest point of a surface of revolution lies in that plane):
    /// resting on the floor and touching a wall at θ to it, the ball's
    /// centre lies r·tan(θ/2) out from the wall's foot (on the bisector of
    /// the corner, r from both lines). Every corner axis lies there within
    /// the bisection's step, the settling height's share (SETTLE / tan θ) and
    /// the 720-gon's sag; a wall gentle enough that the corner lies within
    /// `near` of the foot gets no corner pass.
    #[test]
    fn the_corner_axis_rests_on_the_floor_against_the_wall() {
        let profile = DepthProfile::Linear {
            s_bottom: 0.9,
            depth: 3.0,
        };
        let p = params(&profile);
        let r = p.cutter.radius;
        // One charge at the centre: −∇u points radially out.
        let field = crate::field::Field::new(vec![Vec2::new(0.0, 0.0)], vec![1.0]);
        let (rf, near) = (10.0, 0.356);
        let foot: Vec<Vec2> = (0..36)
            .map(|k| {
                let t = k as f64 / 36.0 * std::f64::consts::TAU + 0.01;
                Vec2::new(rf * t.cos(), rf * t.sin())
            })
            .collect();
        for rt in [9.9, 8.5, 8.0] {
            let mesh = MeshIndex::new(cone(rt, rf, 720), 0.8);
            let theta = (3.0 / (rf - rt)).atan();
            let want = rf + r * (0.5 * theta).tan();
            let c = corner_axes(&foot, &field, &p, &mesh, -3.0, (near, 2.0 * r))
                .expect("a corner pass at a steep wall");
            let slack = STEP + SETTLE / theta.tan() + 1e-3;
            for q in &c.axes {
                let d = q.norm();
                assert!(
                    d <= want + slack && d >= want - SETTLE / theta.tan() - 1e-3,
                    "rt {rt}: axis at {d}, the ball in the corner at {want}"
                );
            }
        }
        // tan θ = 0.1: the corner lies r·tan(θ/2) = 0.079 mm out, within near.
        let wide: Vec<Vec2> = foot.iter().map(|&q| q * 4.0).collect();
        let mesh = MeshIndex::new(cone(4.0 * rf - 30.0, 4.0 * rf, 2880), 0.8);
        assert!(corner_axes(&wide, &field, &p, &mesh, -3.0, (near, 2.0 * r)).is_none());
    }
}
