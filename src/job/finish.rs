//! `[finish]`: the finishing tool and its scallop bound, and
//! `operation.stock_to_leave`, what the roughing leaves on the walls for it.
//!
//! GRBL has no tool changer, so a job with a `[finish]` table writes two
//! programs: `<name>.rough.nc` with `[tool]` and `<name>.finish.nc` with this
//! tool (docs/job-format.md, docs/method.md §12).

use super::resolve::{one_of, show};
use super::{invalid, limits, JobError};
use serde::Deserialize;

/// The shape of a cutter's end.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum CutterShape {
    /// Flat end mill.
    Flat,
    /// Ball end mill: corner radius = radius.
    Ball,
    /// Bull nose: a flat end with a corner radius between 0 and the radius.
    Bull,
}

impl CutterShape {
    /// The words of the G-code header's tool line (`ball end mill`).
    pub(crate) fn header_words(self) -> &'static str {
        match self {
            CutterShape::Flat => "end mill",
            CutterShape::Ball => "ball end mill",
            CutterShape::Bull => "bull nose end mill",
        }
    }
}

/// The finishing tool.
#[derive(Clone, Debug, PartialEq)]
pub struct Finish {
    /// Flat, ball or bull nose.
    pub(crate) shape: CutterShape,
    /// Diameter, mm.
    pub(crate) diameter: f64,
    /// Corner radius, mm: 0 (flat), the radius (ball), or between (bull).
    pub(crate) corner: f64,
    /// Cutting feed, mm/min.
    pub(crate) feed: f64,
    /// Plunge and ramp feed, mm/min.
    pub(crate) plunge_feed: f64,
    /// Spindle speed, rev/min.
    pub(crate) spindle: f64,
    /// Largest scallop height the passes may leave on the surface, mm.
    pub scallop: f64,
    /// How a boss's or cavity's wall passes are laid out.
    pub(crate) pattern: Pattern,
}

/// `finish.pattern`: the curves a boss's or cavity's wall passes follow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Pattern {
    /// Equipotentials Γ(s), whole, spaced for each wall's widest place.
    Equipotential,
    /// Levels of the distance on S2 from the top edge (`finish::geodesic`).
    Geodesic,
}

/// The accepted `finish.pattern` words.
pub(crate) const PATTERNS: &[&str] = &["equipotential", "geodesic"];

impl Finish {
    /// Radius, mm.
    pub(crate) fn radius(&self) -> f64 {
        self.diameter / 2.0
    }
}

/// `[finish]` as written.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawFinish {
    /// `shape`: ball, flat or bull
    pub(crate) shape: Option<String>,
    /// `diameter`, mm
    pub(crate) diameter: Option<f64>,
    /// `corner_radius`, mm (bull)
    pub(crate) corner_radius: Option<f64>,
    /// `feed`, mm/min
    pub(crate) feed: Option<f64>,
    /// `plunge_feed`, mm/min
    pub(crate) plunge_feed: Option<f64>,
    /// `spindle`, rev/min
    pub(crate) spindle: Option<f64>,
    /// `scallop`, mm
    pub(crate) scallop: Option<f64>,
    /// `pattern`: equipotential or geodesic
    pub(crate) pattern: Option<String>,
}

/// Defaults of `[finish]`.
pub(crate) mod defaults {
    /// `finish.shape`.
    pub(crate) const SHAPE: &str = "ball";
    /// `finish.scallop`, mm: below what the eye and a thermoformed sheet show.
    pub(crate) const SCALLOP: f64 = 0.01;
    /// `operation.stock_to_leave` with a `[finish]` table, mm.
    pub(crate) const STOCK_TO_LEAVE: f64 = 0.2;
}

/// The accepted `finish.shape` words.
pub(crate) const SHAPES: &[&str] = &["ball", "flat", "bull"];

