//! From the pass curves to the finishing tool path: where the cutter's axis
//! goes for each contact point, how low it may go (the drop-cutter against
//! S2's mesh, so no triangle of the part is ever entered), and the order and
//! links of the loops.
//!
//! - Axis. At a point p of Γ(s), S2's slope θ has tan θ = |φ'(s)|·|∇u(p)|,
//!   and the surface falls away from the material along d̂ = ∓∇u/|∇u| (− for a
//!   boss, + for a cavity). A cutter of radius r and corner rc touching S2 at p
//!   with its corner has its axis (r − rc) + rc·sin θ from p along d̂. Its tip
//!   height is then the drop-cutter's: the lowest at which it touches the mesh,
//!   which also lifts it where another part of the surface is nearer than p.
//! - Order. The passes are cut from the floor up, so every link between
//!   neighbouring passes climbs and no move descends into what the roughing
//!   left. The loops form a tree (each loop's parent is the nearest loop of the
//!   pass below); a depth-first walk cuts a loop's first child straight after
//!   it (a short feed link over the surface) and reaches the others by a
//!   retract.
//! - Entry. After a retract the cutter comes down in rapid to `entry` above
//!   the surface (what the roughing can have left there: a stepdown and the
//!   stock to leave) and ramps down along the loop at `ramp_angle`, then cuts
//!   the whole loop at depth.

use super::geodesic::Curve;
use super::passes::At;
use super::{FinishError, FinishParams};
use crate::field::level::{project, Limits};
use crate::field::Field;
use crate::geometry::{densify, densify_values, DistanceIndex, Vec2};
use crate::toolpath::dropcutter::{Cutter, MeshIndex};
use crate::toolpath::{Move, Section, Toolpath, Vec3};

/// Spacing of the contact points along a pass, mm (the chords between
/// dropped points then follow the surface within a few µm).
pub(crate) const SAMPLE: f64 = 0.1;
/// Longest feed link between a loop and its first child, in pass widths; a
/// farther child is reached by a retract.
pub(crate) const LINK_WIDTHS: f64 = 6.0;
/// Longest feed link to an open arc, mm: arcs end on the wall's foot, and
/// the next arc's end lies along the foot, over a floor the roughing cut to
/// size; a retract and an entry's ramp (a stepdown and more at the ramp
/// angle and the plunge feed) take as long as a feed link of well over this.
pub(crate) const ARC_LINK: f64 = 25.0;
/// Most contact points added between two neighbours so their axes lie at
/// most [`SAMPLE`] apart.
const MAX_SPLIT: usize = 64;
/// Most halvings of one chord between tips to keep it above the drop height.
const CHORD_DEPTH: usize = 6;
/// Steepest descent of the tip along a pass (Δz over XY length): tan 40°,
/// under the 45° from which `pfcam simulate` counts a straight plunge.
const DESCENT_SLOPE: f64 = 0.839_099_631_177_280_1;

/// One loop of one pass, as the cutter's tip follows it.
#[derive(Clone, Debug)]
pub(crate) struct Loop {
    /// The pass (index into the passes, from the floor up).
    pub(crate) pass: usize,
    /// Where the pass lies.
    pub(crate) at: At,
    /// Whether the curve is closed (else an open arc, cut from either end).
    pub(crate) closed: bool,
    /// The contact curve (first point not repeated), a closed one oriented
    /// for the cutting direction.
    pub(crate) contact: Vec<Vec2>,
    /// The tip positions, one per contact point.
    pub(crate) tip: Vec<Vec3>,
}

/// The side the material lies on: +1 when it is on the right of the loop's
/// direction (at most points), −1 on the left.
fn material_side(pts: &[Vec2], away: &[Vec2]) -> f64 {
    let n = pts.len();
    let mut sum = 0.0;
    for i in 0..n {
        let t = pts[(i + 1) % n] - pts[i];
        // Right of t is −perp(t); the material is at −away.
        sum += (-t.perp()).dot(-away[i]);
    }
    sum.signum()
}

/// The pass curve `curve` of pass `pass` (lying where `at` says) with its
/// tip positions (see the module docs); `Err` names a point no triangle lies
/// under. On Γ(s) the slope φ′ is φ′(s); elsewhere it is φ′(u) at each
/// contact point.
pub(crate) fn tip_loop(
    curve: &Curve,
    pass: usize,
    at: At,
    field: &Field,
    p: &FinishParams,
    mesh: &MeshIndex,
) -> Result<Loop, FinishError> {
    let closed = curve.closed;
    let mut contact = densify(&curve.pts, SAMPLE, closed);
    if curve.s.len() == curve.pts.len() {
        let s = densify_values(&curve.pts, &curve.s, SAMPLE, closed);
        onto_levels(&mut contact, &s, field);
    }
    let sign = if p.cavity { 1.0 } else { -1.0 };
    let (lo, hi) = p.profile.s_range();
    let s_at = |q: Vec2| match at {
        At::S(s) => s,
        At::D(_) => field.value(q).clamp(lo, hi),
    };
    // ∇u once per contact point: its direction is `away`, its length the slope.
    let mut grads: Vec<Vec2> = contact.iter().map(|&q| field.grad(q)).collect();
    let mut away: Vec<Vec2> = grads.iter().map(|g| g.normalized() * sign).collect();
    // Climb: the material on the right; conventional: on the left. An open
    // arc is cut from whichever end the cutter reaches first.
    let want = if p.climb { 1.0 } else { -1.0 };
    if closed && material_side(&contact, &away) != want {
        contact.reverse();
        away.reverse();
        grads.reverse();
    }
    let axes = spread_axes(
        (
            contact,
            closed,
            in_crease(at, p).then_some((mesh, p.tol / 2.0)),
        ),
        &away,
        &grads,
        &|q| {
            // u once per point (a field evaluation on an arc's pass).
            let s = s_at(q);
            (s, super::passes::dphi_ds(p.profile, s).abs())
        },
        p.cutter,
        field,
        sign,
    );
    let tips = drop_tips(&axes, p, mesh)?;
    let tip = limit_descent(chord_safe(tips, closed, p, mesh), closed, DESCENT_SLOPE);
    Ok(Loop {
        pass,
        at,
        closed,
        contact: axes.contact,
        tip,
    })
}

/// Each point of a level of σ moved onto Γ(s) for its own s (the u of its
/// crossing, [`super::geodesic::Curve::s`]) by three Newton steps along ∇u;
/// a point that would move farther than [`ONTO_LEVEL`] in plan (near a
/// saddle of u, where ∇u vanishes) stays where it was. Why: on a
/// near-vertical wall a point's height is known far better than its place
/// in plan, and round a corner of the top edge the chords of marching
/// squares cut inside the true top (u past s_top): there the contact took
/// the top's height and the cutter sat on the edge (mfs-sign's M, 0.031 mm
/// left on the wall under it).
fn onto_levels(pts: &mut [Vec2], s: &[f64], field: &Field) {
    use rayon::prelude::*;
    let limits = Limits {
        leash: true,
        ..Limits::steps(3, ONTO_LEVEL)
    };
    pts.par_iter_mut().zip(s).for_each(|(q, &s)| {
        if let Some(on) = project(field, *q, s, &limits) {
            *q = on;
        }
    });
}

