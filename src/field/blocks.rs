//! A word's field letter by letter (issue 46): each letter (an outline with
//! its counters and their sinks) is a block with its own charges, collocation
//! and check points, refined on its own (`field::refine` on the letter
//! alone, without the outer circle) until its own boundary error meets the
//! target; the outer circle is one more block. The word's field is
//! the sum of the blocks' fields, coupled by block Gauss–Seidel over the
//! blocks with a coarse step (FIELD-NOTES.md: without it the sweeps diverge,
//! because a block's net charge moves every other block's boundary by about
//! q log(distance)): after each sweep, one amplitude per block times its
//! "unit" solution (its own fit to u = 1 on its contours) is fitted to the
//! residual over every collocation point of the word.
//!
//! A block acts on another's points through an explicit matrix where they
//! are near (its charges within half the distance to the points), else
//! through its multipole expansion about its centre, so the cost and memory
//! grow with the letters and their neighbours, not with N² of the word. The
//! max boundary error is measured on the whole word's check points (letters,
//! sinks and the outer circle) with the summed field.

use super::mfs::{Factor, Field, Problem, Solution};
use super::{adaptive, FieldError, Prepared};
use crate::geometry::Vec2;
use faer::Mat;
use rayon::prelude::*;

/// Most Gauss–Seidel sweeps of the coupling.
pub const MAX_SWEEPS: usize = 60;

/// A block is far from a set of points when its charges lie within this
/// fraction of the distance from its centre to every point.
pub const FAR_RATIO: f64 = 0.5;

/// Terms of a block's multipole expansion: FAR_RATIO^ORDER ≈ 9e-19.
pub const ORDER: usize = 60;

/// Most couplings of a word: the first, and rounds that grow the letters
/// still over the target in the word.
pub const REGROW_ROUNDS: usize = 3;

/// A letter regrown in the word aims, alone, at this fraction of what it
/// would need for its error in the word to meet the target.
pub const REGROW_MARGIN: f64 = 0.8;

/// Charges on the outer circle of a word (the paired layout's most).
pub const RING_CHARGES: usize = super::setup::PAIRED_OUTER_CHARGES.1;

/// One letter's layout, chosen alone.
#[derive(Clone, Debug)]
pub struct LetterSolve {
    /// Singularities of the letter's block (without the outer circle's).
    pub n: usize,
    /// The max boundary error of the letter solved alone.
    pub alone: f64,
    /// The max boundary error on the letter's check points in the word's field.
    pub in_word: f64,
    /// The letter's pseudo-boundary distance.
    pub distance: f64,
}

/// The word's field and how it was reached.
#[derive(Clone, Debug)]
pub struct BlockSolved {
    /// The summed field and its max boundary error over the whole word.
    pub solution: Solution,
    /// Per letter, in the order given.
    pub letters: Vec<LetterSolve>,
    /// Singularities in all (letters, sinks and the outer circle).
    pub n: usize,
    /// Collocation points in all.
    pub m: usize,
    /// Sweeps of the coupling.
    pub sweeps: usize,
    /// Max residual at the collocation points after the coupling.
    pub residual: f64,
    /// Couplings solved: 1, plus one per round that grew a letter over the
    /// target in the word.
    pub rounds: usize,
}

/// One block: its points, its factor, its current coefficients.
struct Block {
    problem: Problem,
    factor: Factor,
    /// The block's fit to u = 1 on its own u = 1 points (0 elsewhere).
    unit: Vec<f64>,
    coef: Vec<f64>,
    centre: Vec2,
    rho: f64,
    /// Whether the block is the letter's refined layout ([`letter_refined`]).
    refined: bool,
}

