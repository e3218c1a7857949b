//! Where a finishing ring of a tube touches its section: the contacts in
//! cutting order, each with a key that matches it with the same contact of
//! the neighbouring rings (`rings::tip_gap`).
//!
//! - **Untrimmed**: X(u, vⱼ), vⱼ = 2πj/P, j = 0..P (the first again at the
//!   end), key j.
//! - **With a slot** (one trim, v ∈ [a, b], b − a < π, from u₀ up): every
//!   ring starts at v = a. Below the floor the whole curve, X(u, a + 2πk/P),
//!   key k. From the floor up the kept pie piece, counter-clockwise: X(u, a),
//!   round the wall's convex corner there to the slot's side a, along it
//!   inward to where the cutter touches both sides (r / tan(θ/2) from the
//!   spine, θ the angle between the sides), out along side b, round the
//!   corner to X(u, b), and along the wall to X(u, a + 2π). A side's contact
//!   has the horizontal normal into the slot; a corner's the normals turned
//!   from the side's to the wall's, about the corner point. Climb milling
//!   runs the list backwards.

use crate::finish::FinishError;
use crate::sources::pde_tube::PdeTube;
use std::f64::consts::TAU;

/// A ring's contact.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Contact {
    /// On the wall, at X(u, v).
    Wall(f64),
    /// At a point (x, y, z in the curves' frame) with the unit normal into
    /// free space there.
    At([f64; 3], [f64; 3]),
    /// Wherever the drop puts the cutter over (x, y) (the top ring's way
    /// into the slot's V, riding on the two sides' top edges).
    Drop([f64; 2]),
}

/// Contacts per side.
const SIDE_STEP: f64 = 0.1;
/// Contacts round a corner.
const CORNER: usize = 24;
/// Keys of the sides' and corners' contacts.
const SIDE_A: i64 = 1_000_000;
const SIDE_B: i64 = 2_000_000;
const CORNER_A: i64 = 3_000_000;
const CORNER_B: i64 = 4_000_000;
const KEY_B: i64 = -1;
const V_KEY: i64 = 5_000_000;
/// Steps along the bisector into the V on the top ring (mm).
const V_STEP: f64 = 0.05;
/// How far short of touching both sides the deepest contact stays (mm).
const V_MARGIN: f64 = 1e-2;
/// How far off a side its contacts are taken (mm): a ball exactly
/// tangent to a vertical face touches it at every height, and the
/// drop-cutter then lifts it to the face's top; the sides also twist by
/// some 1e-4 mm over the slot's height (docs/method.md §16.3).
const SIDE_CLEARANCE: f64 = 2e-3;

/// The ring's geometry that does not change with u.
pub(crate) struct Rings {
    /// Samples of the whole curve.
    pub(crate) p: usize,
    /// The slot's angles, contacts per side, and its floor's u.
    slot: Option<(f64, f64, usize, f64)>,
    /// The cutter's radius, mm.
    r: f64,
}

impl Rings {
    /// The rings of `tube` with `p` samples, for a cutter of radius `r`
    /// (mm): an error when the tube has trims other than one slot.
    pub(crate) fn new(tube: &PdeTube, p: usize, r: f64) -> Result<Rings, FinishError> {
        let Some(t) = tube.trims().first() else {
            return Ok(Rings { p, slot: None, r });
        };
        let vs = t.iter().map(|q| q[1]);
        let a = vs.clone().fold(f64::INFINITY, f64::min);
        let b = vs.fold(f64::NEG_INFINITY, f64::max);
        let u0 = t.iter().map(|q| q[0]).fold(f64::INFINITY, f64::min);
        if tube.trims().len() > 1 || !(b > a && b - a < 0.5 * TAU) {
            return Err(FinishError::RingTrims);
        }
        let xy = |v: f64| {
            let q = tube.surface().point(u0, v);
            let c = tube.surface().spine().point(u0);
            (q[0] - c[0]).hypot(q[1] - c[1])
        };
        let m = ((xy(a).max(xy(b)) / SIDE_STEP).ceil() as usize).max(4);
        Ok(Rings {
            p,
            slot: Some((a, b, m, u0)),
            r,
        })
    }

    /// Heights (relative to the top) the rings must include: just under a
    /// slot's floor, the last full ring, whose contacts in the slot's
    /// angles reach the wall's edge there.
    pub(crate) fn extra_heights(&self, tube: &PdeTube) -> Vec<f64> {
        match self.slot {
            Some((_, _, _, u0)) => {
                vec![tube.surface().spine().point(u0)[2] - tube.top_z() - 1e-6]
            }
            None => Vec::new(),
        }
    }

    /// Whether the rings go round a slot.
    pub(crate) fn has_slot(&self) -> bool {
        self.slot.is_some()
    }

