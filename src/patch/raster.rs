//! Finishing a height field by drop-cutter parallel passes (a raster): the
//! `[finish]` tool runs along x, passes stepped over in y, zig-zag, its tip
//! at every sample the drop-cutter's height against the part's mesh
//! (`toolpath::dropcutter`: the lowest tip height at which the cutter
//! touches the mesh without entering it), so the path is the exact offset
//! of the mesh for the tool's shape, by construction.
//!
//! - Passes cover the rectangle grown by the tool radius r on every side
//!   (the cutter's contact reaches the border of the top surface), from
//!   y0 − r to y1 + r, Δy apart: the pass width w for `finish.scallop`
//!   (`finish::passes::pass_width`) is measured on the surface, and two
//!   passes Δy apart on a slope of angle θ across them are Δy / cos θ
//!   apart on it, so Δy = w / √(1 + max |∂h/∂y|²).
//! - Along a pass the samples are δ = √(4 rc tol) apart (rc the corner
//!   radius): the chord between two samples on an offset surface of
//!   curvature radius at least rc strays by at most δ²/(8 rc) = tol / 2 below
//!   it. A flat end mill (rc = 0) would need δ → 0 at the block's edges, and
//!   is refused.
//! - Links: the end of one pass joins the start of the next along the
//!   border, at depth, its samples dropped as the passes' are (so the link
//!   never goes below the drop height at a sample).

use crate::finish::{cutter_of, passes::pass_width, FinishError, Finished};
use crate::geometry::Vec2;
use crate::job::{CutterShape, Finish, Job};
use crate::toolpath::dropcutter::MeshIndex;
use crate::toolpath::{Move, Section, Toolpath, Vec3};

/// Most passes of a raster.
pub(crate) const MAX_PASSES: usize = 20_000;

/// Most samples of all passes together (each is a G-code line).
pub(crate) const MAX_SAMPLES: usize = 4_000_000;

/// What the raster needs of the part.
pub(crate) struct RasterPart<'a> {
    /// The rectangle's lower-left corner and size, mm.
    pub(crate) rect: (Vec2, Vec2),
    /// The largest |∂h/∂y| over the rectangle.
    pub(crate) max_slope_y: f64,
    /// The part's mesh (top surface and floor), for the drop-cutter.
    pub(crate) mesh: &'a MeshIndex,
    /// z of the floor, mm: where the mesh has nothing under the cutter.
    pub(crate) z_floor: f64,
    /// Area of the top surface, mm² (for the time's lower bound).
    pub(crate) area: f64,
    /// Whether the part has concave kinks (a relief meeting its flat base):
    /// a chord across the offset's kink there stands above the drop and
    /// leaves material, so steps are also halved while the drop at the
    /// midpoint lies more than tol below the chord.
    pub(crate) valleys: bool,
}

/// The raster's spacing: (Δy across the passes, δ along them), mm.
pub(crate) fn spacing(f: &Finish, max_slope_y: f64, tol: f64) -> Result<(f64, f64), FinishError> {
    if f.shape == CutterShape::Flat || f.corner <= 0.0 {
        return Err(FinishError::FlatOnSurface);
    }
    let w = pass_width(f.corner, f.scallop);
    let dy = w / (1.0 + max_slope_y * max_slope_y).sqrt();
    Ok((dy, (4.0 * f.corner * tol).sqrt()))
}

/// Evenly spaced values from `a` to `b`, at most `step` apart (both ends).
fn stations(a: f64, b: f64, step: f64) -> Vec<f64> {
    let n = (((b - a) / step).ceil() as usize).max(1);
    (0..=n).map(|k| a + (b - a) * k as f64 / n as f64).collect()
}

/// Passes per scallop spacing on a part with concave kinks
/// ([`RasterPart::valleys`]). Beside a kink the cutter's centre path bends
/// up, and the reachable surface there (the ball touching both facets) lies
/// below the chord between two passes' centres by about (d/2) sin(θ/2) (d
/// the passes' distance, θ the bend): 0.039 mm over the ball's reach at the
/// full spacing on jobs/polyharmonic-face.toml, 0.021 at half.
pub(crate) const VALLEY_PASSES: f64 = 3.0;

/// Halvings of a step at most where its chord strays below the drop.
const REFINE_DEPTH: usize = 8;

/// Bisections of a pass's end, where the cutter stops touching the part.
const END_BISECTIONS: usize = 40;

/// A pass's ends are pulled this far (mm) inside the last touching point,
/// so that a drop there is never the floor by rounding.
const END_BACKOFF: f64 = 1e-4;

