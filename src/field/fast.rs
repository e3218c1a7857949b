//! Field evaluation whose cost does not grow with N: local (Taylor) expansions
//! of the far charges, built lazily per box of a grid, and direct sums for the
//! near ones (issue 13).
//!
//! With F(z) = Σ cₙ log(z − qₙ) (complex), u = −(1/2π) Re F and
//! ∇u = −(1/2π) conj(F′). For a box centred at z_B and a charge q with
//! |q − z_B| ≥ κρ (ρ the box's half-diagonal), every z in the box has
//! w = (z − z_B)/(z_B − q) with |w| ≤ 1/κ, and
//! log(z − q) = log(z_B − q) + Σ_{k≥1} (−1)^{k+1} w^k / k.
//! Summed over the far charges, F_far(z) = Σ_k a_k (z − z_B)^k with
//! a_0 = Σ c log(z_B − q), a_k = Σ c (−1)^{k+1} / (k (z_B − q)^k). Truncated at
//! order p the error in F is at most C κ^{−(p+1)} / (1 − 1/κ) and in F′ at most
//! C κ^{−p} / ((1 − 1/κ) κρ), C = Σ_far |c|; p is chosen per box so both are
//! below [`ABS_TOL`].

use crate::geometry::Vec2;
use std::sync::OnceLock;

/// Boxes per diagonal of the region a field is accelerated over
/// ([`Field::accelerated_around`](super::Field::accelerated_around)).
pub const BOXES_PER_DIAGONAL: f64 = 100.0;

/// Far charges are at least this many box half-diagonals from the box centre.
pub const KAPPA: f64 = 3.0;

/// Bound on the truncation error of F and of F′ (per mm) in each box.
pub const ABS_TOL: f64 = 1e-15;

/// Largest expansion order (a box needing more evaluates directly).
pub const MAX_ORDER: usize = 90;

/// Points whose expansions [`Accel::sums_many`] evaluates side by side.
pub const LANES: usize = 4;

/// The raw sums at `p` in `cell` from the far part's F (`f`) and F′ (`df`)
/// at p: Re F plus the near charges' c log|p − q|, and conj(F′) plus their
/// c (p − q)/|p − q|².
fn near_sums(cell: &Cell, charges: &[Vec2], coef: &[f64], p: Vec2, f: C, df: C) -> (f64, Vec2) {
    let (mut s, mut gx, mut gy) = (f.re, df.re, -df.im);
    for &i in &cell.near {
        let (q, c) = (charges[i as usize], coef[i as usize]);
        let d = p - q;
        let r2 = d.norm2();
        s += 0.5 * c * r2.ln();
        let w = c / r2;
        gx += w * d.x;
        gy += w * d.y;
    }
    (s, Vec2::new(gx, gy))
}

/// The far part's F and F′ at offsets `t` from a box's centre, by Horner's
/// scheme on its coefficients `a`: the L chains interleaved, each lane the
/// same operations in the same order as a chain on its own.
fn horner<const L: usize>(a: &[C], t: [C; L]) -> ([C; L], [C; L]) {
    let n = a.len();
    let (mut f, mut df) = ([a[n - 1]; L], [C::default(); L]);
    for j in (0..n - 1).rev() {
        for l in 0..L {
            df[l] = df[l].mul(t[l]).add(f[l]);
            f[l] = f[l].mul(t[l]).add(a[j]);
        }
    }
    (f, df)
}

/// A minimal complex number (only what the expansions need).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct C {
    re: f64,
    im: f64,
}