impl RawFinish {
    /// Checks `[finish]`; the feeds and spindle default to `[tool]`'s.
    pub(crate) fn resolve(self, tool: &super::Tool) -> Result<Finish, JobError> {
        let pattern = match self.pattern.as_deref() {
            None => Pattern::Geodesic,
            Some(p) => {
                one_of("finish.pattern", p, PATTERNS)?;
                if p == "geodesic" {
                    Pattern::Geodesic
                } else {
                    Pattern::Equipotential
                }
            }
        };
        let word = self.shape.unwrap_or_else(|| defaults::SHAPE.into());
        one_of("finish.shape", &word, SHAPES)?;
        let diameter = limits::TOOL_DIAMETER.check(
            "finish.diameter",
            self.diameter
                .ok_or_else(|| invalid("finish.diameter", "is required (mm)"))?,
        )?;
        let r = diameter / 2.0;
        let (shape, corner) = match (word.as_str(), self.corner_radius) {
            ("bull", None) => {
                return Err(invalid(
                    "finish.corner_radius",
                    "is required for a bull nose (mm, between 0 and the radius)",
                ))
            }
            ("bull", Some(c)) => {
                if !(c.is_finite() && c > 0.0 && c < r) {
                    return Err(invalid(
                        "finish.corner_radius",
                        format!(
                            "must lie strictly between 0 and the radius ({} mm), got {}",
                            show(r),
                            show(c)
                        ),
                    ));
                }
                (CutterShape::Bull, c)
            }
            (w, Some(_)) => {
                return Err(invalid(
                    "finish.corner_radius",
                    format!("only applies to shape = \"bull\" (this tool is {w:?})"),
                ))
            }
            ("flat", None) => (CutterShape::Flat, 0.0),
            _ => (CutterShape::Ball, r),
        };
        Ok(Finish {
            shape,
            diameter,
            corner,
            feed: limits::FEED.check("finish.feed", self.feed.unwrap_or(tool.feed))?,
            plunge_feed: limits::FEED.check(
                "finish.plunge_feed",
                self.plunge_feed.unwrap_or(tool.plunge_feed),
            )?,
            spindle: limits::SPINDLE
                .check("finish.spindle", self.spindle.unwrap_or(tool.spindle))?,
            scallop: limits::SCALLOP
                .check("finish.scallop", self.scallop.unwrap_or(defaults::SCALLOP))?,
            pattern,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::job::{parse_job, JobError};
    use std::path::Path;

    const BASE: &str = "[shape]\ntext = \"I\"\n[tool]\ndiameter = 3.0\nfeed = 700.0\n[operation]\nkind = \"boss\"\ndepth = 2.0\n";

    fn job(extra: &str) -> Result<crate::job::Job, JobError> {
        parse_job(&format!("{BASE}{extra}"), "t", Path::new("."))
    }

    fn key_of(e: JobError) -> String {
        match e {
            JobError::Invalid { key, .. } => key,
            other => panic!("not a key error: {other}"),
        }
    }

    #[test]
    fn finish_defaults_follow_the_tool_and_leave_stock() {
        let j = job("[finish]\ndiameter = 2.0\n").unwrap();
        let f = j.finish.as_ref().unwrap();
        assert_eq!(f.shape, CutterShape::Ball);
        assert_eq!(f.corner, 1.0);
        assert_eq!(f.feed, 700.0);
        assert_eq!(f.scallop, defaults::SCALLOP);
        assert_eq!(f.pattern, Pattern::Geodesic);
        let eq = job("[finish]\ndiameter = 2.0\npattern = \"equipotential\"\n").unwrap();
        assert_eq!(eq.finish.unwrap().pattern, Pattern::Equipotential);
        assert_eq!(j.operation.stock_to_leave, defaults::STOCK_TO_LEAVE);
        let fj = j.finishing().unwrap();
        assert_eq!((fj.tool.diameter, fj.tool.shape), (2.0, CutterShape::Ball));
        // Without [finish]: nothing left, one program.
        let plain = job("").unwrap();
        assert_eq!(plain.operation.stock_to_leave, 0.0);
        assert!(plain.finishing().is_none());
    }

    #[test]
    fn bad_finish_tables_name_their_key() {
        for (extra, key) in [
            (
                "[finish]\nshape = \"bull\"\ndiameter = 4.0\n",
                "finish.corner_radius",
            ),
            (
                "[finish]\nshape = \"bull\"\ndiameter = 4.0\ncorner_radius = 2.0\n",
                "finish.corner_radius",
            ),
            (
                "[finish]\ndiameter = 4.0\ncorner_radius = 1.0\n",
                "finish.corner_radius",
            ),
            (
                "[finish]\nshape = \"cone\"\ndiameter = 4.0\n",
                "finish.shape",
            ),
            (
                "[finish]\ndiameter = 4.0\npattern = \"spiral\"\n",
                "finish.pattern",
            ),
            ("[finish]\nfeed = 100.0\n", "finish.diameter"),
            (
                "[finish]\ndiameter = 4.0\nscallop = 0.0\n",
                "finish.scallop",
            ),
            ("[finish]\ndiameter = 4.0\nfeed = 1e300\n", "finish.feed"),
        ] {
            assert_eq!(key_of(job(extra).unwrap_err()), key, "{extra}");
        }
        let bull =
            job("[finish]\nshape = \"bull\"\ndiameter = 4.0\ncorner_radius = 0.5\n").unwrap();
        assert_eq!(bull.finish.unwrap().corner, 0.5);
        // A profile has neither.
        let profile = BASE.replace("\"boss\"", "\"profile\"");
        let e = parse_job(
            &format!("{profile}[finish]\ndiameter = 2.0\n"),
            "t",
            Path::new("."),
        );
        assert_eq!(key_of(e.unwrap_err()), "finish");
        let e = parse_job(
            &format!("{profile}stock_to_leave = 0.3\n"),
            "t",
            Path::new("."),
        );
        assert_eq!(key_of(e.unwrap_err()), "operation.stock_to_leave");
    }
}
