//! The profile operation: the tool centre traced around every outline (outside)
//! and inside every counter the tool fits into, cut in passes of at most
//! `stepdown` from the stock top to the depth.

use super::entry::{enter, ramp_loop, start_near, Entry};
use super::stock::{model_radius, StockMap};
use super::trace::{trace, Navigator, TraceError, TraceParams};
use super::{Move, Section, Toolpath, Vec3};
pub(crate) use crate::geometry::deepest_point;
use crate::geometry::{DistanceIndex, Shape, Vec2};

/// Settings of a profile, mm and mm/min.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProfileParams {
    /// Tool radius.
    pub radius: f64,
    /// Chord tolerance.
    pub(crate) tol: f64,
    /// Climb milling (material on the tool's right with an M3 spindle).
    pub(crate) climb: bool,
    /// Stock top Z.
    pub top: f64,
    /// Depth below the top.
    pub(crate) depth: f64,
    /// Largest depth per pass.
    pub(crate) stepdown: f64,
    /// Safe Z for rapids.
    pub(crate) safe_z: f64,
    /// Cutting feed.
    pub(crate) feed: f64,
    /// Plunge and ramp feed.
    pub(crate) plunge_feed: f64,
    /// Ramp angle for entries into material, degrees.
    pub(crate) ramp_angle: f64,
}

impl ProfileParams {
    /// The entry settings of these parameters.
    pub(crate) fn entry(&self) -> Entry {
        Entry {
            radius: self.radius,
            ramp_angle: self.ramp_angle,
            plunge_feed: self.plunge_feed,
            feed: self.feed,
            safe_z: self.safe_z,
            top: self.top,
        }
    }
}

/// One traced loop.
#[derive(Clone, Debug, PartialEq)]
pub struct Loop {
    /// e.g. `outside A (1)` or `counter 1 of A (1)`.
    pub label: String,
    /// Centre positions, closed (last = first).
    pub points: Vec<Vec2>,
    /// Field fallbacks (see `Traced::fallbacks`).
    pub(crate) fallbacks: usize,
}

/// Why a profile failed.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum ProfileError {
    /// Tracing one loop failed.
    #[error("tracing {label}: {source}")]
    Trace {
        /// which loop
        label: String,
        /// why
        source: TraceError,
    },
    /// A field solved for a path (a cavity's inverse problem) failed.
    #[error("{0}")]
    Field(#[from] crate::field::FieldError),
    /// A boss level's clearing loop has too many points for the exact
    /// difference of the stock rectangle and the part's ring
    /// ([`clearing`](super::clearing)).
    #[error("{path}: {source}; raise operation.tolerance")]
    TooComplex {
        /// The clearing loop, as `level k (z …): loop j of the clearing`.
        path: String,
        /// The clearing's refusal.
        source: super::clearing::TooComplex,
    },
    /// A broken invariant: the distance between two clearing rings came out
    /// NaN.
    #[error("{level}: the distance between two clearing rings is not a number (NaN): this is a pfcam bug, please report it with the job file")]
    RingGapNotANumber {
        /// The level, as its paths' labels begin.
        level: String,
    },
    /// A broken invariant: the distance from the stock a clearing leaves to
    /// the part came out NaN (or infinite).
    #[error("{level}: the distance from the stock it leaves to the part is not a number (NaN): this is a pfcam bug, please report it with the job file")]
    StockGapNotANumber {
        /// The level, as its paths' labels begin.
        level: String,
    },
}

/// Z of every pass: equal steps of at most `stepdown`, the last exactly at the depth.
pub(crate) fn pass_depths(top: f64, depth: f64, stepdown: f64) -> Vec<f64> {
    let n = ((depth / stepdown) - 1e-9).ceil().max(1.0) as usize;
    (1..=n).map(|k| top - depth * k as f64 / n as f64).collect()
}

/// Trace every loop of the shape: for each region, its counters (inside first, so
/// the part is still held while its holes are cut), then its outline.
/// `polys[i]` is the flattening of the i-th contour of `shape.contours()`.
pub(crate) fn trace_loops<N: Navigator + Sync>(
    shape: &Shape,
    polys: &[Vec<Vec2>],
    part: &DistanceIndex,
    nav: &N,
    p: &ProfileParams,
    warnings: &mut Vec<String>,
) -> Result<Vec<Loop>, ProfileError> {
    use rayon::prelude::*;
    let r = p.radius;
    let tp = TraceParams {
        radius: r,
        tol: p.tol,
        part_on_left: !p.climb,
    };
    // (label, start point) for every loop, in cutting order.
    let mut jobs: Vec<(String, Vec2)> = Vec::new();
    let mut k = 0;
    for region in &shape.regions {
        let outline_poly = &polys[k];
        k += 1;
        for (ci, _) in region.counters.iter().enumerate() {
            let poly = &polys[k];
            k += 1;
            let label = format!("counter {} of {}", ci + 1, region.name);
            let (deep, room) = deepest_point(poly, part);
            if room < r + p.tol {
                warnings.push(format!(
                    "{label} is too small for the tool (largest inscribed radius {room:.3} mm, tool radius {r:.3} mm): not cut"
                ));
                continue;
            }
            jobs.push((label, deep));
        }
        // Outside: start below the lowest point of the outline.
        let low = outline_poly.iter().copied().fold(outline_poly[0], |a, b| {
            if b.y < a.y || (b.y == a.y && b.x < a.x) {
                b
            } else {
                a
            }
        });
        jobs.push((
            format!("outside {}", region.name),
            low - Vec2::new(0.0, 2.0 * r + 1.0),
        ));
    }
    jobs.par_iter()
        .map(|(label, start)| {
            trace(nav, part, *start, tp)
                .map(|t| Loop {
                    label: label.clone(),
                    points: t.points,
                    fallbacks: t.fallbacks,
                })
                .map_err(|source| ProfileError::Trace {
                    label: label.clone(),
                    source,
                })
        })
        .collect()
}

