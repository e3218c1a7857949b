//! Honest estimates and guards (issue 14): a quick lower bound of a job's
//! machining time, computed from its outlines before the expensive work, and
//! the checks of `machine.max_hours` and `machine.max_file_mb` against that
//! bound and against the finished program.
//!
//! The bound of a boss or cavity is the issue's: the area to clear at each
//! stepdown ÷ `tool.stepover` ÷ `tool.feed`, plus the outline at every level ÷
//! `tool.feed`. The pass along the outline itself sweeps a band one diameter
//! wide, so that band is taken off the area before dividing by the stepover
//! (the outline is not counted twice). Rapids, plunges, ramps and links add to
//! it, never subtract: a program cannot be faster than its bound.

use crate::geometry::Vec2;
use crate::geometry::{closed_length, polygon_area};
use crate::job::Machine;

/// One level of a boss or cavity as the bound sees it.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub(crate) struct LevelArea {
    /// Area of stock the level removes (a boss: the stock rectangle minus the
    /// part's section; a cavity: the cavity's section), mm².
    pub(crate) clear_area: f64,
    /// Length of the level's outline Γ(s), mm.
    pub(crate) outline: f64,
}

/// The level's outline and the area it leaves to clear, from its contours
/// (material on their left: outlines counter-clockwise, holes clockwise). A
/// boss gives its stock rectangle (the area is what lies outside the part); a
/// cavity gives none (the area is the cavity's own).
pub(crate) fn level_area(polys: &[Vec<Vec2>], stock: Option<(Vec2, Vec2)>) -> LevelArea {
    let inside: f64 = polys.iter().map(|p| polygon_area(p)).sum();
    let clear_area = match stock {
        Some((lo, hi)) => (hi.x - lo.x) * (hi.y - lo.y) - inside,
        None => inside,
    };
    LevelArea {
        clear_area: clear_area.max(0.0),
        outline: polys.iter().map(|p| closed_length(p)).sum(),
    }
}

/// A lower bound of a program's machining time, in its two parts.
#[derive(Clone, Copy, Debug, PartialEq, Default, serde::Serialize)]
pub struct LowerBound {
    /// Clearing: the area to clear at each stepdown, less the band the
    /// outline pass sweeps, ÷ stepover ÷ feed, s.
    pub(crate) clearing_s: f64,
    /// The outline at every level (every pass of a profile) ÷ feed, s.
    pub(crate) outline_s: f64,
}

impl LowerBound {
    /// The whole bound, s.
    pub(crate) fn total_s(&self) -> f64 {
        self.clearing_s + self.outline_s
    }
}

/// The bound of a boss or cavity: `rough` are the levels of the plain stepdown
/// schedule (each clears its whole area), `all` every level cut (each runs
/// its outline at least once); mm, mm/min.
pub(crate) fn levels_bound(
    rough: &[LevelArea],
    all: &[LevelArea],
    diameter: f64,
    stepover: f64,
    feed: f64,
) -> LowerBound {
    let rest: f64 = rough
        .iter()
        .map(|l| (l.clear_area - diameter * l.outline).max(0.0))
        .sum();
    let outline: f64 = all.iter().map(|l| l.outline).sum();
    LowerBound {
        clearing_s: rest / stepover / feed * 60.0,
        outline_s: outline / feed * 60.0,
    }
}

/// The bound of a profile: every pass runs a loop around every outline, and
/// a closed loop around an outline is at least as long as the outline's
/// convex hull.
pub(crate) fn profile_bound(outlines: &[Vec<Vec2>], passes: usize, feed: f64) -> LowerBound {
    let hulls: f64 = outlines
        .iter()
        .map(|o| closed_length(&convex_hull(o)))
        .sum();
    LowerBound {
        clearing_s: 0.0,
        outline_s: passes as f64 * hulls / feed * 60.0,
    }
}