/// The farthest a point of a level of σ moves onto its Γ(s), mm (mfs-sign's
/// geodesic copy gives the same program with 0.03 and 0.1).
const ONTO_LEVEL: f64 = 0.03;

/// Whether the pass runs along the concave crease where the wall meets the
/// floor under it (a boss's foot Γ(s2), a mould's letter floor Γ(s1)): no
/// cutter reaches into such a crease, and the nearest it comes is wedged
/// against both faces, its contact normal halfway between the floor's
/// (vertical) and the wall's (at the slope θ of the wall side, φ′ there).
fn in_crease(at: At, p: &FinishParams) -> bool {
    let (lo, hi) = p.profile.s_range();
    match at {
        At::S(s) if s == lo => p.z_of(lo) < p.z_of(hi),
        At::S(s) if s == hi => p.z_of(hi) < p.z_of(lo),
        _ => false,
    }
}

/// The cutter's axis for a contact point `q` where ∇u = `g` and the surface
/// falls away along `d` (see the module docs), and how far its tip then lies
/// under q: rc·(1 − cos θ), the corner's sag at the slope θ. In a concave
/// crease (`half`) where a floor meets the wall at the slope θ, the corner
/// wedged against both faces: its centre rc from each lies on the bisector,
/// rc·tan(θ/2) out from the crease in plan, its tip on the floor (sag 0); a
/// ball then comes within r·(1/cos(θ/2) − 1) of the crease, the least any
/// ball position can (≈ r·θ²/8), where the wall's own normal holds it
/// r·sin θ out and r·(√(1 + sin²θ) − 1) from it (≈ r·θ²/2).
fn axis_at(q: Vec2, d: Vec2, g: Vec2, (dphi, half): (f64, bool), cutter: Cutter) -> (Vec2, f64) {
    let t = dphi * g.norm();
    let sec = (1.0 + t * t).sqrt();
    let flat = cutter.radius - cutter.corner;
    if half {
        // tan(θ/2) = tan θ / (1 + sec θ).
        return (q + d * (flat + cutter.corner * t / (1.0 + sec)), 0.0);
    }
    let (sin, cos) = (t / sec, 1.0 / sec);
    (
        q + d * (flat + cutter.corner * sin),
        cutter.corner * (1.0 - cos),
    )
}

/// [`axis_at`] for a contact point of a concave crease (`crease`: the mesh
/// and the lift allowed, half the tolerance; `None` elsewhere: the wall's
/// normal). Along a crease that is straight on the cutter's scale the
/// bisector's axis wedges the cutter against both faces, on the floor but
/// for the wall's own curvature (0.002 mm on q-mould's sigmoid wall).
/// Round a corner of the crease tighter than the cutter both faces lift it
/// (up to 0.087 mm on the mould of a 20 mm letter I), and the floor in the
/// corner would keep that; the wall's axis, r·sin θ farther out over the
/// floor, still sits on it. So the bisector's axis is kept unless its
/// cutter stands more than the allowed lift over the wall's: the lift adds
/// to what the floor keeps beside the pass, within the tolerance's share of
/// the bound (scallop + tolerance).
fn crease_axis(
    q: Vec2,
    d: Vec2,
    g: Vec2,
    dphi: f64,
    cutter: Cutter,
    crease: Option<(&MeshIndex, f64)>,
) -> (Vec2, f64) {
    let wall = axis_at(q, d, g, (dphi, false), cutter);
    let Some((mesh, lift)) = crease else {
        return wall;
    };
    let half = axis_at(q, d, g, (dphi, true), cutter);
    let z = |a: Vec2| cutter.drop(mesh, a.x, a.y);
    match (z(wall.0), z(half.0)) {
        (Some(zw), Some(zh)) if zw + lift < zh => wall,
        _ => half,
    }
}

/// Contact points with their cutter axes.
struct Axes {
    /// The contact points.
    contact: Vec<Vec2>,
    /// The axis of each.
    axes: Vec<Vec2>,
    /// The corner's sag of [`axis_at`] at each.
    sags: Vec<f64>,
    /// S2's height at each contact point, mm (absolute).
    z: Vec<f64>,
}

/// The axes of the contact points, with contact points added (between
/// neighbours, on their chord) wherever two neighbouring axes lie more than
/// [`SAMPLE`] apart: round a sharp convex corner of Γ(s) the axes fan out on
/// a circle of radius r about it, and a chord between axes a radian apart
/// would cut into the wall. `slope(q)` is (s, |φ′(s)|) at contact point q;
/// `crease` the mesh and the lift allowed when the curve is a concave crease
/// ([`crease_axis`]).
fn spread_axes(
    (contact, closed, crease): (Vec<Vec2>, bool, Option<(&MeshIndex, f64)>),
    away: &[Vec2],
    grads: &[Vec2],
    slope: &(dyn Fn(Vec2) -> (f64, f64) + Sync),
    cutter: Cutter,
    field: &Field,
    sign: f64,
) -> Axes {
    let n = contact.len();
    let at: Vec<(f64, f64)> = contact.iter().map(|&q| slope(q)).collect();
    let axes: Vec<(Vec2, f64)> = (0..n)
        .map(|i| crease_axis(contact[i], away[i], grads[i], at[i].1, cutter, crease))
        .collect();
    let mut out = Axes {
        contact: Vec::with_capacity(n),
        axes: Vec::with_capacity(n),
        sags: Vec::with_capacity(n),
        z: Vec::with_capacity(n),
    };
    let chords = if closed { n } else { n.saturating_sub(1) };
    for i in 0..n {
        out.contact.push(contact[i]);
        out.axes.push(axes[i].0);
        out.sags.push(axes[i].1);
        out.z.push(at[i].0);
        if i >= chords {
            continue;
        }
        let j = (i + 1) % n;
        let k = ((axes[i].0.dist(axes[j].0) / SAMPLE).ceil() as usize).clamp(1, MAX_SPLIT);
        for m in 1..k {
            let q = contact[i].lerp(contact[j], m as f64 / k as f64);
            let g = field.grad(q);
            let (s, dphi) = slope(q);
            let (a, sag) = crease_axis(q, g.normalized() * sign, g, dphi, cutter, crease);
            out.contact.push(q);
            out.axes.push(a);
            out.sags.push(sag);
            out.z.push(s);
        }
    }
    out
}

/// How far under the tip the contact geometry predicts (the pass's height
/// less the corner's sag) a drop search first looks, mm: the mesh's
/// departure from S2 and the lift by other parts of the surface are both
/// well inside it. Only speed depends on it ([`Cutter::drop_hinted`]): of
/// q-sign's 126 271 tip drops none lay more than 0.0033 mm under the
/// prediction (0.05 mm before: a lower start lets more triangles through).
const HINT_MARGIN: f64 = 0.005;

