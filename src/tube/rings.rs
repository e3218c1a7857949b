//! Finishing a PDE tube along its sections: one closed pass of the
//! `[finish]` ball or bull nose around each section ring X(u(z), ·), from
//! the floor up, the rings spaced for `finish.scallop`.
//!
//! - **Spacing.** Two contact curves d apart on the surface leave a scallop
//!   of h when d = w = 2√(2·rc·h − h²) (rc the cutter's corner radius,
//!   `finish::passes::pass_width`). From the lowest ring (z = −H) the next
//!   is the highest z' (bisected) with max over v of |X(u(z'), v) −
//!   X(u(z), v)| ≤ w: the distance between the curves is at most that of
//!   points at the same v, so neighbouring rings are at most w apart.
//! - **The cutter at a contact point.** For the contact p = X(u, v) with
//!   unit normal n pointing out of the material (±Xᵤ × Xᵥ), the corner
//!   circle's centre is p + rc·n and the axis (r − rc) further along n's
//!   horizontal direction; its tip height is then the drop-cutter's against
//!   the part's mesh (`toolpath::dropcutter`: the lowest at which the cutter
//!   touches no triangle), so the finisher never enters the modelled part.
//! - **Samples.** A ring has the section's P points (chords within 0.1 ×
//!   tolerance on the surface), and every chord between two tips whose
//!   midpoint lies more than tol/2 under the drop there is halved (up to
//!   `REFINE_DEPTH` times), as the patch's raster does.
//! - **Links.** Ring k's end (its start: a ring is closed) to ring k + 1's
//!   start follows the drop at samples `LINK_STEP` apart: a feed over the
//!   surface, never below it. The first ring is entered from `APPROACH` mm
//!   off its start along the normal, into free space (off the wall), where
//!   the cutter comes down from the retract height.
//! - **Direction.** Climb milling (`operation.direction`): clockwise seen
//!   from above round a boss, counter-clockwise round a mould's pocket.

use super::ring_contacts::{Contact, Rings};
use crate::finish::{cutter_of, passes::pass_width, FinishError, Finished};
use crate::job::{CutterShape, Direction, Finish, Job};
use crate::levels::sections::Sections;
use crate::sources::pde_tube::{PdeTube, TubeKind};
use crate::toolpath::dropcutter::{Cutter, MeshIndex};
use crate::toolpath::{Move, Section, Toolpath, Vec3};

/// Most rings of a finish.
pub(crate) const MAX_RINGS: usize = 20_000;

/// Most samples of all rings together (each is a G-code line).
pub(crate) const MAX_SAMPLES: usize = 4_000_000;

/// Halvings of a chord at most where it strays below the drop.
const REFINE_DEPTH: usize = 8;

/// Samples of a link between rings, mm apart at most.
const LINK_STEP: f64 = 0.05;

/// How far off the first ring's start the cutter comes down, mm.
const APPROACH: f64 = 1.0;

/// The steepest descent along a ring with a slot (tan 40°: `simulate`
/// calls a descent over 45° into material a plunge).
const MAX_DESCENT: f64 = 0.839;

/// Bisections of a ring's height.
const BISECTIONS: usize = 40;

/// The finish's part: the tube, its mesh and the wall's area (mm², for the
/// time's lower bound).
pub(crate) struct RingPart<'a> {
    /// The tube.
    pub(crate) tube: &'a PdeTube,
    /// The part's mesh, for the drop-cutter.
    pub(crate) mesh: &'a MeshIndex,
    /// The wall's area, mm².
    pub(crate) area: f64,
    /// Machine z of the tube's top (the stock top), mm.
    pub(crate) top: f64,
    /// Where the rings touch ([`Rings`]).
    pub(crate) rings: &'a Rings,
}

/// The ring heights z (relative to the top), from −H up to 0, neighbours'
/// curves at most `w` apart at equal v (module doc).
fn ring_heights(tube: &PdeTube, w: f64) -> Result<Vec<f64>, FinishError> {
    let (lo, hi) = tube.z_range();
    let p = tube.points();
    let ring = |z: f64| tube.surface().ring(tube.u_of(z), p);
    let apart = |a: &[[f64; 3]], b: &[[f64; 3]]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (0..3).map(|i| (x[i] - y[i]).powi(2)).sum::<f64>().sqrt())
            .fold(0.0, crate::num::max_or_nan)
    };
    let mut zs = vec![lo];
    let mut here = ring(lo);
    while zs.last().is_some_and(|&z| z < hi) {
        if zs.len() > MAX_RINGS {
            return Err(FinishError::TooManyRings { max: MAX_RINGS });
        }
        let z = *zs.last().unwrap_or(&lo);
        // |Δz| ≤ the distance, so the next ring is at most w higher.
        let top = (z + w).min(hi);
        let next = if apart(&here, &ring(top)) <= w {
            top
        } else {
            let (mut a, mut b) = (z, top);
            for _ in 0..BISECTIONS {
                let m = 0.5 * (a + b);
                if apart(&here, &ring(m)) <= w {
                    a = m;
                } else {
                    b = m;
                }
            }
            a
        };
        if next <= z {
            return Err(FinishError::RingsStall { z });
        }
        zs.push(next);
        here = ring(next);
    }
    Ok(zs)
}