impl C {
    fn new(re: f64, im: f64) -> C {
        C { re, im }
    }
    fn mul(self, o: C) -> C {
        C::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
    fn add(self, o: C) -> C {
        C::new(self.re + o.re, self.im + o.im)
    }
    fn scale(self, k: f64) -> C {
        C::new(self.re * k, self.im * k)
    }
    fn inv(self) -> C {
        let d = self.re * self.re + self.im * self.im;
        C::new(self.re / d, -self.im / d)
    }
}

/// One box: the near charges (summed directly) and the far charges' local
/// expansion about the centre (`a[0]` holds only Re a₀ = Σ c log|z_B − q|;
/// its imaginary part, which only Im F would need, is not kept).
#[derive(Debug)]
struct Cell {
    centre: Vec2,
    near: Vec<u32>,
    a: Vec<C>,
}

impl Cell {
    /// z − z_B for the point `p`.
    fn offset(&self, p: Vec2) -> C {
        C::new(p.x - self.centre.x, p.y - self.centre.y)
    }
}

/// One level of the hierarchy: boxes `scale` times the leaves' side.
#[derive(Debug)]
struct Level {
    size: f64,
    nx: usize,
    cells: Vec<OnceLock<Option<Cell>>>,
}

/// The lazily built boxes over a rectangle, in a hierarchy of levels whose
/// boxes double in side up to one box over everything; points outside it are
/// evaluated directly by the caller. A box's expansion is its parent's,
/// re-centred (exact for a polynomial), plus the charges near the parent but
/// far from it: each box touches only the charges near its parent, not all N.
#[derive(Debug)]
pub struct Accel {
    lo: Vec2,
    /// `levels[0]` is the single top box, the last level the leaves.
    levels: Vec<Level>,
}

impl Accel {
    /// Boxes of side `size` (mm) over [lo, hi]; at most 2²⁰ boxes (the side
    /// grows to keep within that).
    pub fn new(lo: Vec2, hi: Vec2, size: f64) -> Accel {
        let ext = hi - lo;
        let mut size = size.max(1e-6);
        while (ext.x / size).ceil() * (ext.y / size).ceil() > (1u64 << 20) as f64 {
            size *= 2.0;
        }
        let nx = ((ext.x / size).ceil() as usize).max(1);
        let ny = ((ext.y / size).ceil() as usize).max(1);
        // Levels up from the leaves, halving the counts, until one box.
        let mut levels = Vec::new();
        let (mut s, mut cx, mut cy) = (size, nx, ny);
        loop {
            levels.push(Level {
                size: s,
                nx: cx,
                cells: (0..cx * cy).map(|_| OnceLock::new()).collect(),
            });
            if cx == 1 && cy == 1 {
                break;
            }
            s *= 2.0;
            cx = cx.div_ceil(2);
            cy = cy.div_ceil(2);
        }
        levels.reverse();
        Accel { lo, levels }
    }

    fn leaf_of(&self, p: Vec2) -> Option<(usize, usize)> {
        let leaves = self.levels.last()?;
        let ny = leaves.cells.len() / leaves.nx;
        let fx = (p.x - self.lo.x) / leaves.size;
        let fy = (p.y - self.lo.y) / leaves.size;
        if !(fx >= 0.0 && fy >= 0.0 && fx < leaves.nx as f64 && fy < ny as f64) {
            return None;
        }
        Some((fx as usize, fy as usize))
    }

    /// Σ c log|P − q| and Σ c (P − q)/|P − q|² (the raw sums of `Field`), or
    /// None outside the boxes or where a box could not be expanded.
    pub fn sums(&self, charges: &[Vec2], coef: &[f64], p: Vec2) -> Option<(f64, Vec2)> {
        let (i, j) = self.leaf_of(p)?;
        let cell = self.cell(self.levels.len() - 1, i, j, charges, coef)?;
        crate::count::eval(cell.near.len(), cell.a.len());
        let ([f], [df]) = horner(&cell.a, [cell.offset(p)]);
        Some(near_sums(cell, charges, coef, p, f, df))
    }

    /// [`Accel::sums`] at each of `ps`, into `out` (one per point; a longer
    /// `out` keeps the rest, a shorter one takes the first points). Each
    /// point gets the same operations in the same order, so the same bits;
    /// where [`LANES`] consecutive points fall in one box their Horner chains
    /// run interleaved, which a single point's chain, each step waiting on
    /// the one before, cannot.
    pub fn sums_many(
        &self,
        charges: &[Vec2],
        coef: &[f64],
        ps: &[Vec2],
        out: &mut [Option<(f64, Vec2)>],
    ) {
        let n = ps.len().min(out.len());
        for (ps, out) in ps[..n].chunks(LANES).zip(out[..n].chunks_mut(LANES)) {
            let leaf = self.leaf_of(ps[0]);
            let same = ps.len() == LANES && ps.iter().all(|&p| self.leaf_of(p) == leaf);
            let cell = match leaf {
                Some((i, j)) if same => self.cell(self.levels.len() - 1, i, j, charges, coef),
                _ => None,
            };
            let Some(cell) = cell else {
                for (o, &p) in out.iter_mut().zip(ps) {
                    *o = self.sums(charges, coef, p);
                }
                continue;
            };
            let t: [C; LANES] = std::array::from_fn(|l| cell.offset(ps[l]));
            let (f, df) = horner(&cell.a, t);
            for l in 0..LANES {
                crate::count::eval(cell.near.len(), cell.a.len());
                out[l] = Some(near_sums(cell, charges, coef, ps[l], f[l], df[l]));
            }
        }
    }