/// The drop-cutter's tip at each axis; `Err` names a point no triangle lies
/// under.
fn drop_tips(axes: &Axes, p: &FinishParams, mesh: &MeshIndex) -> Result<Vec<Vec3>, FinishError> {
    let pts: Vec<(f64, f64, f64)> = (0..axes.axes.len())
        .map(|i| {
            let a = axes.axes[i];
            (a.x, a.y, p.z_of(axes.z[i]) - axes.sags[i] - HINT_MARGIN)
        })
        .collect();
    let zs = {
        let _stage = crate::count::enter(crate::count::Stage::FinishTips);
        p.cutter.drop_many_hinted(mesh, &pts)
    };
    axes.axes
        .iter()
        .zip(zs)
        .map(|(a, z)| {
            z.map(|z| Vec3::new(a.x, a.y, z))
                .ok_or(FinishError::NothingUnder { x: a.x, y: a.y })
        })
        .collect()
}

/// The tip loop (or arc) with points added where the straight move between two
/// tips would pass below the drop-cutter's height by more than a quarter of
/// the tolerance (the drop height is not linear between samples, above all
/// where the cutter turns round a corner or rides up a wall). A chord is
/// tested at its middle, and a steep one at the points of [`chord_points`]
/// along it (a ball reaching the top of a wall late in the move passes the
/// middle in the clear); it is split at its worst point and each half tested
/// again, at most [`CHORD_DEPTH`] deep.
fn chord_safe(tips: Vec<Vec3>, closed: bool, p: &FinishParams, mesh: &MeshIndex) -> Vec<Vec3> {
    let n = tips.len();
    let m = if closed { n } else { n.saturating_sub(1) };
    let chords: Vec<(Vec3, Vec3)> = (0..m).map(|i| (tips[i], tips[(i + 1) % n])).collect();
    let mut out = Vec::with_capacity(n);
    for (&(a, _), added) in chords.iter().zip(split_chords(&chords, p, mesh)) {
        out.push(a);
        out.extend(added);
    }
    if !closed {
        out.extend(tips.last());
    }
    out
}

/// For each chord, the points to add between its ends (in order from its
/// start) so that no straight move passes below the drop-cutter's height
/// (see [`chord_safe`]).
fn split_chords(chords: &[(Vec3, Vec3)], p: &FinishParams, mesh: &MeshIndex) -> Vec<Vec<Vec3>> {
    let _stage = crate::count::enter(crate::count::Stage::FinishChords);
    // The first test of every chord in one parallel batch; the few chords
    // that need more are split one at a time.
    let points: Vec<Vec<Vec3>> = chords.iter().map(|&(a, b)| chord_points(a, b)).collect();
    // Only a drop height above a point's own threshold matters to
    // `worst_above`, so the drop-cutter skips what cannot reach it.
    let flat: Vec<(f64, f64, f64)> = points
        .iter()
        .flatten()
        .map(|m| (m.x, m.y, chord_threshold(m, p.tol)))
        .collect();
    let mut drops = p.cutter.drop_many_above(mesh, &flat).into_iter();
    let mut out = Vec::with_capacity(chords.len());
    for (&(a, b), pts) in chords.iter().zip(&points) {
        let zs: Vec<Option<f64>> = drops.by_ref().take(pts.len()).collect();
        let Some(first) = worst_above(pts, &zs, p.tol) else {
            out.push(Vec::new());
            continue;
        };
        let mut mids = vec![(0, first)];
        // Depth first, the first part first.
        let mut stack = vec![(first, b, 1), (a, first, 1)];
        while let Some((a, b, depth)) = stack.pop() {
            if depth >= CHORD_DEPTH {
                continue;
            }
            let pts = chord_points(a, b);
            let zs: Vec<Option<f64>> = pts
                .iter()
                .map(|m| {
                    p.cutter
                        .drop_above(mesh, m.x, m.y, chord_threshold(m, p.tol))
                })
                .collect();
            if let Some(q) = worst_above(&pts, &zs, p.tol) {
                stack.push((q, b, depth + 1));
                stack.push((a, q, depth + 1));
                mids.push((depth, q));
            }
        }
        out.push(order_between(a, mids));
    }
    out
}

/// Rise or fall of a chord (mm) per test point along it: a chord that climbs
/// more is tested at more points than its middle.
const CHORD_DZ: f64 = 0.05;

/// Most test points on one chord.
const CHORD_POINTS: usize = 32;

/// The points of the chord from `a` to `b` at which its height is tested
/// against the drop-cutter's: its middle, or for a chord that rises or
/// falls by more than [`CHORD_DZ`], equally spaced points every
/// [`CHORD_DZ`] of its rise (at most [`CHORD_POINTS`]).
fn chord_points(a: Vec3, b: Vec3) -> Vec<Vec3> {
    let dz = (b.z - a.z).abs();
    let k = if dz > CHORD_DZ {
        ((dz / CHORD_DZ).ceil() as usize).clamp(1, CHORD_POINTS)
    } else {
        1
    };
    (1..=k)
        .map(|i| {
            let t = i as f64 / (k + 1) as f64;
            Vec3::new(
                a.x + t * (b.x - a.x),
                a.y + t * (b.y - a.y),
                a.z + t * (b.z - a.z),
            )
        })
        .collect()
}

/// A height a little under the least drop height [`worst_above`] reports at
/// test point `m` (a quarter of `tol` above it; the nanometre keeps rounding
/// on the right side), so that drops under it need not be found.
fn chord_threshold(m: &Vec3, tol: f64) -> f64 {
    m.z + 0.25 * tol - 1e-6
}

/// The test point whose drop height lies farthest above the chord, lifted
/// to that height, if one lies more than a quarter of `tol` above it.
fn worst_above(pts: &[Vec3], zs: &[Option<f64>], tol: f64) -> Option<Vec3> {
    pts.iter()
        .zip(zs)
        .filter_map(|(m, z)| z.map(|z| (z - m.z, Vec3::new(m.x, m.y, z))))
        .filter(|&(over, _)| over > 0.25 * tol)
        .max_by(|x, y| x.0.total_cmp(&y.0))
        .map(|(_, q)| q)
}

/// Points that lie on the segment from `a` (in XY), in order of their
/// distance from `a`.
fn order_between(a: Vec3, mut pts: Vec<(usize, Vec3)>) -> Vec<Vec3> {
    let d = |q: &Vec3| (q.x - a.x).powi(2) + (q.y - a.y).powi(2);
    pts.sort_by(|x, y| d(&x.1).total_cmp(&d(&y.1)));
    pts.into_iter().map(|(_, q)| q).collect()
}