/// The point X(u, v) and the unit normal into free space there (±Xᵤ × Xᵥ:
/// away from the axis for a boss, toward it for a mould); `None` where the
/// normal is not defined.
pub(super) fn wall_normal(tube: &PdeTube, u: f64, v: f64) -> Option<([f64; 3], [f64; 3])> {
    let s = tube.surface();
    let (p, xu, xv) = (s.point(u, v), s.du(u, v), s.dv(u, v));
    let n = [
        xu[1] * xv[2] - xu[2] * xv[1],
        xu[2] * xv[0] - xu[0] * xv[2],
        xu[0] * xv[1] - xu[1] * xv[0],
    ];
    let c = s.spine().point(u);
    let out = (p[0] - c[0]) * n[0] + (p[1] - c[1]) * n[1];
    // A boss's free space is away from the axis, a mould's toward it.
    let flip = (out < 0.0) == (tube.kind() == TubeKind::Boss);
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len.is_nan() || len <= 0.0 {
        return None;
    }
    let sign = if flip { -1.0 } else { 1.0 } / len;
    Some((p, n.map(|x| x * sign)))
}

/// The cutter's tip (x, y, z relative to the curves' frame) touching the
/// contact p alone, n the unit normal into free space there, and the
/// horizontal direction of n.
fn tip_at(p: [f64; 3], n: [f64; 3], f: &Finish) -> ([f64; 3], [f64; 2]) {
    // The horizontal direction of n (none where the wall is flat).
    let h = n[0].hypot(n[1]);
    let hz = if h > 1e-12 {
        [n[0] / h, n[1] / h]
    } else {
        [0.0, 0.0]
    };
    let (r, rc) = (f.radius(), f.corner);
    let x = p[0] + rc * n[0] + (r - rc) * hz[0];
    let y = p[1] + rc * n[1] + (r - rc) * hz[1];
    // The tip touching at p alone: the corner circle's lowest point.
    let z = p[2] + rc * n[2] - rc;
    ([x, y, z], hz)
}

/// The drop-cutter against the tube's part.
struct Dropper<'a> {
    cutter: Cutter,
    mesh: &'a MeshIndex,
}

impl Dropper<'_> {
    fn at(&self, x: f64, y: f64) -> Option<Vec3> {
        self.cutter
            .drop(self.mesh, x, y)
            .map(|z| Vec3::new(x, y, z))
    }

    /// Points between `a` and `b` (exclusive) so that no chord's midpoint
    /// lies more than `tol` below the drop.
    fn refine(&self, a: Vec3, b: Vec3, tol: f64, depth: usize, out: &mut Vec<Vec3>) {
        if depth == 0 {
            return;
        }
        let Some(m) = self.at(0.5 * (a.x + b.x), 0.5 * (a.y + b.y)) else {
            return;
        };
        if m.z > 0.5 * (a.z + b.z) + tol {
            self.refine(a, m, tol, depth - 1, out);
            out.push(m);
            self.refine(m, b, tol, depth - 1, out);
        }
    }

    /// The tips along `a`–`b` (exclusive of both), at most [`LINK_STEP`]
    /// apart, each at the higher of the line and the drop.
    fn link(&self, a: Vec3, b: Vec3) -> Vec<Vec3> {
        let n = (((b.x - a.x).hypot(b.y - a.y) / LINK_STEP).ceil() as usize).max(1);
        (1..n)
            .map(|k| {
                let t = k as f64 / n as f64;
                let (x, y, z) = (
                    a.x + t * (b.x - a.x),
                    a.y + t * (b.y - a.y),
                    a.z + t * (b.z - a.z),
                );
                let d = self.cutter.drop(self.mesh, x, y).unwrap_or(z);
                Vec3::new(x, y, z.max(d))
            })
            .collect()
    }
}