/// Solve each letter alone to `target` (its own charges, collocation and
/// check points, without the outer circle), then the word by coupling the
/// letters' blocks and the word's outer circle (`centre`, `radius` of the
/// letters' boundaries). `letters` are the letters' own preparations
/// (`Prepared::new` of a boundary holding one outline and its counters).
pub fn solve_word(
    letters: &[Prepared],
    target: &adaptive::Target,
) -> Result<BlockSolved, FieldError> {
    let first = letters.first().ok_or(FieldError::NoContours)?;
    let (centre, radius) = (first.boundary.centre, first.boundary.radius);
    let alone: Vec<(Block, f64, f64)> = letters
        .par_iter()
        .map(|prep| letter_block(prep, target, 0, target.max_error))
        .collect::<Result<_, _>>()?;
    let mut lone: Vec<(f64, f64)> = alone.iter().map(|(_, e, d)| (*e, *d)).collect();
    let mut blocks: Vec<Block> = alone.into_iter().map(|(b, _, _)| b).collect();
    let checks = super::setup::CHECKS_PER_INTERVAL.1;
    blocks.push(Block::new(super::setup::circle(
        centre,
        radius,
        radius * super::setup::OUTER_CHARGE_FACTOR,
        RING_CHARGES,
        checks,
    ))?);
    let mut rounds = 0;
    loop {
        let solved = couple(&mut blocks, target.max_error, &lone)?;
        rounds += 1;
        // A letter over the target in the word (the others' field is data
        // it fits too) is grown past its N, and the word coupled again.
        let grow: Vec<usize> = solved
            .letters
            .iter()
            .enumerate()
            .filter(|(_, l)| l.in_word > target.max_error && l.n < target.n_max)
            .map(|(i, _)| i)
            .collect();
        if grow.is_empty() || rounds >= REGROW_ROUNDS {
            return Ok(BlockSolved { rounds, ..solved });
        }
        let grown: Vec<(usize, Block, f64, f64)> = grow
            .par_iter()
            .map(|&i| {
                // Alone, the letter is asked for as much less as the word
                // added to its error.
                let l = &solved.letters[i];
                let aim = (REGROW_MARGIN * target.max_error * l.alone / l.in_word)
                    .min(REGROW_MARGIN * l.alone);
                let from = blocks[i].problem.charges.len() + 1;
                // A letter whose sequence of N already missed is refined
                // again at once, not sent through the sequence a second time.
                let grown = if blocks[i].refined && target.distance.is_none() {
                    letter_refined(&letters[i], target, aim)
                } else {
                    letter_block(&letters[i], target, from, aim)
                };
                grown.map(|(b, e, d)| (i, b, e, d))
            })
            .collect::<Result<_, _>>()?;
        for (i, b, e, d) in grown {
            blocks[i] = b;
            lone[i] = (e, d);
        }
        for b in &mut blocks {
            b.coef.iter_mut().for_each(|c| *c = 0.0);
        }
    }
}

/// A letter's block: the paired layout's sequence of Ns
/// ([`letter_sequence`], from `from` on, to `target`), and when that misses
/// the target, the letter refined where it errs ([`letter_refined`], to
/// `aim`) if that does better. Returns the block, its error alone and its
/// pseudo-boundary distance.
fn letter_block(
    prep: &Prepared,
    target: &adaptive::Target,
    from: usize,
    aim: f64,
) -> Result<(Block, f64, f64), FieldError> {
    let seq = letter_sequence(prep, target, from);
    if matches!(&seq, Ok((_, e, _)) if *e <= target.max_error) || target.distance.is_some() {
        return seq;
    }
    match (seq, letter_refined(prep, target, aim)) {
        (Ok(s), Ok(r)) => Ok(if r.1 < s.1 { r } else { s }),
        (Ok(s), Err(_)) => Ok(s),
        (Err(_), r) => r,
    }
}

/// The letter alone (no outer circle) refined ([`super::refine::refine`],
/// from `target.n_start` uniform charges, at most `target.n_max`) until its
/// max error on its own check points is at most `aim`; the block of the
/// first layout that is, else of the best, its error and its mean
/// pseudo-boundary distance.
fn letter_refined(
    prep: &Prepared,
    target: &adaptive::Target,
    aim: f64,
) -> Result<(Block, f64, f64), FieldError> {
    let mut prep = prep.clone();
    prep.outer = false;
    let r = super::refine::refine(&prep, target.n_start, aim, target.n_max, |pr| {
        let block = Block::new(pr.clone())?;
        let field = Field::new(block.problem.charges.clone(), block.unit.clone());
        let errors = super::mfs::check_errors(&field, &block.problem.checks);
        Ok((block, errors))
    })?;
    let distance = r.refinement.layout(&prep).distance;
    let mut block = r.out;
    block.refined = true;
    Ok((block, r.max_error, distance))
}