/// The convex hull of points, counter-clockwise (Andrew's monotone chain).
pub(crate) fn convex_hull(points: &[Vec2]) -> Vec<Vec2> {
    let mut p: Vec<Vec2> = points
        .iter()
        .copied()
        .filter(|q| q.x.is_finite() && q.y.is_finite())
        .collect();
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let mut hull: Vec<Vec2> = Vec::with_capacity(2 * p.len());
    for pass in [&p[..], &p.iter().rev().copied().collect::<Vec<_>>()[..]] {
        let base = hull.len();
        for &q in pass {
            while hull.len() >= base + 2
                && (hull[hull.len() - 1] - hull[hull.len() - 2]).cross(q - hull[hull.len() - 2])
                    <= 0.0
            {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
    hull
}

/// Why a job is refused for its time or size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cause {
    /// Clearing dominates at a stepover of at least the default fraction of
    /// the diameter: the tool is small for the area.
    ToolTooSmall,
    /// Clearing dominates and the stepover is finer than the default.
    StepoverTooSmall,
    /// The outlines of all the levels dominate.
    OutlineTooLong,
}

impl Cause {
    /// The cause of a bound's size: its larger part, and for clearing the
    /// stepover against the default 0.4 × diameter.
    pub(crate) fn of(bound: &LowerBound, diameter: f64, stepover: f64) -> Cause {
        if bound.outline_s > bound.clearing_s {
            Cause::OutlineTooLong
        } else if stepover < crate::job::defaults::STEPOVER_FRACTION * diameter * (1.0 - 1e-9) {
            Cause::StepoverTooSmall
        } else {
            Cause::ToolTooSmall
        }
    }

    /// The cause in words, with the keys that change it.
    pub(crate) fn advice(self) -> &'static str {
        match self {
            Cause::ToolTooSmall => "tool too small for the area: use a larger tool.diameter (with its tool.stepover), or raise tool.feed",
            Cause::StepoverTooSmall => "stepover too small: raise tool.stepover (the default is 0.4 × tool.diameter), or raise tool.feed",
            Cause::OutlineTooLong => "outlines too long for the feed: raise tool.feed, or tool.stepdown / operation.max_scallop for fewer levels",
        }
    }
}

/// A job or program that passes `machine.max_hours` or `machine.max_file_mb`.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum GuardError {
    /// The lower bound alone passes `machine.max_hours` (found before the work).
    #[error("machine.max_hours = {max_hours} h: this job needs at least {:.1} h of cutting (lower bound: clearing {:.1} h, outlines {:.1} h), before any level was traced; cause: {}; or raise machine.max_hours", hours(bound.total_s()), hours(bound.clearing_s), hours(bound.outline_s), cause.advice())]
    BoundTooLong {
        /// the bound
        bound: LowerBound,
        /// the limit, h
        max_hours: f64,
        /// why
        cause: Cause,
    },
    /// The finished program's estimated time passes `machine.max_hours`.
    #[error("machine.max_hours = {max_hours} h: the program's estimated time is {} ({hours:.3} h, as its header would say): raise tool.stepover, tool.diameter or tool.feed, or machine.max_hours", crate::gcode::format_duration(hours * 3600.0))]
    TooLong {
        /// the estimate, h
        hours: f64,
        /// the limit, h
        max_hours: f64,
    },
    /// The program's G-code passes `machine.max_file_mb`.
    #[error("machine.max_file_mb = {max_mb} MB: the G-code would be {mb:.6} MB: raise tool.stepover or tool.diameter (fewer moves), or machine.max_file_mb")]
    TooLarge {
        /// the size, MB
        mb: f64,
        /// the limit, MB
        max_mb: f64,
    },
}

fn hours(s: f64) -> f64 {
    s / 3600.0
}

/// The bound against `machine.max_hours`.
pub(crate) fn check_bound(
    bound: &LowerBound,
    max_hours: f64,
    diameter: f64,
    stepover: f64,
) -> Result<(), GuardError> {
    if hours(bound.total_s()) <= max_hours {
        return Ok(());
    }
    Err(GuardError::BoundTooLong {
        bound: *bound,
        max_hours,
        cause: Cause::of(bound, diameter, stepover),
    })
}