/// How far beside the rectangle (beyond the cutter's radius) the cutter
/// comes down after a lift, mm.
const APPROACH: f64 = 0.5;

/// The drop-cutter against the part: the tip height at (x, y), `None` where
/// the cutter touches only the floor (off the part).
struct Dropper<'a> {
    cutter: crate::toolpath::dropcutter::Cutter,
    part: &'a RasterPart<'a>,
}

impl Dropper<'_> {
    fn on_part(&self, x: f64, y: f64) -> Option<f64> {
        self.cutter
            .drop(self.part.mesh, x, y)
            .filter(|&z| z > self.part.z_floor + 1e-6)
    }

    /// The point between `off` (off the part) and `on` (on it) where the
    /// cutter leaves the part, a hair on the part's side.
    fn edge(&self, off: f64, on: f64, y: f64) -> Option<Vec3> {
        let (mut a, mut b) = (off, on);
        for _ in 0..END_BISECTIONS {
            let m = 0.5 * (a + b);
            if self.on_part(m, y).is_some() {
                b = m;
            } else {
                a = m;
            }
        }
        // Back off toward `on`, but not past it.
        let x = b + (on - off).signum() * END_BACKOFF;
        let x = if (x - off).abs() < (on - off).abs() {
            x
        } else {
            on
        };
        self.on_part(x, y).map(|z| Vec3::new(x, y, z))
    }

    /// Points between `a` and `b` (exclusive) so that no chord's midpoint
    /// lies more than `tol` below the drop there (nor, with
    /// [`RasterPart::valleys`], more than `tol` above it).
    fn refine(&self, a: Vec3, b: Vec3, tol: f64, depth: usize, out: &mut Vec<Vec3>) {
        if depth == 0 {
            return;
        }
        let (mx, my) = (0.5 * (a.x + b.x), 0.5 * (a.y + b.y));
        let Some(z) = self.on_part(mx, my) else {
            return;
        };
        let chord = 0.5 * (a.z + b.z);
        if z > chord + tol || (self.part.valleys && z < chord - tol) {
            let m = Vec3::new(mx, my, z);
            self.refine(a, m, tol, depth - 1, out);
            out.push(m);
            self.refine(m, b, tol, depth - 1, out);
        }
    }

    /// One pass along `xs` at `y`: the samples on the part, its ends moved
    /// to where the cutter leaves the part, every step refined.
    fn pass(&self, xs: &[f64], y: f64, tol: f64) -> Vec<Vec3> {
        let zs: Vec<Option<f64>> = xs.iter().map(|&x| self.on_part(x, y)).collect();
        let (Some(i0), Some(i1)) = (
            zs.iter().position(Option::is_some),
            zs.iter().rposition(Option::is_some),
        ) else {
            return Vec::new();
        };
        let mut pts: Vec<Vec3> = Vec::with_capacity(i1 - i0 + 3);
        if i0 > 0 {
            pts.extend(self.edge(xs[i0 - 1], xs[i0], y));
        }
        pts.extend((i0..=i1).filter_map(|i| zs[i].map(|z| Vec3::new(xs[i], y, z))));
        if i1 + 1 < xs.len() {
            pts.extend(self.edge(xs[i1 + 1], xs[i1], y));
        }
        let mut out = Vec::with_capacity(pts.len() * 2);
        for w in pts.windows(2) {
            out.push(w[0]);
            self.refine(w[0], w[1], tol, REFINE_DEPTH, &mut out);
        }
        out.extend(pts.last().copied());
        out
    }

    /// Where to come down for a pass: level with its start, beside the
    /// rectangle (the cutter's radius and [`APPROACH`] off its side), so that
    /// the move in along the pass is horizontal; the start itself when that
    /// move would pass below the drop.
    fn approach(&self, pass: &[Vec3], r: f64, tol: f64) -> Vec3 {
        let (b, c) = (pass[0], pass[1]);
        let (lo, size) = self.part.rect;
        let x = if c.x > b.x {
            (b.x - APPROACH).min(lo.x - r - APPROACH)
        } else {
            (b.x + APPROACH).max(lo.x + size.x + r + APPROACH)
        };
        let p0 = Vec3::new(x, b.y, b.z);
        let n = (((b.x - x).abs() / 0.1).ceil() as usize).max(1);
        let clear = (0..n).all(|k| {
            let xx = x + (b.x - x) * k as f64 / n as f64;
            self.cutter
                .drop(self.part.mesh, xx, b.y)
                .is_none_or(|d| d <= b.z + tol)
        });
        if clear {
            p0
        } else {
            b
        }
    }

    /// Whether the straight move `a`–`b` stays above the drop less `tol` at
    /// samples `step` apart (and on the part).
    fn link_clear(&self, a: Vec3, b: Vec3, step: f64, tol: f64) -> bool {
        let n = (((b.x - a.x).hypot(b.y - a.y) / step).ceil() as usize).max(1);
        (1..n).all(|k| {
            let t = k as f64 / n as f64;
            let (x, y, z) = (
                a.x + t * (b.x - a.x),
                a.y + t * (b.y - a.y),
                a.z + t * (b.z - a.z),
            );
            // As a pass's own chords: at most `tol` below the drop.
            self.on_part(x, y).is_some_and(|d| d <= z + tol)
        })
    }
}