/// A letter's block: N grown as [`adaptive::solve_sequence`] grows it (the
/// paired layout at d = 2h unless the target fixes d), the letter alone (no
/// outer circle), until its max error on its own check points meets the
/// target; the block of the first N (from `from` on) that does, else of the
/// best. Returns the block, that error and the pseudo-boundary distance.
fn letter_sequence(
    prep: &Prepared,
    target: &adaptive::Target,
    from: usize,
) -> Result<(Block, f64, f64), FieldError> {
    let mut prep = prep.clone();
    prep.outer = false;
    let mut best: Option<(Block, f64, f64)> = None;
    let mut last_err = None;
    let ns = adaptive::sequence(target);
    let first = ns.iter().position(|&n| n >= from).unwrap_or(ns.len() - 1);
    for &n in &ns[first..] {
        let layout = adaptive::layout(&prep, n, target.distance);
        let block = prep.problem(&layout).and_then(Block::new);
        let block = match block {
            Ok(b) => b,
            Err(e) => {
                last_err = Some(e);
                continue;
            }
        };
        let field = Field::new(block.problem.charges.clone(), block.unit.clone());
        let err = super::mfs::max_error(&field, &block.problem.checks);
        if !err.is_finite() {
            last_err = Some(FieldError::NotANumberAtCheck);
            continue;
        }
        let done = err <= target.max_error;
        if best.as_ref().is_none_or(|b| err < b.1) {
            best = Some((block, err, layout.distance));
        }
        if done {
            break;
        }
    }
    best.ok_or(last_err.unwrap_or(FieldError::NoLayoutSolved))
}

impl Block {
    /// Factor the block's own system and fit it to its own data.
    fn new(problem: Problem) -> Result<Block, FieldError> {
        let points: Vec<Vec2> = problem.colloc.iter().map(|c| c.p).collect();
        let values: Vec<f64> = problem.colloc.iter().map(|c| c.value).collect();
        let (factor, unit) = if values.iter().any(|&v| v != 0.0) {
            Factor::new(&problem.charges, &points, &values)?
        } else {
            Factor::new(&problem.charges, &points, &vec![1.0; points.len()])?
        };
        let (lo, hi) = bbox(&problem.charges);
        let centre = (lo + hi) * 0.5;
        let rho = problem
            .charges
            .iter()
            .map(|q| q.dist(centre))
            .fold(0.0, f64::max);
        Ok(Block {
            coef: vec![0.0; problem.charges.len()],
            problem,
            factor,
            unit,
            centre,
            rho,
            refined: false,
        })
    }
}

/// The least box holding the points.
fn bbox(ps: &[Vec2]) -> (Vec2, Vec2) {
    ps.iter().fold(
        (
            Vec2::new(f64::INFINITY, f64::INFINITY),
            Vec2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
        ),
        |(lo, hi), p| {
            (
                Vec2::new(lo.x.min(p.x), lo.y.min(p.y)),
                Vec2::new(hi.x.max(p.x), hi.y.max(p.y)),
            )
        },
    )
}

/// How block k acts on the points of block j.
enum Coupling {
    /// k(P_j, Q_k) explicitly, M_j × N_k.
    Near(Mat<f64>),
    /// Through k's multipole expansion.
    Far,
}

/// A block's charge-weighted multipole about its centre, in units of its
/// radius: Σ c log(z − q) = Q log(z − z_c) + Σ_m b_m (ρ/(z − z_c))^m.
struct Multipole {
    centre: Vec2,
    rho: f64,
    q: f64,
    b: Vec<(f64, f64)>,
}

impl Multipole {
    fn new(block: &Block, coef: &[f64]) -> Multipole {
        let mut b = vec![(0.0, 0.0); ORDER];
        let mut q = 0.0;
        for (&p, &c) in block.problem.charges.iter().zip(coef) {
            q += c;
            let w = (p - block.centre) * (1.0 / block.rho);
            let (mut re, mut im) = (1.0, 0.0);
            for (m, bm) in b.iter_mut().enumerate() {
                (re, im) = (re * w.x - im * w.y, re * w.y + im * w.x);
                let k = c / (m + 1) as f64;
                bm.0 -= k * re;
                bm.1 -= k * im;
            }
        }
        Multipole {
            centre: block.centre,
            rho: block.rho,
            q,
            b,
        }
    }

    /// Re Σ c log(z − q) at p.
    fn value(&self, p: Vec2) -> f64 {
        let d = p - self.centre;
        let r2 = d.norm2();
        // t = ρ / (z − z_c) = ρ conj(d) / |d|².
        let (tr, ti) = (self.rho * d.x / r2, -self.rho * d.y / r2);
        let (mut re, mut im) = (0.0, 0.0);
        for &(br, bi) in self.b.iter().rev() {
            (re, im) = (re + br, im + bi);
            (re, im) = (re * tr - im * ti, re * ti + im * tr);
        }
        self.q * 0.5 * r2.ln() + re
    }
}