/// The tip loop raised where it would descend steeper than `slope` (Δz
/// over XY length) in the cutting direction: a ball entering the wall the
/// roughing left that steeply is a plunge. Raising only lifts the cutter off
/// the surface (it never enters the part). A closed loop is walked twice so
/// the result does not depend on where it starts; an open arc, cut from
/// either end, is walked forwards and then backwards (a backward raise never
/// undoes a forward one: it lifts a tip to at most the next one's height
/// plus the slope's rise).
fn limit_descent(mut tips: Vec<Vec3>, closed: bool, slope: f64) -> Vec<Vec3> {
    let n = tips.len();
    if n < 2 {
        return tips;
    }
    let raise = |tips: &mut Vec<Vec3>, from: usize, to: usize| {
        let (a, b) = (tips[from], tips[to]);
        let floor = a.z - slope * run_xy(a, b);
        if b.z < floor {
            tips[to].z = floor;
        }
    };
    if closed {
        for k in 1..=2 * n {
            raise(&mut tips, (k - 1) % n, k % n);
        }
    } else {
        for k in 1..n {
            raise(&mut tips, k - 1, k);
        }
        for k in (1..n).rev() {
            raise(&mut tips, k, k - 1);
        }
    }
    tips
}

/// The parent of each loop: the nearest loop of the highest pass below it
/// that has one within `reach` of the loop's first point, else the nearest
/// loop below (passes added about an extremum of u hold only the loops there,
/// so the pass just below need not hold a loop's neighbour); `None` for the
/// first pass.
fn parents(loops: &[Loop], reach: f64) -> Vec<Option<usize>> {
    let mut out = vec![None; loops.len()];
    // One index per loop, built once (not once per loop that asks).
    let index: Vec<DistanceIndex> = loops
        .iter()
        .map(|m| DistanceIndex::new(std::slice::from_ref(&m.contact)))
        .collect();
    for (i, l) in loops.iter().enumerate() {
        // An arc's middle: its ends lie on the foot, beyond the shorter
        // arc of the pass below.
        let probe = l.contact[if l.closed { 0 } else { l.contact.len() / 2 }];
        let mut best: Option<(usize, (bool, usize, f64))> = None;
        for (j, m) in loops.iter().enumerate() {
            if m.pass >= l.pass {
                continue;
            }
            let d = index[j].distance(probe);
            // Within reach first, then the highest pass, then the nearest.
            let key = (d > reach, usize::MAX - m.pass, d);
            let better = best.is_none_or(|(_, b)| {
                (key.0, key.1)
                    .cmp(&(b.0, b.1))
                    .then(key.2.total_cmp(&b.2))
                    .is_lt()
            });
            if better {
                best = Some((j, key));
            }
        }
        out[i] = best.map(|(j, _)| j);
    }
    out
}

/// The loops in cutting order, each with whether it is reached by a feed link
/// from the loop before it (else by a retract): a depth-first walk of the
/// tree, nearest child first.
pub(crate) fn order(loops: &[Loop], reach: f64, max_link: f64) -> Vec<(usize, bool)> {
    let parent = parents(loops, reach);
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); loops.len()];
    let mut roots = Vec::new();
    for (i, p) in parent.iter().enumerate() {
        match p {
            Some(j) => children[*j].push(i),
            None => roots.push(i),
        }
    }
    let mut out = Vec::with_capacity(loops.len());
    let mut stack: Vec<(usize, bool)> = roots.iter().rev().map(|&i| (i, false)).collect();
    let mut at = Vec2::new(f64::INFINITY, f64::INFINITY);
    while let Some((i, linked)) = stack.pop() {
        let most = link_limit(&loops[i], max_link);
        out.push((i, linked && reach_of(&loops[i], at) <= most));
        at = end_from(&loops[i], at);
        // The nearest child is cut next (pushed last); the others follow by
        // retracts once its subtree is done.
        let mut kids = children[i].clone();
        kids.sort_by(|&a, &b| reach_of(&loops[b], at).total_cmp(&reach_of(&loops[a], at)));
        let last = kids.len().saturating_sub(1);
        for (k, &c) in kids.iter().enumerate() {
            stack.push((c, k == last));
        }
    }
    out
}

/// The loops in cutting order, each with whether it is reached by a feed
/// link: from where the cutter is, the nearest loop whose parent (as
/// [`order`] finds it) is cut, linked when it lies within `max_link` (an
/// open arc: [`ARC_LINK`]), else reached by a retract. With open arcs the
/// parent tree branches at every arc that the wall's foot cuts short, and a
/// depth-first walk retracts at every branch; this walk retracts only when
/// nothing that may be cut lies near.
pub(crate) fn order_nearest(loops: &[Loop], reach: f64, max_link: f64) -> Vec<(usize, bool)> {
    let parent = parents(loops, reach);
    // Every tenth contact point, and an arc's ends: where a loop is near.
    let probes: Vec<Vec<Vec2>> = loops
        .iter()
        .map(|l| {
            let mut p: Vec<Vec2> = l.contact.iter().step_by(10).copied().collect();
            p.extend(l.contact.last());
            p
        })
        .collect();
    let near = |i: usize, at: Vec2| -> f64 {
        if loops[i].closed {
            probes[i]
                .iter()
                .map(|q| q.dist(at))
                .fold(f64::INFINITY, f64::min)
        } else {
            reach_of(&loops[i], at)
        }
    };
    let mut done = vec![false; loops.len()];
    let mut out = Vec::with_capacity(loops.len());
    let mut at = Vec2::new(f64::INFINITY, f64::INFINITY);
    for _ in 0..loops.len() {
        let next = (0..loops.len())
            .filter(|&i| !done[i] && parent[i].is_none_or(|p| done[p]))
            .map(|i| (i, if at.x.is_finite() { near(i, at) } else { 0.0 }))
            .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
        let Some((i, d)) = next else { break };
        let most = link_limit(&loops[i], max_link);
        out.push((i, at.x.is_finite() && d <= most));
        done[i] = true;
        at = end_from(&loops[i], at);
    }
    out
}

/// The longest feed link to `l`: `max_link`, or [`ARC_LINK`] to an arc.
fn link_limit(l: &Loop, max_link: f64) -> f64 {
    if l.closed {
        max_link
    } else {
        ARC_LINK.max(max_link)
    }
}

/// Where the cutter ends `l` when it starts from `at` (XY): a loop's start,
/// an arc's far end.
fn end_from(l: &Loop, at: Vec2) -> Vec2 {
    let tips = oriented(l, Vec3::new(at.x, at.y, 0.0));
    let end = if l.closed { tips.first() } else { tips.last() };
    end.map_or(at, |t| Vec2::new(t.x, t.y))
}

/// How far from `at` the cutter starts `l`: its nearest contact point, or an
/// arc's nearer end.
fn reach_of(l: &Loop, at: Vec2) -> f64 {
    if l.closed {
        l.contact
            .iter()
            .map(|q| q.dist(at))
            .fold(f64::INFINITY, f64::min)
    } else {
        let (a, b) = (l.contact[0], l.contact[l.contact.len() - 1]);
        a.dist(at).min(b.dist(at))
    }
}

/// The tips of `l` in cutting order from `at`: a closed loop rotated to start
/// at the tip nearest `at` (XY), an arc from its nearer end.
fn oriented(l: &Loop, at: Vec3) -> Vec<Vec3> {
    if l.closed {
        return starting_near(l, at);
    }
    let d = |t: &Vec3| (t.x - at.x).powi(2) + (t.y - at.y).powi(2);
    let (first, last) = (&l.tip[0], &l.tip[l.tip.len() - 1]);
    if d(last) < d(first) {
        l.tip.iter().rev().copied().collect()
    } else {
        l.tip.clone()
    }
}

