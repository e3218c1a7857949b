//! Outlines and counters from a bag of closed contours, by containment depth.
//!
//! A contour nested inside an even number of others (0, 2, …) bounds material from
//! outside: it is an *outline* and is made counter-clockwise. One nested inside an
//! odd number is a *counter* (a hole) and is made clockwise; it belongs to the
//! outline that directly encloses it. An island inside a counter (depth 2) is a
//! new outline with its own region. Containment uses the winding number of the
//! paper's Appendix I ([`polygon_winding_number`]) on a fine flattening.
//!
//! The contours must not cross each other (fonts and well-formed SVG satisfy this);
//! where they do, the result follows the majority of three test points.

use super::{polygon_winding_number, Contour, Region, Segment, Vec2};

/// Relative flattening tolerance for the containment test: a fraction of the
/// container's bounding-box diagonal. Contours closer together than this can be
/// misjudged; 1e-5 of a 50 mm letter is 0.5 µm, far below any tool.
const NEST_TOL: f64 = 1e-5;

/// Contours whose |area| is below this fraction of their bounding-box diagonal
/// squared have no inside (a path that doubles back on itself) and are dropped.
const DEGENERATE_AREA: f64 = 1e-12;

/// Whether a contour encloses area: |signed area| > `DEGENERATE_AREA` × d²,
/// d its box's diagonal (a ratio, so the same at every scale). Contours that
/// do not (a subpath drawn forth and back along a line) are no region.
pub(crate) fn encloses_area(c: &Contour) -> bool {
    let diag = c.bbox().map(|(lo, hi)| (hi - lo).norm2()).unwrap_or(0.0);
    diag > 0.0 && c.signed_area().abs() > DEGENERATE_AREA * diag
}

/// Splits `contours` into regions: outlines counter-clockwise, each with the
/// counters directly inside it clockwise. Regions come in the order of their
/// outlines in `contours`; counters keep their input order.
///
/// Names: a single region is called `name`; several are numbered from 1, inside
/// the parentheses when `name` ends with one (`i (3)` → `i (3.1)`, `i (3.2)`), else
/// appended (`logo` → `logo (1)`).
pub fn regions_from_contours(name: &str, contours: Vec<Contour>) -> Vec<Region> {
    let contours: Vec<Contour> = contours.into_iter().filter(encloses_area).collect();
    let n = contours.len();
    let boxes: Vec<(Vec2, Vec2)> = contours
        .iter()
        .map(|c| c.bbox().unwrap_or((Vec2::ZERO, Vec2::ZERO)))
        .collect();
    let polys: Vec<Vec<Vec2>> = contours
        .iter()
        .zip(&boxes)
        .map(|(c, (lo, hi))| c.flatten(NEST_TOL * (*hi - *lo).norm()))
        .collect();
    let probes: Vec<[Vec2; 3]> = contours.iter().map(test_points).collect();

    // inside[i][j]: contour i lies inside contour j.
    let inside = |i: usize, j: usize| -> bool {
        if i == j {
            return false;
        }
        let (lo, hi) = boxes[j];
        let votes = probes[i]
            .iter()
            .filter(|p| {
                p.x >= lo.x
                    && p.x <= hi.x
                    && p.y >= lo.y
                    && p.y <= hi.y
                    && polygon_winding_number(&polys[j], **p) != 0
            })
            .count();
        votes >= 2
    };
    let containers: Vec<Vec<usize>> = (0..n)
        .map(|i| (0..n).filter(|&j| inside(i, j)).collect())
        .collect();
    let depth: Vec<usize> = containers.iter().map(Vec::len).collect();
    // The direct parent: the deepest container (ties cannot happen without crossings;
    // the smaller area then decides).
    let parent: Vec<Option<usize>> = containers
        .iter()
        .map(|cs| {
            cs.iter().copied().max_by(|&a, &b| {
                depth[a].cmp(&depth[b]).then(
                    contours[b]
                        .signed_area()
                        .abs()
                        .total_cmp(&contours[a].signed_area().abs()),
                )
            })
        })
        .collect();

    let outlines: Vec<usize> = (0..n).filter(|&i| depth[i] % 2 == 0).collect();
    let many = outlines.len() > 1;
    outlines
        .iter()
        .enumerate()
        .map(|(k, &o)| Region {
            name: if many {
                numbered(name, k + 1)
            } else {
                name.to_string()
            },
            outline: oriented(&contours[o], true),
            counters: (0..n)
                .filter(|&c| depth[c] % 2 == 1 && parent[c] == Some(o))
                .map(|c| oriented(&contours[c], false))
                .collect(),
        })
        .collect()
}

/// `c` made counter-clockwise (`ccw`) or clockwise.
fn oriented(c: &Contour, ccw: bool) -> Contour {
    if c.is_ccw() == ccw {
        c.clone()
    } else {
        c.reversed()
    }
}

/// Three points on the contour, at the middles of segments spread along it.
fn test_points(c: &Contour) -> [Vec2; 3] {
    let n = c.segments.len();
    let at = |k: usize| -> Vec2 {
        let s: &Segment = &c.segments[k.min(n - 1)];
        s.eval(0.5)
    };
    [at(0), at(n / 3), at(2 * n / 3)]
}