/// A finished program (its header's estimated time in seconds and its
/// G-code's size in bytes) against `machine.max_hours` and `machine.max_file_mb`.
pub fn check_program(time_s: f64, bytes: usize, machine: &Machine) -> Result<(), GuardError> {
    let h = hours(time_s);
    if h > machine.max_hours || h.is_nan() {
        return Err(GuardError::TooLong {
            hours: h,
            max_hours: machine.max_hours,
        });
    }
    let mb = bytes as f64 / 1e6;
    if mb > machine.max_file_mb {
        return Err(GuardError::TooLarge {
            mb,
            max_mb: machine.max_file_mb,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Vec2> {
        vec![
            Vec2::new(x0, y0),
            Vec2::new(x1, y0),
            Vec2::new(x1, y1),
            Vec2::new(x0, y1),
        ]
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-9 * b.abs().max(1.0)
    }

    /// A 20 mm square boss on a 40 × 30 mm stock: 1200 − 400 = 800 mm² to
    /// clear and 80 mm of outline; a 20 mm square cavity with a 10 mm square
    /// island (clockwise): 400 − 100 = 300 mm² and 120 mm.
    #[test]
    fn level_areas_by_hand() {
        let square = rect(10.0, 5.0, 30.0, 25.0);
        let stock = (Vec2::new(0.0, 0.0), Vec2::new(40.0, 30.0));
        let b = level_area(std::slice::from_ref(&square), Some(stock));
        assert!(
            close(b.clear_area, 800.0) && close(b.outline, 80.0),
            "{b:?}"
        );
        let island: Vec<Vec2> = rect(15.0, 10.0, 25.0, 20.0).into_iter().rev().collect();
        let c = level_area(&[square, island], None);
        assert!(
            close(c.clear_area, 300.0) && close(c.outline, 120.0),
            "{c:?}"
        );
        // A part larger than its stock leaves nothing (never a negative area).
        let big = rect(-10.0, -10.0, 50.0, 40.0);
        assert_eq!(level_area(&[big], Some(stock)).clear_area, 0.0);
    }

    /// The square boss, 3 mm tool at 1.2 mm stepover and 600 mm/min, two
    /// stepdown levels and one added level: clearing 2 × (800 − 3 × 80) / 1.2
    /// / 600 min = 1.5556 min; outlines 3 × 80 / 600 min = 0.4 min.
    #[test]
    fn boss_bound_by_hand() {
        let l = LevelArea {
            clear_area: 800.0,
            outline: 80.0,
        };
        let b = levels_bound(&[l, l], &[l, l, l], 3.0, 1.2, 600.0);
        assert!(
            close(b.clearing_s, 2.0 * 560.0 / 1.2 / 600.0 * 60.0),
            "{b:?}"
        );
        assert!(close(b.outline_s, 24.0), "{b:?}");
        assert!(close(b.total_s(), 93.333_333_333_333_33 + 24.0), "{b:?}");
        // A tool so wide its outline pass sweeps everything: outlines only.
        let b = levels_bound(&[l], &[l], 20.0, 8.0, 600.0);
        assert_eq!(b.clearing_s, 0.0);
    }

    /// An L-shaped outline's hull is its bounding square cut at one corner;
    /// two passes of it and of a 10 mm square at 600 mm/min.
    #[test]
    fn profile_bound_by_hand() {
        let l_shape = vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(20.0, 0.0),
            Vec2::new(20.0, 5.0),
            Vec2::new(5.0, 5.0),
            Vec2::new(5.0, 20.0),
            Vec2::new(0.0, 20.0),
        ];
        let hull = convex_hull(&l_shape);
        assert_eq!(hull.len(), 5, "{hull:?}");
        let hull_len = 20.0 + 5.0 + 15.0 * 2f64.sqrt() + 5.0 + 20.0;
        assert!(close(closed_length(&hull), hull_len));
        assert!(polygon_area(&hull) > 0.0, "counter-clockwise");
        let b = profile_bound(&[l_shape, rect(30.0, 0.0, 40.0, 10.0)], 2, 600.0);
        assert!(close(b.outline_s, 2.0 * (hull_len + 40.0) / 10.0), "{b:?}");
        assert_eq!(b.clearing_s, 0.0);
    }

    #[test]
    fn causes_and_messages() {
        let clearing = LowerBound {
            clearing_s: 7200.0,
            outline_s: 100.0,
        };
        assert!(check_bound(
            &LowerBound {
                clearing_s: 3000.0,
                outline_s: 600.0
            },
            1.0,
            3.0,
            1.2
        )
        .is_ok());
        let e = check_bound(&clearing, 1.0, 0.5, 0.2).unwrap_err();
        assert_eq!(
            e.to_string().split(':').next(),
            Some("machine.max_hours = 1 h")
        );
        assert!(e.to_string().contains("at least 2.0 h"), "{e}");
        assert!(e.to_string().contains("tool too small for the area"), "{e}");
        let e = check_bound(&clearing, 1.0, 3.0, 0.3).unwrap_err();
        assert!(
            e.to_string()
                .contains("stepover too small: raise tool.stepover"),
            "{e}"
        );
        let outlines = LowerBound {
            clearing_s: 100.0,
            outline_s: 7200.0,
        };
        let e = check_bound(&outlines, 1.0, 3.0, 1.2).unwrap_err();
        assert!(e.to_string().contains("raise tool.feed"), "{e}");
    }

    #[test]
    fn programs_against_hours_and_megabytes() {
        let m = Machine {
            max_hours: 2.0,
            max_file_mb: 1.5,
            ..Machine::default()
        };
        let st = |h: f64| h * 3600.0;
        assert!(check_program(st(2.0), 1_500_000, &m).is_ok());
        let e = check_program(st(2.01), 10, &m).unwrap_err();
        assert!(matches!(e, GuardError::TooLong { .. }), "{e}");
        assert!(
            e.to_string().starts_with(
                "machine.max_hours = 2 h: the program's estimated time is 2 h 0 min 36 s (2.010 h"
            ),
            "{e}"
        );
        let e = check_program(st(1.0), 1_500_001, &m).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("machine.max_file_mb = 1.5 MB: the G-code would be 1.500001 MB"),
            "{e}"
        );
        assert!(check_program(f64::NAN, 10, &m).is_err());
    }
}