/// The tips of `l` rotated to start at the tip nearest `at` (XY).
fn starting_near(l: &Loop, at: Vec3) -> Vec<Vec3> {
    let k = l
        .tip
        .iter()
        .enumerate()
        .min_by(|a, b| {
            let d = |t: &Vec3| (t.x - at.x).powi(2) + (t.y - at.y).powi(2);
            d(a.1).total_cmp(&d(b.1))
        })
        .map_or(0, |(k, _)| k);
    l.tip[k..].iter().chain(&l.tip[..k]).copied().collect()
}

/// A feed link over the surface from `a` to `b`: straight in XY, sampled
/// every [`SAMPLE`], each point at the drop-cutter's height (the safe height
/// where no triangle lies under it), with points added between samples as
/// [`chord_safe`] adds them between a loop's tips.
fn surface_link(a: Vec3, b: Vec3, p: &FinishParams, mesh: &MeshIndex) -> Vec<Vec3> {
    let (pa, pb) = (Vec2::new(a.x, a.y), Vec2::new(b.x, b.y));
    let k = (pa.dist(pb) / SAMPLE).ceil().max(1.0) as usize;
    let pts: Vec<(f64, f64)> = (1..k)
        .map(|j| {
            let q = pa.lerp(pb, j as f64 / k as f64);
            (q.x, q.y)
        })
        .collect();
    let zs = p.cutter.drop_many(mesh, &pts);
    let mut path: Vec<Vec3> = std::iter::once(a)
        .chain(
            pts.iter()
                .zip(zs)
                .map(|(&(x, y), z)| Vec3::new(x, y, z.unwrap_or(p.safe_z))),
        )
        .collect();
    path.push(b);
    // Between the samples as between a loop's tips: a link that climbs a
    // wall passes under the top edge between two samples that clear it.
    let chords: Vec<(Vec3, Vec3)> = path.windows(2).map(|w| (w[0], w[1])).collect();
    let mut out = Vec::with_capacity(path.len());
    for (&(_, b), added) in chords.iter().zip(split_chords(&chords, p, mesh)) {
        out.extend(added);
        out.push(b);
    }
    out
}

/// The height above which an entry's ramp starts `p.entry` up, at the first
/// tip `first` of a loop: the higher of that tip and the tip of the cutter
/// grown by the stock to leave, dropped on S2 there. The cutter at the grown
/// one's tip plus `leave` lies `leave` off S2 in every direction, out of
/// what the roughing left across the walls, and `entry` = stepdown +
/// `leave` + 0.5 mm then puts it a stepdown and 0.5 mm over that, as over a
/// flat floor (where the two tips are one). On a gentle slope the grown
/// cutter's tip lies only `leave`·(sec θ − 1) over the cutter's; beside a
/// near-vertical wall the cutter's side stands at the wall all the way up,
/// and only the grown cutter, resting on the wall's top edge, finds where the
/// stock left on the wall ends (mfs-sign's power wall: a rapid 0.24 mm into
/// it, docs/method.md §13).
fn entry_base(first: Vec3, p: &FinishParams, mesh: &MeshIndex) -> f64 {
    let grown = p.grown(p.leave).drop(mesh, first.x, first.y);
    grown.map_or(first.z, |z| first.z.max(z))
}

/// The XY length of the move from `a` to `b`, mm.
fn run_xy(a: Vec3, b: Vec3) -> f64 {
    ((b.x - a.x).powi(2) + (b.y - a.y).powi(2)).sqrt()
}

/// Whether the polyline from `at` through `pts` descends anywhere steeper
/// than `slope` (Δz over XY length) by more than a micrometre.
fn dives(at: Vec3, pts: &[Vec3], slope: f64) -> bool {
    std::iter::once(&at)
        .chain(pts)
        .zip(pts)
        .any(|(a, b)| a.z - b.z > slope * run_xy(*a, *b) + 1e-3)
}

/// The moves of the whole program from the loops in order (see the module
/// docs). Where each loop starts depends only on where the one before it
/// ended, so the starts are placed in order first (cheap), and the sections,
/// whose links, entries and thinning drop the cutter thousands of times,
/// are then built in parallel, in order.
pub(crate) fn moves(
    loops: &[Loop],
    order: &[(usize, bool)],
    p: &FinishParams,
    mesh: &MeshIndex,
) -> Toolpath {
    use rayon::prelude::*;
    let start = Vec3::new(0.0, 0.0, p.safe_z);
    let mut at = start;
    let mut placed = Vec::with_capacity(order.len());
    for &(i, linked) in order {
        let l = &loops[i];
        let tips = oriented(l, at);
        let end = if l.closed {
            tips[0]
        } else {
            tips[tips.len() - 1]
        };
        placed.push((l, linked, at, tips));
        at = end;
    }
    let mut sections: Vec<Section> = placed
        .into_par_iter()
        .map(|(l, linked, at, tips)| section(l, linked, at, tips, p, mesh))
        .collect();
    if let Some(last) = sections.last_mut() {
        last.moves.push(Move::Rapid {
            to: Vec3::new(at.x, at.y, p.safe_z),
        });
    }
    Toolpath { start, sections }
}

/// One loop's section: from `at`, where the tool is, a feed link over the
/// surface when `linked` (unless it would dive) or a retract, a rapid and
/// the entry's ramp; then round the loop's `tips` (already oriented for
/// `at`), thinned.
fn section(
    l: &Loop,
    linked: bool,
    at: Vec3,
    tips: Vec<Vec3>,
    p: &FinishParams,
    mesh: &MeshIndex,
) -> Section {
    let _stage = crate::count::enter(crate::count::Stage::FinishMoves);
    let tan = p.ramp_angle.to_radians().tan();
    let mut mv = Vec::with_capacity(tips.len() + 8);
    let first = tips[0];
    // A link that would dive into the wall steeper than a pass may is
    // replaced by a retract and a ramp.
    let link = linked
        .then(|| surface_link(at, first, p, mesh))
        .filter(|l| !dives(at, l, DESCENT_SLOPE));
    if let Some(link) = link {
        for q in link {
            mv.push(Move::Linear {
                to: q,
                feed: p.feed,
            });
        }
    } else {
        // Over at the retract height, or higher where the tool already is.
        let over = at.z.max(p.retract_z);
        if at.z < over {
            mv.push(Move::Rapid {
                to: Vec3::new(at.x, at.y, over),
            });
        }
        mv.push(Move::Rapid {
            to: Vec3::new(first.x, first.y, over),
        });
        let top = (entry_base(first, p, mesh) + p.entry).min(over);
        mv.push(Move::Rapid {
            to: Vec3::new(first.x, first.y, top),
        });
        mv.extend(ramp(&tips, l.closed, top, tan, p));
    }
    let back = l.closed.then_some(&first);
    for q in tips.iter().skip(1).chain(back) {
        mv.push(Move::Linear {
            to: *q,
            feed: p.feed,
        });
    }
    let z = tips.iter().map(|t| t.z).fold(f64::INFINITY, f64::min);
    Section {
        label: match l.at {
            At::S(s) => format!("{} {} s {s:.5}", crate::toolpath::FINISH_PASS, l.pass + 1),
            At::D(d) => format!("{} {} d {d:.3}", crate::toolpath::FINISH_PASS, l.pass + 1),
        },
        z,
        moves: simplify(at, mv, p.tol, &|m| {
            p.cutter
                .drop_above(mesh, m.x, m.y, chord_threshold(&m, p.tol))
                .is_some()
        }),
    }
}