/// One ring at height `z` (relative): the tip over every contact
/// ([`super::ring_contacts`]: the curve's samples, with a slot its sides and
/// corners), in the cutting direction (`None` where the normal or the drop
/// is not defined), each with its contact's key, and the free-space
/// direction at its start.
struct Ring {
    z: f64,
    keys: Vec<i64>,
    tips: Vec<Option<Vec3>>,
    start_dir: [f64; 2],
    /// At each sample, whether the drop lifted the tip more than the
    /// tolerance off its nominal contact (the cutter resting on something
    /// else too).
    lifted: Vec<bool>,
}

/// The tip touching `c` alone (curves' frame) and the horizontal direction
/// of its normal.
fn contact_tip(tube: &PdeTube, f: &Finish, u: f64, c: Contact) -> Option<([f64; 3], [f64; 2])> {
    match c {
        Contact::Wall(v) => wall_normal(tube, u, v).map(|(p, n)| tip_at(p, n, f)),
        Contact::At(p, n) => Some(tip_at(p, n, f)),
        Contact::Drop(q) => Some(([q[0], q[1], f64::NEG_INFINITY], [0.0, 0.0])),
    }
}

fn ring_at(
    part: &RingPart,
    f: &Finish,
    dropper: &Dropper,
    (z, reverse, tol): (f64, bool, f64),
) -> Result<Ring, FinishError> {
    let tube = part.tube;
    let u = tube.u_of(z);
    let contacts = part.rings.contacts(tube, u, reverse)?;
    let mut start_dir = [0.0, 0.0];
    let mut lifted = vec![false; contacts.len()];
    // Machine z of the curves' frame: the tube's top is the stock top.
    let shift = part.top - tube.top_z();
    let tips = contacts
        .iter()
        .enumerate()
        .map(|(j, &(_, c))| {
            let (tip, dir) = contact_tip(tube, f, u, c)?;
            if j == 0 {
                start_dir = dir;
            }
            let mut at = dropper.at(tip[0], tip[1])?;
            // Beside a vertical side the drop finds the floor: the tip is
            // the contact's own, unless the drop is higher.
            if let Contact::At(..) = c {
                at.z = at.z.max(tip[2] + shift);
            }
            lifted[j] = at.z > tip[2] + shift + tol;
            Some(at)
        })
        .collect();
    Ok(Ring {
        z,
        keys: contacts.iter().map(|c| c.0).collect(),
        tips,
        start_dir,
        lifted,
    })
}

/// The largest ratio, over the contacts the two rings share (by key), of
/// the distance between their tips there (the balls' centres are the tips
/// raised by r: the same distance) to its limit (see [`rings_spaced`]).
fn tip_gap(a: &Ring, b: &Ring, (w, tol): (f64, f64)) -> f64 {
    let pairs: Vec<(usize, usize)> = if a.keys == b.keys {
        (0..a.keys.len()).map(|j| (j, j)).collect()
    } else {
        let index: std::collections::HashMap<i64, usize> =
            b.keys.iter().enumerate().map(|(j, &k)| (k, j)).collect();
        (0..a.keys.len())
            .filter_map(|j| Some((j, *index.get(&a.keys[j])?)))
            .collect()
    };
    pairs
        .into_iter()
        .filter_map(|(i, j)| {
            let d = a.tips[i].as_ref()?.dist(*b.tips[j].as_ref()?);
            let limit = match (a.lifted[i], b.lifted[j]) {
                (false, false) => w,
                (true, true) => 0.5 * w,
                _ => tol,
            };
            Some(d / limit)
        })
        .fold(0.0, crate::num::max_or_nan)
}

/// The rings at `zs`, with rings added half way between two neighbours
/// whose tips are more than a limit apart at some sample: w where both
/// tips there touch their nominal contacts, w/2 where the drop lifted both (round a
/// boss's foot, the cutter resting on the floor: there the contacts'
/// spacing no longer bounds the scallop, the tips' does), and the
/// tolerance where one is lifted and the other not. Between those two the
/// placements turn a corner, from resting on the floor to touching the
/// wall, and the fillet the ball leaves in the corner is reached only by
/// the placement touching both: on its steep side a ball 0.06 mm off that
/// placement left 0.041 mm more (measured on the vase), so the rings close
/// in on it to the tolerance.
fn rings_spaced(
    part: &RingPart,
    f: &Finish,
    dropper: &Dropper,
    zs: &[f64],
    (w, reverse, tol): (f64, bool, f64),
) -> Result<Vec<Ring>, FinishError> {
    use rayon::prelude::*;
    let mut rings: Vec<Ring> = zs
        .par_iter()
        .map(|&z| ring_at(part, f, dropper, (z, reverse, tol)))
        .collect::<Result<_, _>>()?;
    let mut k = 0;
    while k + 1 < rings.len() {
        let (za, zb) = (rings[k].z, rings[k + 1].z);
        if zb - za > 1e-6 && tip_gap(&rings[k], &rings[k + 1], (w, tol)) > 1.0 {
            if rings.len() >= MAX_RINGS {
                return Err(FinishError::TooManyRings { max: MAX_RINGS });
            }
            rings.insert(
                k + 1,
                ring_at(part, f, dropper, (0.5 * (za + zb), reverse, tol))?,
            );
        } else {
            k += 1;
        }
    }
    Ok(rings)
}

