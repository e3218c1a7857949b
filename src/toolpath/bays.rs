//! Rest clearing of a boss's stepdown level: the stock its rings leave.
//!
//! The clearing rings around neighbouring outlines merge as they grow. Where
//! two rings merge at both ends of a gap between letters, the middle of the gap
//! is a hole of the region the rings enclose, and no ring enters it: a bay of
//! full-depth stock (mfs-sign's M–F gap kept two such columns a stepdown tall,
//! which the next stepdown level then met two stepdowns deep). They are found
//! on a grid and cleared by rings traced from inside, innermost first, as the
//! counters of letters are.

use super::profile::ProfileError;
use super::spot::spot_loop;
use super::trace::{trace, Navigator, TraceParams};
use super::zlevel::{CutPath, LevelParams};
use crate::geometry::{DistanceIndex, Vec2};

/// At most this many bays (or single spots) are cleared on one level; what is
/// left after them is reported.
pub(crate) const MAX_BAYS: usize = 200;

/// A path as a closed polygon with no chord of its own: an open run is walked
/// there and back, so that a distance index over it measures distance to the
/// run and not to a closing segment across the stock.
fn as_loop(c: &CutPath) -> Vec<Vec2> {
    let n = c.points.len();
    if c.closed {
        c.points[..n.saturating_sub(1).max(1)].to_vec()
    } else {
        let mut pts = c.points.clone();
        pts.extend(c.points[1..n.saturating_sub(1)].iter().rev());
        pts
    }
}

/// Grid points (spacing `h`) of the rectangle `[lo, hi]` outside the part,
/// where the tool centre may sit (at least `wall + tol` from the part), farther
/// than `r` from every path: the stock the paths leave that the tool can reach
/// from inside. As (distance to the part, point), deepest first.
#[allow(clippy::too_many_arguments)]
pub(crate) fn uncut_spots(
    part: &[Vec<Vec2>],
    index: &DistanceIndex,
    paths: &[CutPath],
    (lo, hi): (Vec2, Vec2),
    h: f64,
    wall: f64,
    r: f64,
    tol: f64,
) -> Vec<(f64, Vec2)> {
    let loops: Vec<Vec<Vec2>> = paths.iter().map(as_loop).collect();
    let pindex = DistanceIndex::new(&loops);
    let size = hi - lo;
    let (nx, ny) = (
        (size.x / h).floor() as usize + 1,
        (size.y / h).floor() as usize + 1,
    );
    let inside = crate::field::isolines::fill_rows(lo, h, nx, ny, part);
    let mut spots = Vec::new();
    let hint = std::cell::Cell::new(0);
    for j in 0..ny {
        for i in 0..nx {
            if inside[j * nx + i] {
                continue;
            }
            let q = lo + Vec2::new(i as f64 * h, j as f64 * h);
            let d = index.distance(q);
            if d >= wall + tol && !pindex.closer_than(q, r, &hint) {
                spots.push((d, q));
            }
        }
    }
    spots.sort_by(|a, b| {
        b.0.total_cmp(&a.0)
            .then(a.1.x.total_cmp(&b.1.x))
            .then(a.1.y.total_cmp(&b.1.y))
    });
    spots
}

/// Rings around the bay that holds `q` (`room` from the part), innermost
/// first, each a stepover outside the last, up to the first that is no longer
/// the bay's own (it runs along a ring already cut: the bay opens there).
fn bay_rings<N: Navigator>(
    nav: &N,
    index: &DistanceIndex,
    cut: &DistanceIndex,
    q: Vec2,
    room: f64,
    p: &LevelParams,
) -> Vec<Vec<Vec2>> {
    let r = p.wall();
    let n = ((room - r - p.tol) / p.stepover).floor().max(0.0) as usize;
    let mut rings = Vec::new();
    let hint = std::cell::Cell::new(0);
    for j in (0..=n).rev() {
        let rj = r + j as f64 * p.stepover;
        let tp = TraceParams {
            radius: rj,
            tol: p.tol,
            part_on_left: !p.climb,
        };
        let Ok(t) = trace(nav, index, q, tp) else {
            break;
        };
        let on_cut = t
            .points
            .iter()
            .filter(|&&x| cut.closer_than(x, 0.25 * p.stepover, &hint))
            .count();
        if 2 * on_cut > t.points.len() {
            break;
        }
        rings.push(t.points);
    }
    rings
}

/// Add to `paths` what clears the stock they leave on a boss's stepdown level
/// (see the module's comment): rings around each bay, or, where no ring of its
/// own fits, a small loop at the spot. `Err` only for a non-finite figure; a
/// level with stock still left after [`MAX_BAYS`] gets a warning.
pub(crate) fn clear_bays<N: Navigator>(
    part: &[Vec<Vec2>],
    index: &DistanceIndex,
    nav: &N,
    p: &LevelParams,
    label: &str,
    paths: &mut Vec<CutPath>,
    warnings: &mut Vec<String>,
) -> Result<(), ProfileError> {
    let r = p.radius;
    let h = 0.25 * r;
    let rect = (p.stock_lo, p.stock_hi);
    let mut spots = uncut_spots(part, index, paths, rect, h, p.wall(), r, p.tol);
    let mut bays = 0;
    while let Some(&(room, q)) = spots.first() {
        if !room.is_finite() {
            return Err(ProfileError::StockGapNotANumber {
                level: label.to_string(),
            });
        }
        if bays == MAX_BAYS {
            warnings.push(format!(
                "{label}: {} grid points of stock ({h:.2} mm apart) are left after clearing {MAX_BAYS} bays: check the part with `pfcam simulate`",
                spots.len()
            ));
            break;
        }
        bays += 1;
        let loops: Vec<Vec<Vec2>> = paths.iter().map(as_loop).collect();
        let cut = DistanceIndex::new(&loops);
        let ring_label = || format!("{label}: ring in a bay");
        let rings = bay_rings(nav, index, &cut, q, room, p);
        let rings: Vec<CutPath> = if rings.is_empty() {
            // No ring of its own: a loop of radius up to r/2 about the spot,
            // its disk still r + tol from the part.
            let rho = (0.5 * r).min(room - p.wall() - p.tol);
            vec![spot_loop(q, rho, ring_label())]
        } else {
            rings
                .into_iter()
                .map(|points| CutPath {
                    label: ring_label(),
                    points,
                    closed: true,
                    ring: None,
                })
                .collect()
        };
        let new = DistanceIndex::new(
            &rings
                .iter()
                .map(|c| c.points[..c.points.len() - 1].to_vec())
                .collect::<Vec<_>>(),
        );
        let hint = std::cell::Cell::new(0);
        spots.retain(|&(_, x)| x != q && !new.closer_than(x, r, &hint));
        paths.extend(rings);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_open_run_is_measured_without_a_closing_chord() {
        // A U-shaped run from (0, 0) up and over to (10, 0): the point (5, 0)
        // lies on the chord between its ends, 5 from the run.
        let run = CutPath {
            label: String::new(),
            points: vec![
                Vec2::new(0.0, 0.0),
                Vec2::new(0.0, 5.0),
                Vec2::new(10.0, 5.0),
                Vec2::new(10.0, 0.0),
            ],
            closed: false,
            ring: None,
        };
        let idx = DistanceIndex::new(&[as_loop(&run)]);
        assert!((idx.distance(Vec2::new(5.0, 0.0)) - 5.0).abs() < 1e-12);
        assert!(idx.distance(Vec2::new(5.0, 5.0)) < 1e-12);
    }
}