/// The entry's ramp from `top` over the first of `tips` down to the pass at
/// `tan` (the ramp angle's tangent) and the ramp feed
/// ([`crate::toolpath::entry::ramp_feed`]), then back at depth to the first tip:
/// along a closed loop round and round until the ramp line is below every
/// tip, then on round to the start; along an arc to and fro, then back.
fn ramp(tips: &[Vec3], closed: bool, top: f64, tan: f64, p: &FinishParams) -> Vec<Move> {
    let n = tips.len();
    let mut mv = Vec::new();
    if n < 2 {
        mv.push(Move::Linear {
            to: tips[0],
            feed: p.plunge_feed,
        });
        return mv;
    }
    // The k-th tip of the ramp's walk.
    let period = 2 * (n - 1);
    let index = |k: usize| {
        if closed {
            k % n
        } else if k % period < n {
            k % period
        } else {
            period - k % period
        }
    };
    let zmin = tips.iter().map(|t| t.z).fold(f64::INFINITY, f64::min);
    let first = tips[0];
    let feed = crate::toolpath::entry::ramp_feed(p.feed, p.plunge_feed, p.ramp_angle);
    // Enough steps to descend from `top` to `zmin` at `tan` (each walk of
    // the pass runs its XY length), with one walk to spare.
    let walk: f64 = (1..=period.min(n))
        .map(|k| run_xy(tips[index(k - 1)], tips[index(k)]))
        .sum();
    let walks = ((top - zmin) / tan / walk.max(1e-3)).ceil().min(1e4) as usize + 1;
    let (mut z, mut prev) = (top, Vec3::new(first.x, first.y, top));
    let mut k = 1;
    while z > zmin && k <= walks * n {
        let q = tips[index(k)];
        z -= prev.dist(Vec3::new(q.x, q.y, prev.z)) * tan;
        let to = Vec3::new(q.x, q.y, q.z.max(z));
        mv.push(Move::Linear { to, feed });
        prev = to;
        k += 1;
    }
    // Back to the start at depth, along the pass.
    let at = index(k - 1);
    let back: Vec<Vec3> = if closed {
        tips[at..].iter().skip(1).copied().collect()
    } else {
        tips[..at].iter().rev().copied().collect()
    };
    for q in back {
        mv.push(Move::Linear {
            to: q,
            feed: p.feed,
        });
    }
    if closed || at != 0 {
        mv.push(Move::Linear {
            to: first,
            feed: p.feed,
        });
    }
    mv
}

/// Runs of feed moves at one feed thinned where a point lies within `tol`/4 of
/// the chord of its neighbours (3-D Douglas–Peucker); rapids and feed changes
/// are kept.
fn simplify(start: Vec3, moves: Vec<Move>, tol: f64, under: &Under<'_>) -> Vec<Move> {
    let eps = 0.25 * tol;
    let mut out = Vec::with_capacity(moves.len() / 4);
    let mut run: Vec<Vec3> = Vec::new();
    let mut run_feed = f64::NAN;
    let flush = |run: &mut Vec<Vec3>, feed: f64, out: &mut Vec<Move>| {
        if run.len() > 1 {
            for q in douglas_peucker(run, eps, under).into_iter().skip(1) {
                out.push(Move::Linear { to: q, feed });
            }
        }
        run.clear();
    };
    let mut at = start;
    for m in moves {
        match m {
            Move::Linear { to, feed } => {
                if feed != run_feed {
                    flush(&mut run, run_feed, &mut out);
                    // A run starts where the tool is.
                    run.push(at);
                    run_feed = feed;
                }
                run.push(to);
            }
            other => {
                flush(&mut run, run_feed, &mut out);
                out.push(other);
                run_feed = f64::NAN;
            }
        }
        at = m.to();
    }
    flush(&mut run, run_feed, &mut out);
    out
}

/// Whether a point of a straight move lies under the drop-cutter's height by
/// more than a quarter of the tolerance.
type Under<'a> = dyn Fn(Vec3) -> bool + Sync + 'a;

/// The points of a polyline kept by Douglas–Peucker within `eps` (ends
/// kept), and where a chord would pass `under` the drop height at the
/// place of a point it drops (its projection on the chord), that point kept
/// too: beside a near-vertical wall the cutter touches with its side, a
/// chord a micrometre off the tips in XY is tens of micrometres into the
/// wall measured vertically (the README sign's power wall: 0.0013 mm in Y,
/// a 0.021 mm gouge).
fn douglas_peucker(pts: &[Vec3], eps: f64, under: &Under<'_>) -> Vec<Vec3> {
    let keep = crate::geometry::thin::keep_mask(
        pts.len(),
        eps,
        |k, a, b| seg_dist(pts[k], pts[a], pts[b]),
        |a, b| (a + 1..b).find(|&k| under(on_chord(pts[k], pts[a], pts[b]))),
    );
    pts.iter()
        .zip(keep)
        .filter(|(_, k)| *k)
        .map(|(q, _)| *q)
        .collect()
}