/// A ring's tips with every chord refined (`tol` under the drop at most).
fn refined(ring: &Ring, dropper: &Dropper, tol: f64) -> Vec<Vec3> {
    let tips: Vec<Vec3> = ring.tips.iter().flatten().copied().collect();
    let mut out = Vec::with_capacity(2 * tips.len());
    for w in tips.windows(2) {
        out.push(w[0]);
        dropper.refine(w[0], w[1], tol, REFINE_DEPTH, &mut out);
    }
    out.extend(tips.last().copied());
    out
}

/// Descents steeper than [`MAX_DESCENT`] (Δz over the XY length) raised to
/// it, each point at least the previous one's z less the slope times their
/// XY distance: round a slot's corner near its floor the drop lifts the
/// ball onto the edge of the wall below, and the next contact, on the
/// slot's side, rests on its floor; going straight down there would enter
/// the side's stock as a plunge. Raising a point never takes it under the
/// drop.
fn limit_descent(tips: &mut [Vec3]) {
    for j in 1..tips.len() {
        let (a, b) = (tips[j - 1], tips[j]);
        let floor = a.z - MAX_DESCENT * (b.x - a.x).hypot(b.y - a.y);
        if b.z < floor {
            tips[j].z = floor;
        }
    }
}

/// The finishing program of a tube job (module doc).
pub(crate) fn ring_finish(job: &Job, f: &Finish, part: &RingPart) -> Result<Finished, FinishError> {
    use rayon::prelude::*;
    if f.shape == CutterShape::Flat || f.corner <= 0.0 {
        return Err(FinishError::FlatOnWall);
    }
    let tol = job.operation.tolerance;
    let w = pass_width(f.corner, f.scallop);
    let mut zs = ring_heights(part.tube, w)?;
    for z in part.rings.extra_heights(part.tube) {
        if zs.iter().all(|&y| (y - z).abs() > 1e-4) {
            zs.push(z);
        }
    }
    zs.sort_by(f64::total_cmp);
    if zs.len().saturating_mul(part.tube.points()) > MAX_SAMPLES {
        return Err(FinishError::TooManyRingSamples {
            rings: zs.len(),
            samples: part.tube.points(),
            max: MAX_SAMPLES,
        });
    }
    let boss = part.tube.kind() == TubeKind::Boss;
    let reverse = boss == (job.operation.direction == Direction::Climb);
    let dropper = Dropper {
        cutter: cutter_of(f),
        mesh: part.mesh,
    };
    let spaced = rings_spaced(part, f, &dropper, &zs, (w, reverse, tol))?;
    let rings: Vec<(Vec<Vec3>, [f64; 2])> = spaced
        .par_iter()
        .map(|r| {
            let mut tips = refined(r, &dropper, 0.5 * tol);
            if part.rings.has_slot() {
                limit_descent(&mut tips);
            }
            (tips, r.start_dir)
        })
        .collect();
    let zs: Vec<f64> = spaced.iter().map(|r| r.z).collect();
    let mut sections = Vec::with_capacity(rings.len());
    let mut last: Option<Vec3> = None;
    for (k, (ring, dir)) in rings.iter().enumerate() {
        let Some(&b) = ring.first() else { continue };
        let mut moves = Vec::with_capacity(ring.len() + 64);
        let feed = |to| Move::Linear { to, feed: f.feed };
        match last {
            Some(a) => moves.extend(dropper.link(a, b).into_iter().chain([b]).map(feed)),
            None => {
                let p0 = Vec3::new(b.x + APPROACH * dir[0], b.y + APPROACH * dir[1], b.z);
                moves.push(Move::Rapid {
                    to: Vec3::new(p0.x, p0.y, job.stock.safe_z),
                });
                moves.push(Move::Rapid {
                    to: Vec3::new(p0.x, p0.y, job.stock.retract_z),
                });
                moves.push(Move::Linear {
                    to: p0,
                    feed: f.plunge_feed,
                });
                moves.extend(dropper.link(p0, b).into_iter().chain([b]).map(feed));
            }
        }
        moves.extend(ring[1..].iter().copied().map(feed));
        last = ring.last().copied();
        sections.push(Section {
            label: format!(
                "{} {} s {:.4}",
                crate::toolpath::FINISH_PASS,
                k + 1,
                part.tube.u_of(zs[k])
            ),
            z: ring.iter().map(|p| p.z).fold(f64::INFINITY, f64::min),
            moves,
        });
    }
    if let (Some(end), Some(s)) = (last, sections.last_mut()) {
        s.moves.push(Move::Rapid {
            to: Vec3::new(end.x, end.y, job.stock.safe_z),
        });
    }
    Ok(Finished {
        toolpath: Toolpath {
            start: Vec3::new(0.0, 0.0, job.stock.safe_z),
            sections,
        },
        width: w,
        lower_bound_s: part.area / w / f.feed * 60.0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::ShapeSource;

    /// The shipped vase's job, tube, and the part's mesh at 0.2 mm.
    fn vase() -> (Job, PdeTube, MeshIndex) {
        let text = include_str!("../../jobs/pde-vase.toml");
        let job = crate::job::parse_job(text, "vase", std::path::Path::new(".")).unwrap();
        let ShapeSource::PdeTube(spec) = &job.shape else {
            panic!("a tube")
        };
        let tube = spec.tube().unwrap();
        let stock = super::super::tube_stock(&job, &tube);
        let s = super::super::mesh::tube_mesh(&tube, 0.0, 0.2, stock).unwrap();
        let tris = (0..s.mesh.triangles.len())
            .map(|t| s.mesh.corners(t))
            .collect();
        (job, tube, MeshIndex::new(tris, 0.8))
    }

    #[test]
    fn rings_are_spaced_for_the_scallop_by_contacts_and_tips() {
        let (job, tube, mesh) = vase();
        let f = job.finish.clone().unwrap();
        let w = pass_width(f.corner, f.scallop);
        let zs = ring_heights(&tube, w).unwrap();
        assert_eq!((zs[0], *zs.last().unwrap()), (-15.0, 0.0));
        let p = tube.points();
        for pair in zs.windows(2) {
            assert!(pair[1] > pair[0]);
            let (a, b) = (
                tube.surface().ring(tube.u_of(pair[0]), p),
                tube.surface().ring(tube.u_of(pair[1]), p),
            );
            let d = a
                .iter()
                .zip(&b)
                .map(|(x, y)| (0..3).map(|i| (x[i] - y[i]).powi(2)).sum::<f64>().sqrt())
                .fold(0.0, f64::max);
            assert!(d <= w + 1e-9, "z {pair:?}: {d} > {w}");
        }
        let contacts = Rings::new(&tube, tube.points(), f.radius()).unwrap();
        let part = RingPart {
            tube: &tube,
            mesh: &mesh,
            area: 1.0,
            top: 0.0,
            rings: &contacts,
        };
        let dropper = Dropper {
            cutter: cutter_of(&f),
            mesh: &mesh,
        };
        let tol = job.operation.tolerance;
        let rings = rings_spaced(&part, &f, &dropper, &zs, (w, true, tol)).unwrap();
        assert!(rings.len() > zs.len(), "rings were added round the foot");
        // Round the foot some tips rest on the floor (lifted), higher up none.
        assert!(rings[0].lifted.iter().any(|&l| l));
        assert!(rings.last().unwrap().lifted.iter().all(|&l| !l));
        for pair in rings.windows(2) {
            assert!(tip_gap(&pair[0], &pair[1], (w, tol)) <= 1.0);
        }
        // The program: one closed ring per height, every tip at or above
        // the drop there.
        let done = ring_finish(&job, &f, &part).unwrap();
        assert_eq!(done.toolpath.sections.len(), rings.len());
        for s in &done.toolpath.sections {
            for m in &s.moves {
                if let Move::Linear { to, .. } = m {
                    let d = dropper.cutter.drop(&mesh, to.x, to.y).unwrap();
                    assert!(d <= to.z + 1e-9, "{to:?} under the drop {d}");
                }
            }
        }
        let flat = Finish {
            shape: CutterShape::Flat,
            corner: 0.0,
            ..f.clone()
        };
        assert_eq!(
            ring_finish(&job, &flat, &part),
            Err(FinishError::FlatOnWall)
        );
    }
}