/// Link the loops into a tool path. For each loop: rapid above its start at safe
/// Z and enter it ([`enter`]: a rapid down to a clearance above the material
/// left, then a ramp along the loop from the material top to the first pass
/// depth and one full lap); each further pass ramps down along the loop from
/// the pass above, from where the tool stands, then cuts a full lap; then
/// retract to safe Z. A model of the sheet ([`StockMap`]) follows the cuts, so a
/// loop that starts where an earlier one cut is entered from what is left.
pub fn link(loops: &[Loop], p: &ProfileParams) -> Toolpath {
    let depths = pass_depths(p.top, p.depth, p.stepdown);
    let start = Vec3::new(0.0, 0.0, p.safe_z);
    let e = p.entry();
    let (lo, hi) = loops_bounds(loops, p.radius);
    let mut stock = StockMap::new(lo, hi, p.top, p.radius);
    let mut pos = start;
    let mut sections = Vec::new();
    for lp in loops {
        let s0 = lp.points[0];
        let mut moves = vec![Move::Rapid {
            to: Vec3::new(s0.x, s0.y, p.safe_z),
        }];
        let mut z_prev = None;
        for &z in &depths {
            match z_prev {
                None => enter(&stock, &lp.points, true, z, &e, &mut moves),
                Some(zp) => {
                    let at = moves.last().map_or(s0, |m| Vec2::new(m.to().x, m.to().y));
                    let pts = start_near(&lp.points, at);
                    moves.push(Move::Linear {
                        to: Vec3::new(pts[0].x, pts[0].y, zp),
                        feed: p.feed,
                    });
                    ramp_loop(&pts, zp, z, &e, &mut moves);
                }
            }
            z_prev = Some(z);
        }
        let end = moves.last().map_or(s0, |m| Vec2::new(m.to().x, m.to().y));
        moves.push(Move::Rapid {
            to: Vec3::new(end.x, end.y, p.safe_z),
        });
        pos = stock.cut_moves(pos, &moves, model_radius(p.radius, p.tol));
        sections.push(Section {
            label: lp.label.clone(),
            z: p.top - p.depth,
            moves,
        });
    }
    Toolpath { start, sections }
}

/// The rectangle the loops' tool disks cover: the sheet the linker models.
fn loops_bounds(loops: &[Loop], r: f64) -> (Vec2, Vec2) {
    let pts = loops.iter().flat_map(|l| l.points.iter());
    let (mut lo, mut hi) = (
        Vec2::new(f64::INFINITY, f64::INFINITY),
        -Vec2::new(f64::INFINITY, f64::INFINITY),
    );
    for q in pts {
        lo = Vec2::new(lo.x.min(q.x), lo.y.min(q.y));
        hi = Vec2::new(hi.x.max(q.x), hi.y.max(q.y));
    }
    if lo.x > hi.x {
        return (Vec2::ZERO, Vec2::ZERO);
    }
    let grow = Vec2::new(r, r);
    (lo - grow, hi + grow)
}

#[cfg(test)]
mod tests {
    use super::ProfileError;
    use crate::toolpath::clearing::TooComplex;

    /// The texts are the ones the variants had as strings (issue 16).
    #[test]
    fn errors_say_the_strings_they_replace() {
        let level = "level 2 (z -1.500)".to_string();
        let path = format!("{level}: loop 3 of the clearing");
        let bug = "is not a number (NaN): this is a pfcam bug, please report it with the job file";
        let cases = [
            (
                ProfileError::TooComplex { path: path.clone(), source: TooComplex },
                format!("{path}: too many points for the exact difference of the stock and the part's ring; raise operation.tolerance"),
            ),
            (
                ProfileError::RingGapNotANumber { level: level.clone() },
                format!("{level}: the distance between two clearing rings {bug}"),
            ),
            (
                ProfileError::StockGapNotANumber { level: level.clone() },
                format!("{level}: the distance from the stock it leaves to the part {bug}"),
            ),
        ];
        for (e, text) in cases {
            assert_eq!(e.to_string(), text);
        }
    }

    /// The clearing's refusal stays the error's source, and the message
    /// already says it (the CLI appends a source only when it does not).
    #[test]
    fn too_complex_keeps_the_clearing_error_as_its_source() {
        let e = ProfileError::TooComplex {
            path: "loop 1".into(),
            source: TooComplex,
        };
        let source = std::error::Error::source(&e).expect("a source");
        assert!(source.is::<TooComplex>());
        assert!(e.to_string().contains(&source.to_string()));
    }
}