/// The point of the chord a–b at the parameter of `q`'s projection on it
/// in XY.
fn on_chord(q: Vec3, a: Vec3, b: Vec3) -> Vec3 {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((q.x - a.x) * dx + (q.y - a.y) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    Vec3::new(a.x + t * dx, a.y + t * dy, a.z + t * (b.z - a.z))
}

/// Distance from `q` to the segment a–b in 3-D.
fn seg_dist(q: Vec3, a: Vec3, b: Vec3) -> f64 {
    let d = [b.x - a.x, b.y - a.y, b.z - a.z];
    let e = [q.x - a.x, q.y - a.y, q.z - a.z];
    let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let t = if dd > 0.0 {
        ((e[0] * d[0] + e[1] * d[1] + e[2] * d[2]) / dd).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let f = [e[0] - t * d[0], e[1] - t * d[1], e[2] - t * d[2]];
    (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An entry's ramp onto a flat open pass runs at the cutting feed where
    /// that descends no faster than the plunge feed (as the roughing's
    /// entries do, `toolpath::entry::ramp_feed`): at 3° a 1000 mm/min feed
    /// goes down at 52 mm/min, under the 200 mm/min plunge feed. Every ramp
    /// move goes down no faster than the plunge feed, and the ramp reaches
    /// the pass.
    #[test]
    fn an_entry_ramp_descends_no_faster_than_the_plunge_feed() {
        let profile = crate::finish::testing::step_profile();
        let p = crate::finish::testing::params(&profile);
        let tips: Vec<Vec3> = (0..=20)
            .map(|i| Vec3::new(0.5 * i as f64, 0.0, -1.0))
            .collect();
        let top = 0.7;
        let mv = ramp(&tips, false, top, p.ramp_angle.to_radians().tan(), &p);
        let mut at = Vec3::new(0.0, 0.0, top);
        let mut ramped = 0;
        for m in &mv {
            let Move::Linear { to, feed } = *m else {
                panic!("{m:?}")
            };
            let minutes = at.dist(to) / feed;
            if to.z < at.z - 1e-12 {
                ramped += 1;
                assert_eq!(feed, p.feed, "{m:?}");
                assert!((at.z - to.z) / minutes <= p.plunge_feed, "{at:?} to {m:?}");
            }
            at = to;
        }
        assert!(ramped >= 10, "{ramped} ramp moves");
        assert!((at.z + 1.0).abs() < 1e-12 && at.x.abs() < 1e-12, "{at:?}");
    }

    /// A link that climbs from the floor to the top edge of a vertical wall:
    /// between two samples 0.1 mm apart the ball's drop height rises like a
    /// square root where the ball's side meets the edge, and the straight
    /// move between them passed up to 0.8 mm under it. Every move of the link
    /// stays above the drop height at 20 points along it.
    #[test]
    fn a_link_climbing_a_wall_stays_above_the_drop_height() {
        let mesh = crate::finish::testing::step_mesh();
        let profile = crate::finish::testing::step_profile();
        let p = crate::finish::testing::params(&profile);
        let at = |x: f64, y: f64| Vec3::new(x, y, p.cutter.drop(&mesh, x, y).unwrap());
        let (a, b) = (at(-2.03, 0.0), at(-0.47, 0.2));
        assert!(b.z > -1.2 && a.z == -3.0, "{a:?} {b:?}");
        let link = surface_link(a, b, &p, &mesh);
        let mut worst: f64 = 0.0;
        for w in std::iter::once(&a)
            .chain(&link)
            .collect::<Vec<_>>()
            .windows(2)
        {
            for k in 1..20 {
                let t = k as f64 / 20.0;
                let (x, y, z) = (
                    w[0].x + t * (w[1].x - w[0].x),
                    w[0].y + t * (w[1].y - w[0].y),
                    w[0].z + t * (w[1].z - w[0].z),
                );
                worst = worst.max(p.cutter.drop(&mesh, x, y).unwrap() - z);
            }
        }
        assert!(
            worst <= p.tol,
            "a move passes {worst} mm under the drop height"
        );
    }

    /// An entry beside a vertical wall whose roughing left `leave` across it:
    /// the ball, its axis 0.01 mm beyond r from the wall, rests on the floor,
    /// and a rapid down to a ramp start `leave` over that tip drove its side
    /// through the band the roughing left. The entry's base is where the
    /// cutter grown by `leave` rests on the wall's top edge; `leave` over it
    /// (the entry with no stepdown and no margin) the ball clears the band,
    /// as the circle of the ball's section shows: its section at the wall's
    /// top reaches no farther than r − leave + 0.01 from the axis. On the
    /// open floor the base is the tip itself.
    #[test]
    fn an_entry_beside_a_vertical_wall_stays_over_the_stock_left_on_it() {
        let mesh = crate::finish::testing::step_mesh();
        let profile = crate::finish::testing::step_profile();
        let leave = 0.2;
        let p = FinishParams {
            entry: leave,
            leave,
            ..crate::finish::testing::params(&profile)
        };
        let r = p.cutter.radius;
        let x = 1.0 - r - 0.01;
        let first = Vec3::new(x, 0.0, p.cutter.drop(&mesh, x, 0.0).unwrap());
        assert_eq!(first.z, -3.0);
        let tip = entry_base(first, &p, &mesh) + p.entry;
        // The band of stock lies (r + 0.01 − leave) .. (r + 0.01) from the
        // axis up to z = 0; the ball's section at height z has radius
        // √(r² − (tip + r − z)²).
        let reach = r + 0.01 - leave;
        let need = 0.0 - r + (r * r - reach * reach).sqrt();
        assert!(tip >= need - 1e-9, "tip {tip} under {need}");
        assert!(
            first.z + p.entry < need,
            "the test needs the old entry to fail"
        );
        // Out on the floor the entry starts over the tip, as before.
        let far = Vec3::new(-6.0, 0.0, -3.0);
        assert_eq!(entry_base(far, &p, &mesh), -3.0);
    }

    /// z = tan θ · max(0, x, y) (`corner`) or tan θ · max(0, x) on a 0.1 mm
    /// grid over ±5 mm: a floor meeting a wall that rises at θ for x ≥ 0
    /// along the crease x = 0, and with `corner` also for y ≥ 0, the crease
    /// then turning a right angle round the origin, a corner of the floor.
    fn crease_mesh(theta: f64, corner: bool) -> MeshIndex {
        let z = |x: f64, y: f64| theta.tan() * if corner { x.max(y) } else { x }.max(0.0);
        let p = |i: i32, j: i32| {
            let (x, y) = (i as f64 * 0.1, j as f64 * 0.1);
            [x, y, z(x, y)]
        };
        let mut tris = Vec::new();
        for i in -50..50 {
            for j in -50..50 {
                // Split along the diagonal x − y = const: the creases are edges.
                tris.push([p(i, j), p(i + 1, j), p(i + 1, j + 1)]);
                tris.push([p(i, j), p(i + 1, j + 1), p(i, j + 1)]);
            }
        }
        MeshIndex::new(tris, 0.4)
    }

    #[test]
    fn in_a_straight_crease_the_ball_is_wedged_and_round_a_tight_corner_it_sits_on_the_floor() {
        let theta = 20f64.to_radians();
        let r = 1.5875;
        let ball = Cutter::ball(r);
        // At the contact point (0, −3) the surface falls away along −x; with
        // |∇u| = 1, φ′ = tan θ.
        let (q, d, g) = (
            Vec2::new(0.0, -3.0),
            Vec2::new(-1.0, 0.0),
            Vec2::new(1.0, 0.0),
        );
        let straight = crease_mesh(theta, false);
        let (axis, _) = crease_axis(q, d, g, theta.tan(), ball, Some((&straight, 0.005)));
        let tip = ball.drop(&straight, axis.x, axis.y).unwrap();
        // Wedged: on the floor, r·tan(θ/2) from the crease, and the ball
        // comes within r·(1/cos(θ/2) − 1) of it, the least any position can.
        assert!(tip.abs() < 1e-9, "{tip}");
        assert!((axis.x + r * (theta / 2.0).tan()).abs() < 1e-9, "{axis:?}");
        let gap = (axis.x.powi(2) + (tip + r).powi(2)).sqrt() - r;
        assert!(
            (gap - r * (1.0 / (theta / 2.0).cos() - 1.0)).abs() < 1e-9,
            "{gap}"
        );
        // The wall's own normal would hold the ball r·sin θ out, r·(1 − cos
        // θ) short of the crease: farther from it.
        let (wall, _) = crease_axis(q, d, g, theta.tan(), ball, None);
        let wall_gap = (wall.x.powi(2) + r.powi(2)).sqrt() - r;
        assert!(wall_gap > 2.0 * gap, "{wall_gap} vs {gap}");
        // In the corner (the floor falling away along the diagonal) both
        // faces lift the bisector's ball; the wall's axis, farther out, is
        // kept where that lift passes the allowed 0.005 mm.
        let corner = crease_mesh(theta, true);
        let (q, d) = (Vec2::new(0.0, 0.0), Vec2::new(-1.0, -1.0).normalized());
        let (axis, _) = crease_axis(q, d, d * -1.0, theta.tan(), ball, Some((&corner, 0.005)));
        let half = axis_at(q, d, d * -1.0, (theta.tan(), true), ball).0;
        let lifted = ball.drop(&corner, half.x, half.y).unwrap();
        assert!(lifted > 0.005, "{lifted}");
        assert!((axis - d * (r * theta.sin())).norm() < 1e-9, "{axis:?}");
        assert!(ball.drop(&corner, axis.x, axis.y).unwrap() < lifted - 0.005);
    }

    #[test]
    fn douglas_peucker_keeps_what_bends_and_drops_what_does_not() {
        let line: Vec<Vec3> = (0..=10).map(|k| Vec3::new(k as f64, 0.0, 0.0)).collect();
        assert_eq!(douglas_peucker(&line, 1e-3, &|_| false).len(), 2);
        let mut bent = line.clone();
        bent[5].z = 0.01;
        let kept = douglas_peucker(&bent, 1e-3, &|_| false);
        assert!(kept.contains(&bent[5]), "{kept:?}");
        assert_eq!(douglas_peucker(&bent, 0.02, &|_| false).len(), 2);
        // Every dropped point lies within eps of the kept polyline.
        let arc: Vec<Vec3> = (0..=200)
            .map(|k| {
                let t = k as f64 / 200.0;
                Vec3::new(10.0 * t.cos(), 10.0 * t.sin(), t)
            })
            .collect();
        let kept = douglas_peucker(&arc, 0.002, &|_| false);
        for q in &arc {
            let d = kept
                .windows(2)
                .map(|w| seg_dist(*q, w[0], w[1]))
                .fold(f64::INFINITY, f64::min);
            assert!(d <= 0.002 + 1e-12, "{d}");
        }
        assert!(kept.len() < arc.len() / 2);
        // A chord within eps that would pass under the drop height at a
        // dropped point's place keeps that point.
        let wall = |m: Vec3| m.y < -0.0005 && (m.x - 5.0).abs() < 1.0;
        let mut near: Vec<Vec3> = line.clone();
        near[10].y = -0.002;
        let kept = douglas_peucker(&near, 1e-2, &wall);
        assert!(kept.len() > 2, "{kept:?}");
        for w in kept.windows(2) {
            for q in &near {
                if q.x > w[0].x && q.x < w[1].x {
                    assert!(!wall(on_chord(*q, w[0], w[1])), "{q:?} under {w:?}");
                }
            }
        }
    }

    #[test]
    fn the_descent_limit_only_raises_holds_the_slope_and_ignores_the_start() {
        // A loop round a square whose tips dip into a pit on one side.
        let tips: Vec<Vec3> = (0..40)
            .map(|k| {
                let t = k as f64 / 40.0 * std::f64::consts::TAU;
                let z = if (10..14).contains(&k) {
                    -2.0
                } else {
                    -0.1 * t.sin()
                };
                Vec3::new(5.0 * t.cos(), 5.0 * t.sin(), z)
            })
            .collect();
        let slope = DESCENT_SLOPE;
        let out = limit_descent(tips.clone(), true, slope);
        for (a, b) in tips.iter().zip(&out) {
            assert!(b.z >= a.z && (a.x, a.y) == (b.x, b.y));
        }
        for k in 0..out.len() {
            let (a, b) = (out[k], out[(k + 1) % out.len()]);
            assert!(
                a.z - b.z <= slope * run_xy(a, b) + 1e-12,
                "{k}: {a:?} -> {b:?}"
            );
        }
        // The pit's far side is not raised: only descents are limited.
        assert_eq!(out[13].z, -2.0);
        assert!(out[10].z > -2.0);
        // Starting the loop elsewhere gives the same heights.
        let mut cycled = tips.clone();
        cycled.rotate_left(17);
        let mut again = limit_descent(cycled, true, slope);
        again.rotate_right(17);
        assert_eq!(again, out);
    }

    #[test]
    fn a_link_dives_only_where_it_falls_steeper_than_the_slope() {
        let at = Vec3::new(0.0, 0.0, 0.0);
        let gentle = [Vec3::new(1.0, 0.0, -0.5), Vec3::new(2.0, 0.0, -1.0)];
        assert!(!dives(at, &gentle, DESCENT_SLOPE));
        let steep = [Vec3::new(1.0, 0.0, -0.5), Vec3::new(1.1, 0.0, -1.0)];
        assert!(dives(at, &steep, DESCENT_SLOPE));
        // Climbing steeply is not diving.
        let up = [Vec3::new(0.1, 0.0, 2.0)];
        assert!(!dives(at, &up, DESCENT_SLOPE));
    }

    /// Points near the level Γ(s) of one charge's field (circles) land on it;
    /// a point farther than ONTO_LEVEL from it stays.
    #[test]
    fn points_of_a_level_of_sigma_move_onto_their_equipotential() {
        let field = Field::new(vec![Vec2::new(0.0, 0.0)], vec![1.0]);
        let s = field.value(Vec2::new(2.0, 0.0));
        let mut pts: Vec<Vec2> = (0..12)
            .map(|k| {
                let a = k as f64 * 0.5;
                Vec2::new(a.cos(), a.sin()) * (2.0 + 0.02 * (k as f64 / 11.0 - 0.5))
            })
            .collect();
        let far = Vec2::new(0.0, 2.5);
        pts.push(far);
        let before = pts.clone();
        let targets = vec![s; pts.len()];
        onto_levels(&mut pts, &targets, &field);
        for (q, b) in pts.iter().zip(&before).take(12) {
            assert!((q.norm() - 2.0).abs() < 1e-9, "{b:?} -> {q:?}");
            assert!(q.dist(*b) <= ONTO_LEVEL);
        }
        assert_eq!(pts[12], far);
    }

    #[test]
    fn resampling_keeps_the_corners_and_bounds_the_spacing() {
        let sq = vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
        ];
        let r = densify(&sq, 0.3, true);
        assert_eq!(r.len(), 16);
        for c in &sq {
            assert!(r.contains(c));
        }
        for k in 0..r.len() {
            assert!(r[k].dist(r[(k + 1) % r.len()]) <= 0.3 + 1e-12);
        }
    }
}