    /// Box (i, j) of level `l`, built (with its ancestors) on first use.
    fn cell(&self, l: usize, i: usize, j: usize, charges: &[Vec2], coef: &[f64]) -> Option<&Cell> {
        let level = &self.levels[l];
        level.cells[j * level.nx + i]
            .get_or_init(|| self.build(l, i, j, charges, coef))
            .as_ref()
    }

    fn build(&self, l: usize, i: usize, j: usize, charges: &[Vec2], coef: &[f64]) -> Option<Cell> {
        let size = self.levels[l].size;
        let centre = self.lo + Vec2::new((i as f64 + 0.5) * size, (j as f64 + 0.5) * size);
        let reach = KAPPA * size * std::f64::consts::FRAC_1_SQRT_2;
        // Candidates: every charge at the top; below, the parent's near ones
        // (a charge near a box is near its parent: the centres are ρ apart and
        // κρ + ρ ≤ 2κρ for κ ≥ 1).
        let parent = if l == 0 {
            None
        } else {
            Some(self.cell(l - 1, i / 2, j / 2, charges, coef)?)
        };
        let all: Vec<u32>;
        let candidates: &[u32] = match parent {
            Some(p) => &p.near,
            None => {
                all = (0..charges.len() as u32).collect();
                &all
            }
        };
        let (near, far): (Vec<u32>, Vec<u32>) = candidates
            .iter()
            .partition(|&&n| charges[n as usize].dist(centre) < reach);
        let new_far_abs: f64 = far.iter().map(|&n| coef[n as usize].abs()).sum();
        let inherited = parent.map_or(0, |p| p.a.len() - 1);
        let order = order_for(new_far_abs, reach)?.max(inherited);
        let mut a = vec![C::default(); order + 1];
        if let Some(p) = parent {
            a[..p.a.len()].copy_from_slice(&p.a);
            let d = C::new(centre.x - p.centre.x, centre.y - p.centre.y);
            taylor_shift(&mut a, d);
            a[0].im = 0.0;
        }
        for &n in &far {
            let (q, c) = (charges[n as usize], coef[n as usize]);
            let d = C::new(centre.x - q.x, centre.y - q.y);
            a[0].re += 0.5 * c * d.re.mul_add(d.re, d.im * d.im).ln();
            let inv = d.inv();
            let mut pw = inv;
            for (k, ak) in a.iter_mut().enumerate().skip(1) {
                let sign = if k % 2 == 1 { 1.0 } else { -1.0 };
                *ak = ak.add(pw.scale(sign * c / k as f64));
                pw = pw.mul(inv);
            }
        }
        Some(Cell { centre, near, a })
    }
}

/// Re-centre the polynomial Σ a_k t^k at t = d, in place: afterwards
/// Σ a_k s^k equals the old polynomial at t = s + d (repeated synthetic
/// division, p²/2 complex multiply-adds).
fn taylor_shift(a: &mut [C], d: C) {
    let n = a.len();
    for i in 0..n {
        for k in (i..n - 1).rev() {
            a[k] = a[k].add(d.mul(a[k + 1]));
        }
    }
}

/// The smallest order p whose truncation bounds (module docs) are below
/// [`ABS_TOL`] for far charges of total |c| `far_abs` at least `reach` away;
/// None past [`MAX_ORDER`].
fn order_for(far_abs: f64, reach: f64) -> Option<usize> {
    if far_abs == 0.0 {
        return Some(0);
    }
    let lead = far_abs / (1.0 - 1.0 / KAPPA) * (1.0f64).max(1.0 / reach);
    (0..=MAX_ORDER).find(|&p| lead * KAPPA.powi(-(p as i32)) <= ABS_TOL)
}