fn numbered(name: &str, k: usize) -> String {
    match name.strip_suffix(')') {
        Some(head) if head.contains('(') => format!("{head}.{k})"),
        _ => format!("{name} ({k})"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::contour::tests::{circle, square};

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    #[test]
    fn letter_o_has_one_cw_counter() {
        // Both given clockwise, counter first: orientation and order are repaired.
        let outer = circle(v(0.0, 0.0), 10.0).reversed();
        let inner = circle(v(0.5, 0.0), 6.0).reversed();
        let regions = regions_from_contours("O (1)", vec![inner.clone(), outer.clone()]);
        assert_eq!(regions.len(), 1);
        let r = &regions[0];
        assert_eq!(r.name, "O (1)");
        assert!(r.outline.is_ccw());
        assert_eq!(r.outline, outer.reversed());
        assert_eq!(r.counters.len(), 1);
        assert!(!r.counters[0].is_ccw());
        assert_eq!(r.counters[0], inner);
    }

    #[test]
    fn ring_inside_a_ring() {
        // Two concentric rings: depths 0, 1, 2, 3 → two regions with a counter each.
        let cs = vec![
            circle(Vec2::ZERO, 4.0),
            circle(Vec2::ZERO, 20.0),
            circle(Vec2::ZERO, 6.0).reversed(),
            circle(Vec2::ZERO, 15.0),
        ];
        let regions = regions_from_contours("rings", cs);
        assert_eq!(regions.len(), 2);
        assert_eq!(regions[0].name, "rings (1)");
        assert_eq!(regions[1].name, "rings (2)");
        // Region order follows the outlines' input order: the r = 20 ring, then r = 6.
        let radius = |c: &Contour| c.bbox().map(|(lo, hi)| (hi.x - lo.x) / 2.0).unwrap_or(0.0);
        assert!((radius(&regions[0].outline) - 20.0).abs() < 1e-9);
        assert!((radius(&regions[0].counters[0]) - 15.0).abs() < 1e-9);
        assert!((radius(&regions[1].outline) - 6.0).abs() < 1e-9);
        assert!((radius(&regions[1].counters[0]) - 4.0).abs() < 1e-9);
        for r in &regions {
            assert!(r.outline.is_ccw());
            assert_eq!(r.counters.len(), 1);
            assert!(r.counters.iter().all(|c| !c.is_ccw()));
        }
    }

    #[test]
    fn side_by_side_and_two_holes() {
        // A plate with two square holes, and a separate square beside it.
        let cs = vec![
            square(0.0, 0.0, 30.0),
            square(5.0, 5.0, 5.0),
            square(40.0, 0.0, 10.0).reversed(),
            square(20.0, 20.0, 5.0),
        ];
        let regions = regions_from_contours("x", cs);
        assert_eq!(regions.len(), 2);
        assert_eq!(regions[0].counters.len(), 2);
        assert!(regions[1].counters.is_empty());
        assert!(regions[1].outline.is_ccw());
        assert_eq!(regions[1].outline.signed_area(), 100.0);
        let holes: f64 = regions[0].counters.iter().map(Contour::signed_area).sum();
        assert_eq!(holes, -50.0);
    }

    #[test]
    fn degenerate_contours_dropped() {
        let flat = Contour::new(vec![
            Segment::Line {
                a: v(0.0, 0.0),
                b: v(1.0, 0.0),
            },
            Segment::Line {
                a: v(1.0, 0.0),
                b: v(0.0, 0.0),
            },
        ])
        .expect("closed");
        let regions = regions_from_contours("d", vec![flat, square(0.0, 0.0, 1.0)]);
        assert_eq!(regions.len(), 1);
        assert_eq!(regions[0].name, "d");
        assert!(regions_from_contours("e", vec![]).is_empty());
    }

    #[test]
    fn names() {
        assert_eq!(numbered("i (3)", 2), "i (3.2)");
        assert_eq!(numbered("logo", 1), "logo (1)");
        assert_eq!(numbered("a)", 1), "a) (1)");
    }

    #[test]
    fn independent_of_direction_and_start() {
        let base = vec![
            circle(Vec2::ZERO, 20.0),
            circle(v(-8.0, 0.0), 6.0),
            circle(v(8.0, 0.0), 6.0),
            circle(v(8.0, 0.0), 2.0),
        ];
        let want = regions_from_contours("b", base.clone());
        assert_eq!(want.len(), 2);
        assert_eq!(want[0].counters.len(), 2);
        assert_eq!(want[1].counters.len(), 0);
        for k in 0..4 {
            let varied: Vec<Contour> = base
                .iter()
                .enumerate()
                .map(|(i, c)| {
                    let c = c.cycled(k + i);
                    if (i + k) % 2 == 0 {
                        c.reversed()
                    } else {
                        c
                    }
                })
                .collect();
            let got = regions_from_contours("b", varied);
            assert_eq!(got.len(), want.len());
            for (g, w) in got.iter().zip(&want) {
                assert!((g.outline.signed_area() - w.outline.signed_area()).abs() < 1e-9);
                assert_eq!(g.counters.len(), w.counters.len());
                for (gc, wc) in g.counters.iter().zip(&w.counters) {
                    assert!((gc.signed_area() - wc.signed_area()).abs() < 1e-9);
                }
            }
        }
    }
}