    /// The contacts of the ring at u with their keys, in cutting order
    /// (`reverse`: clockwise from above); an error where the kept curve is
    /// not one pie piece.
    pub(crate) fn contacts(
        &self,
        tube: &PdeTube,
        u: f64,
        reverse: bool,
    ) -> Result<Vec<(i64, Contact)>, FinishError> {
        let p = self.p;
        let Some((a, b, m, _)) = self.slot else {
            return Ok((0..=p)
                .map(|j| {
                    let k = if reverse { (p - j % p) % p } else { j % p };
                    (j as i64, Contact::Wall(TAU * k as f64 / p as f64))
                })
                .collect());
        };
        let grid = |k: usize| a + TAU * k as f64 / p as f64;
        let mut out: Vec<(i64, Contact)> = match tube.kept_arcs(u) {
            None => (0..=p)
                .map(|k| (k as i64, Contact::Wall(grid(k))))
                .collect(),
            Some(arcs) if arcs.len() == 1 => {
                let mut out = vec![(0, Contact::Wall(a))];
                out.extend(self.sides(tube, u, (a, b, m)));
                out.push((KEY_B, Contact::Wall(b)));
                out.extend(
                    (1..p)
                        .filter(|&k| grid(k) > b)
                        .map(|k| (k as i64, Contact::Wall(grid(k)))),
                );
                out.push((p as i64, Contact::Wall(a + TAU)));
                out
            }
            Some(_) => return Err(FinishError::SectionPieces { u }),
        };
        if reverse {
            out.reverse();
        }
        Ok(out)
    }

    /// Corner a, side a inward, side b outward, corner b (counter-clockwise).
    fn sides(&self, tube: &PdeTube, u: f64, (a, b, m): (f64, f64, usize)) -> Vec<(i64, Contact)> {
        let s = tube.surface();
        let c = s.spine().point(u);
        let (pa, pb) = (s.point(u, a), s.point(u, b));
        let unit = |q: [f64; 3]| {
            let (dx, dy) = (q[0] - c[0], q[1] - c[1]);
            let l = dx.hypot(dy);
            ([dx / l, dy / l], l)
        };
        let ((da, la), (db, lb)) = (unit(pa), unit(pb));
        let theta = (da[0] * db[0] + da[1] * db[1]).clamp(-1.0, 1.0).acos();
        let stop = self.r / (0.5 * theta).tan() + V_MARGIN;
        // Into the slot: side a's normal turns the ray by +90°, b's by −90°.
        let (na, nb) = ([-da[1], da[0], 0.0], [db[1], -db[0], 0.0]);
        let along = |d: [f64; 2], n: [f64; 3], l: f64, t: f64| {
            let x = (l - (l - stop).max(0.0) * t).max(0.0);
            let k = SIDE_CLEARANCE;
            [c[0] + d[0] * x + k * n[0], c[1] + d[1] * x + k * n[1], c[2]]
        };
        let wall = |v: f64, q: [f64; 3]| match super::rings::wall_normal(tube, u, v) {
            Some((_, n)) => n,
            None => {
                let (d, _) = unit(q);
                [d[0], d[1], 0.0]
            }
        };
        let mut out = corner(pa, wall(a, pa), na, CORNER_A);
        out.extend((1..=m).map(|i| {
            let q = along(da, na, la, i as f64 / m as f64);
            (SIDE_A + i as i64, Contact::At(q, na))
        }));
        if u >= 1.0 - 1e-9 {
            out.extend(v_excursion(c, (da, db), stop / (0.5 * theta).cos()));
        }
        out.extend((1..=m).rev().map(|i| {
            let q = along(db, nb, lb, i as f64 / m as f64);
            (SIDE_B + i as i64, Contact::At(q, nb))
        }));
        let mut cb = corner(pb, wall(b, pb), nb, CORNER_B);
        cb.reverse();
        out.extend(cb);
        out
    }
}

/// On the top ring, from the deepest point of the V (the cutter touching
/// both sides, `depth` mm from the spine point `c` along the bisector of the
/// side directions `d`) in to the spine and back, the cutter where the drop
/// puts it: resting on the two sides' top edges it dips into the V's tip,
/// which no ring reaches.
fn v_excursion(c: [f64; 3], d: ([f64; 2], [f64; 2]), depth: f64) -> Vec<(i64, Contact)> {
    let (mx, my) = (d.0[0] + d.1[0], d.0[1] + d.1[1]);
    let l = mx.hypot(my);
    if !(l > 1e-9 && depth.is_finite()) {
        return Vec::new();
    }
    let (bx, by) = (mx / l, my / l);
    let n = (depth / V_STEP).ceil() as usize;
    let at = |i: usize| {
        let t = depth * (1.0 - i as f64 / n as f64);
        Contact::Drop([c[0] + bx * t, c[1] + by * t])
    };
    let inward = (1..=n).map(|i| (V_KEY + i as i64, at(i)));
    let outward = (0..n).rev().map(|i| (V_KEY + (2 * n - i) as i64, at(i)));
    inward.chain(outward).collect()
}

/// Contacts at the corner point `q` (the wall's edge at the slot), the
/// normal turned from the wall's `from` to the side's `to` (unit vectors,
/// spherical interpolation), both ends excluded; the point is moved off by
/// [`SIDE_CLEARANCE`] along each normal.
fn corner(q: [f64; 3], from: [f64; 3], to: [f64; 3], key: i64) -> Vec<(i64, Contact)> {
    let dot = (0..3)
        .map(|i| from[i] * to[i])
        .sum::<f64>()
        .clamp(-1.0, 1.0);
    let angle = dot.acos();
    (1..CORNER)
        .map(|i| {
            let t = i as f64 / CORNER as f64;
            let (wa, wb) = if angle > 1e-9 {
                let s = angle.sin();
                (((1.0 - t) * angle).sin() / s, (t * angle).sin() / s)
            } else {
                (1.0 - t, t)
            };
            let n = [0, 1, 2].map(|k| wa * from[k] + wb * to[k]);
            let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            let n = n.map(|x| x / l);
            let p = [0, 1, 2].map(|k| q[k] + SIDE_CLEARANCE * n[k]);
            (key + i as i64, Contact::At(p, n))
        })
        .collect()
}