/// The finishing program of a patch job.
pub(crate) fn raster_finish(
    job: &Job,
    f: &Finish,
    part: &RasterPart,
) -> Result<Finished, FinishError> {
    use rayon::prelude::*;
    let tol = job.operation.tolerance;
    let (dy, ds) = spacing(f, part.max_slope_y, tol)?;
    let dy = if part.valleys { dy / VALLEY_PASSES } else { dy };
    let r = f.radius();
    let (lo, size) = part.rect;
    let ys = stations(lo.y - r, lo.y + size.y + r, dy);
    let xs = stations(lo.x - r, lo.x + size.x + r, ds);
    if ys.len() > MAX_PASSES || ys.len().saturating_mul(xs.len()) > MAX_SAMPLES {
        return Err(FinishError::TooManyRasterSamples {
            passes: ys.len(),
            samples: xs.len(),
            max_passes: MAX_PASSES,
            max_samples: MAX_SAMPLES,
        });
    }
    let dropper = Dropper {
        cutter: cutter_of(f),
        part,
    };
    let back: Vec<f64> = xs.iter().rev().copied().collect();
    let passes: Vec<(f64, Vec<Vec3>)> = ys
        .par_iter()
        .enumerate()
        .map(|(k, &y)| {
            let along = if k % 2 == 0 { &xs } else { &back };
            (y, dropper.pass(along, y, 0.5 * tol))
        })
        .filter(|(_, p)| p.len() >= 2)
        .collect();
    let mut sections = Vec::with_capacity(passes.len());
    let mut last: Option<Vec3> = None;
    for (k, (y, pass)) in passes.iter().enumerate() {
        let mut moves = Vec::with_capacity(pass.len() + 4);
        let b = pass[0];
        match last {
            Some(a) if dropper.link_clear(a, b, ds, 0.5 * tol) => moves.push(Move::Linear {
                to: b,
                feed: f.feed,
            }),
            _ => {
                if let Some(a) = last {
                    moves.push(Move::Rapid {
                        to: Vec3::new(a.x, a.y, job.stock.retract_z),
                    });
                }
                let over = if last.is_some() {
                    job.stock.retract_z
                } else {
                    job.stock.safe_z
                };
                // Down beside the part, then in along the pass: no
                // straight descent onto what the roughing left.
                let p0 = dropper.approach(pass, r, 0.5 * tol);
                moves.push(Move::Rapid {
                    to: Vec3::new(p0.x, p0.y, over),
                });
                moves.push(Move::Rapid {
                    to: Vec3::new(p0.x, p0.y, job.stock.retract_z),
                });
                moves.push(Move::Linear {
                    to: p0,
                    feed: f.plunge_feed,
                });
                if p0 != b {
                    moves.push(Move::Linear {
                        to: b,
                        feed: f.feed,
                    });
                }
            }
        }
        for &p in &pass[1..] {
            moves.push(Move::Linear {
                to: p,
                feed: f.feed,
            });
        }
        last = pass.last().copied();
        let z = pass.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
        sections.push(Section {
            label: format!(
                "{} {} y {:.3} {}",
                crate::toolpath::FINISH_PASS,
                k + 1,
                y,
                crate::toolpath::RASTER_PASS
            ),
            z,
            moves,
        });
    }
    if let (Some(end), Some(s)) = (last, sections.last_mut()) {
        s.moves.push(Move::Rapid {
            to: Vec3::new(end.x, end.y, job.stock.safe_z),
        });
    }
    let width = pass_width(f.corner, f.scallop);
    Ok(Finished {
        toolpath: Toolpath {
            start: Vec3::new(0.0, 0.0, job.stock.safe_z),
            sections,
        },
        width,
        lower_bound_s: part.area / width / f.feed * 60.0,
    })
}