/// The couplings of every block to every block's points.
fn couplings(blocks: &[Block]) -> Vec<Vec<Coupling>> {
    blocks
        .par_iter()
        .map(|bj| {
            blocks
                .iter()
                .map(|bk| {
                    let far = bj
                        .problem
                        .colloc
                        .iter()
                        .all(|c| bk.rho <= FAR_RATIO * c.p.dist(bk.centre));
                    if far {
                        return Coupling::Far;
                    }
                    let (m, n) = (bj.problem.colloc.len(), bk.problem.charges.len());
                    Coupling::Near(Mat::from_fn(m, n, |i, l| {
                        super::mfs::kernel(bj.problem.colloc[i].p, bk.problem.charges[l])
                    }))
                })
                .collect()
        })
        .collect()
}

/// u at block j's points from block k's coefficients `coef`, added to `u`.
fn add_field(j: &Block, coupling: &Coupling, far: Option<&Multipole>, coef: &[f64], u: &mut [f64]) {
    match coupling {
        Coupling::Near(a) => {
            for (l, &c) in coef.iter().enumerate() {
                if c == 0.0 {
                    continue;
                }
                let col = a.col(l);
                for (i, ui) in u.iter_mut().enumerate() {
                    *ui += col[i] * c;
                }
            }
        }
        Coupling::Far => {
            if let Some(mp) = far {
                let k = -0.5 / std::f64::consts::PI;
                for (ui, c) in u.iter_mut().zip(&j.problem.colloc) {
                    *ui += k * mp.value(c.p);
                }
            }
        }
    }
}

/// Every block's field change `delta` (coefficients of block k) added to the
/// field values `u` at every block's points.
fn spread(blocks: &[Block], cpl: &[Vec<Coupling>], k: usize, delta: &[f64], u: &mut [Vec<f64>]) {
    let mp = Multipole::new(&blocks[k], delta);
    u.par_iter_mut().enumerate().for_each(|(j, uj)| {
        add_field(&blocks[j], &cpl[j][k], Some(&mp), delta, uj);
    });
}

/// Block Gauss–Seidel with the coarse step, to a residual at the collocation
/// points well under the target; then the word's field and its max error.
fn couple(
    blocks: &mut [Block],
    target: f64,
    lone: &[(f64, f64)],
) -> Result<BlockSolved, FieldError> {
    let cpl = couplings(blocks);
    let nb = blocks.len();
    let mut u: Vec<Vec<f64>> = blocks
        .iter()
        .map(|b| vec![0.0; b.problem.colloc.len()])
        .collect();
    // The coarse columns: each block's unit solution's field at every point.
    let mut v: Vec<Vec<Vec<f64>>> = vec![Vec::new(); nb];
    for (k, vk) in v.iter_mut().enumerate() {
        let mut w = u.iter().map(|x| vec![0.0; x.len()]).collect::<Vec<_>>();
        spread(blocks, &cpl, k, &blocks[k].unit.clone(), &mut w);
        *vk = w;
    }
    let coarse = coarse_factor(&v);
    let (mut best, mut since, mut sweeps) = (f64::INFINITY, 0, 0);
    let mut residual = f64::INFINITY;
    while sweeps < MAX_SWEEPS {
        sweeps += 1;
        for k in 0..nb {
            let own = &u[k];
            let b = &blocks[k];
            let mut others = own.clone();
            if let Coupling::Near(_) = &cpl[k][k] {
                let mut mine = vec![0.0; own.len()];
                add_field(b, &cpl[k][k], None, &b.coef, &mut mine);
                for (o, m) in others.iter_mut().zip(&mine) {
                    *o -= m;
                }
            }
            let rhs: Vec<f64> = b
                .problem
                .colloc
                .iter()
                .zip(&others)
                .map(|(c, o)| c.value - o)
                .collect();
            let new = b.factor.solve(&rhs);
            let delta: Vec<f64> = new.iter().zip(&b.coef).map(|(n, o)| n - o).collect();
            blocks[k].coef = new;
            spread(blocks, &cpl, k, &delta, &mut u);
        }
        // The coarse step over every point.
        let r: Vec<f64> = residuals(blocks, &u).concat();
        let alpha = coarse.solve_lstsq_vec(&r);
        for (k, &a) in alpha.iter().enumerate() {
            let unit = blocks[k].unit.clone();
            for (c, w) in blocks[k].coef.iter_mut().zip(&unit) {
                *c += a * w;
            }
            for (uj, vj) in u.iter_mut().zip(&v[k]) {
                for (x, y) in uj.iter_mut().zip(vj) {
                    *x += a * y;
                }
            }
        }
        residual = residuals(blocks, &u)
            .iter()
            .flatten()
            .fold(0.0, |m: f64, x| m.max(x.abs()));
        if residual < 0.9 * best {
            best = residual;
            since = 0;
        } else {
            since += 1;
        }
        if residual <= 0.01 * target || since >= 4 || !residual.is_finite() {
            break;
        }
    }
    finish(blocks, sweeps, residual, lone)
}

/// g − u at every block's collocation points.
fn residuals(blocks: &[Block], u: &[Vec<f64>]) -> Vec<Vec<f64>> {
    blocks
        .iter()
        .zip(u)
        .map(|(b, uj)| {
            b.problem
                .colloc
                .iter()
                .zip(uj)
                .map(|(c, x)| c.value - x)
                .collect()
        })
        .collect()
}

/// The coarse system: one column per block, its unit solution's field at
/// every collocation point of the word.
struct Coarse {
    qr: faer::linalg::solvers::Qr<f64>,
    n: usize,
}

impl Coarse {
    fn solve_lstsq_vec(&self, r: &[f64]) -> Vec<f64> {
        use faer::linalg::solvers::SolveLstsq;
        let rhs = Mat::<f64>::from_fn(r.len(), 1, |i, _| r[i]);
        let x = self.qr.solve_lstsq(&rhs);
        (0..self.n).map(|k| x[(k, 0)]).collect()
    }
}

fn coarse_factor(v: &[Vec<Vec<f64>>]) -> Coarse {
    let cols: Vec<Vec<f64>> = v.iter().map(|vk| vk.concat()).collect();
    let m = cols.first().map_or(0, Vec::len);
    let a = Mat::<f64>::from_fn(m, cols.len(), |i, k| cols[k][i]);
    faer::set_global_parallelism(faer::Par::Seq);
    Coarse {
        qr: a.qr(),
        n: cols.len(),
    }
}

/// The word's field from the blocks' coefficients, its max error on every
/// check point, and each letter's own.
fn finish(
    blocks: &[Block],
    sweeps: usize,
    residual: f64,
    lone: &[(f64, f64)],
) -> Result<BlockSolved, FieldError> {
    let mut charges = Vec::new();
    let mut coef = Vec::new();
    let (mut m, mut moved, mut condition, mut wc) = (0, 0, 0.0_f64, true);
    for b in blocks {
        charges.extend_from_slice(&b.problem.charges);
        coef.extend_from_slice(&b.coef);
        m += b.problem.colloc.len();
        moved += b.problem.moved;
        condition = condition.max(b.factor.condition);
        wc &= b.factor.well_conditioned;
    }
    if coef.iter().any(|c| !c.is_finite()) {
        return Err(FieldError::NonFiniteCoefficients);
    }
    let n = charges.len();
    let field = Field::new(charges, coef);
    // Each block's own max error (the letters', then the outer circle's);
    // the word's is the largest.
    let at_checks: Vec<Vec<f64>> = blocks
        .iter()
        .map(|b| super::mfs::check_errors(&field, &b.problem.checks))
        .collect();
    let errors: Vec<f64> = at_checks.iter().map(|e| super::mfs::largest(e)).collect();
    let max_error = super::mfs::largest(&errors);
    if !max_error.is_finite() {
        return Err(FieldError::NotANumberAtCheck);
    }
    let checks = blocks
        .iter()
        .flat_map(|b| b.problem.checks.iter().copied())
        .collect();
    let letters = blocks
        .iter()
        .zip(&errors)
        .zip(lone)
        .map(|((b, &in_word), &(alone, distance))| LetterSolve {
            n: b.problem.charges.len(),
            alone,
            in_word,
            distance,
        })
        .collect();
    Ok(BlockSolved {
        solution: Solution {
            field,
            max_error,
            condition,
            well_conditioned: wc,
            moved,
            checks,
            errors: at_checks.concat(),
        },
        letters,
        n,
        m,
        sweeps,
        residual,
        rounds: 1,
    })
}
