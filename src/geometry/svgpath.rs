//! SVG path data (the `d` attribute): `M L H V C S Q T Z`, absolute (upper case)
//! and relative (lower case), with implicit repetition of a command's arguments
//! (extra pairs after `M`/`m` are `L`/`l`), smooth reflections for `S` and `T`, and
//! the compact number syntax (`1.5.5` is 1.5 then .5; `10-5` is 10 then −5).
//! Elliptical arcs (`A`/`a`) are refused with an error for now.
//!
//! Every subpath must be closed: by `Z`, or by ending where it started. The result
//! is flipped (SVG y points down, machine y up), scaled so that the tight bounding
//! box is `height` mm high when a height is given (else 1 unit = 1 mm), moved so
//! the box's bottom-left corner is at `origin`, then nested into outlines and
//! counters by [`regions_from_contours`].

use super::{regions_from_contours, Contour, GeometryError, Segment, Shape, Vec2};

/// A subpath whose end is within this distance (relative to the size of the path's
/// control-point box, at least 1 unit) of its start counts as closed; the gap is then
/// snapped shut. Relative coordinates summed in floating point leave ~1e-15.
const CLOSE_EPS: f64 = 1e-9;

fn err(offset: usize, message: impl Into<String>) -> GeometryError {
    GeometryError::Svg {
        offset,
        message: message.into(),
    }
}

/// The error of path data whose every subpath is a line drawn forth and back.
const NO_AREA: &str = "no subpath of the path data encloses any area";

/// The shape described by the path data `d` (see the module documentation).
pub fn svg_shape(d: &str, height: Option<f64>, origin: Vec2) -> Result<Shape, GeometryError> {
    let contours = parse_path(d)?;
    // Flip y, then scale and place by the tight box of the subpaths that
    // enclose area (the others are no part of the shape: a line drawn forth and
    // back would otherwise stretch the box the height and origin apply to).
    let flipped: Vec<Contour> = contours
        .iter()
        .map(|c| c.map(|p| Vec2::new(p.x, -p.y)))
        .filter(crate::geometry::nesting::encloses_area)
        .collect();
    if flipped.is_empty() && !contours.is_empty() {
        return Err(err(0, NO_AREA));
    }
    let bbox = flipped
        .iter()
        .filter_map(Contour::tight_bbox)
        .reduce(|(a, b), (c, d)| {
            (
                Vec2::new(a.x.min(c.x), a.y.min(c.y)),
                Vec2::new(b.x.max(d.x), b.y.max(d.y)),
            )
        });
    let Some((lo, hi)) = bbox else {
        return Err(err(
            0,
            "the path data draws nothing; expected at least one closed subpath",
        ));
    };
    let scale = match height {
        Some(h) => {
            let extent = hi.y - lo.y;
            if extent <= 0.0 {
                return Err(err(
                    0,
                    "the path has zero height, so it cannot be scaled to a height",
                ));
            }
            h / extent
        }
        None => 1.0,
    };
    let placed: Vec<Contour> = flipped
        .iter()
        .map(|c| c.map(|p| origin + (p - lo) * scale))
        .collect();
    let regions = regions_from_contours("path", placed);
    if regions.is_empty() {
        return Err(err(0, NO_AREA));
    }
    Ok(Shape { regions })
}

/// Parses `d` into closed contours, in SVG coordinates (y down), one per subpath
/// that draws something.
pub fn parse_path(d: &str) -> Result<Vec<Contour>, GeometryError> {
    let mut p = Parser {
        chars: d.chars().collect(),
        i: 0,
    };
    let mut b = PathBuilder::default();
    // The command in force and where it was written.
    let mut cmd: Option<(char, usize)> = None;
    loop {
        p.skip_separators();
        let Some(c) = p.peek() else { break };
        let at = p.i;
        let this = if c.is_ascii_alphabetic() {
            p.i += 1;
            if !"MmZzLlHhVvCcSsQqTtAa".contains(c) {
                return Err(err(
                    at,
                    format!("unknown path command `{c}`; expected one of M L H V C S Q T Z (or lower case)"),
                ));
            }
            if cmd.is_none() && c != 'M' && c != 'm' {
                return Err(err(
                    at,
                    format!("path data must start with a moveto (`M` or `m`), found `{c}`"),
                ));
            }
            (c, at)
        } else if is_number_start(c) {
            match cmd {
                None => {
                    return Err(err(
                        at,
                        "path data must start with a moveto (`M` or `m`), found a number",
                    ))
                }
                Some(('Z' | 'z', _)) => {
                    return Err(err(at, "expected a command after `Z`, found a number"));
                }
                // Extra coordinate pairs after a moveto are linetos.
                Some(('M', _)) => ('L', at),
                Some(('m', _)) => ('l', at),
                Some((k, _)) => (k, at),
            }
        } else {
            return Err(err(
                at,
                format!("unexpected character {c:?}; expected a path command or a number"),
            ));
        };
        if this.0 == 'A' || this.0 == 'a' {
            return Err(err(at, "elliptical arcs are not supported yet"));
        }
        b.command(&mut p, this.0, at)?;
        cmd = Some(this);
    }
    if cmd.is_none() {
        return Err(err(
            0,
            "the path data is empty; expected a moveto (`M` or `m`)",
        ));
    }
    b.end_subpath(None)?;
    Ok(b.contours)
}

fn is_number_start(c: char) -> bool {
    c.is_ascii_digit() || c == '.' || c == '-' || c == '+'
}

struct Parser {
    chars: Vec<char>,
    i: usize,
}

impl Parser {
    fn peek(&self) -> Option<char> {
        self.chars.get(self.i).copied()
    }

    fn skip_separators(&mut self) {
        while let Some(c) = self.peek() {
            if c.is_ascii_whitespace() || c == ',' {
                self.i += 1;
            } else {
                break;
            }
        }
    }

    fn digits(&mut self) -> usize {
        let start = self.i;
        while self.peek().is_some_and(|c| c.is_ascii_digit()) {
            self.i += 1;
        }
        self.i - start
    }

    /// The next number, argument `what` of command `cmd` (written at `cmd_at`).
    fn number(&mut self, cmd: char, what: &str) -> Result<f64, GeometryError> {
        self.skip_separators();
        let start = self.i;
        let found = |p: &Parser| match p.peek() {
            Some(c) => format!("found {c:?}"),
            None => "found the end of the data".to_string(),
        };
        if !self.peek().is_some_and(is_number_start) {
            return Err(err(
                start,
                format!("expected a number ({what}) for `{cmd}`, {}", found(self)),
            ));
        }
        if matches!(self.peek(), Some('+' | '-')) {
            self.i += 1;
        }
        let int = self.digits();
        let mut frac = 0;
        if self.peek() == Some('.') {
            self.i += 1;
            frac = self.digits();
        }
        if int + frac == 0 {
            self.i = start;
            return Err(err(
                start,
                format!(
                    "expected a number ({what}) for `{cmd}`, found {:?}",
                    self.chars[start..].iter().take(3).collect::<String>()
                ),
            ));
        }
        if matches!(self.peek(), Some('e' | 'E')) {
            self.i += 1;
            if matches!(self.peek(), Some('+' | '-')) {
                self.i += 1;
            }
            if self.digits() == 0 {
                return Err(err(
                    self.i,
                    format!("expected the digits of an exponent, {}", found(self)),
                ));
            }
        }
        let text: String = self.chars[start..self.i].iter().collect();
        match text.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(err(start, format!("the number {text} is out of range"))),
        }
    }

    fn pair(&mut self, cmd: char, what: &str) -> Result<Vec2, GeometryError> {
        let x = self.number(cmd, &format!("x of {what}"))?;
        let y = self.number(cmd, &format!("y of {what}"))?;
        Ok(Vec2::new(x, y))
    }
}

#[derive(Default)]
struct PathBuilder {
    contours: Vec<Contour>,
    segments: Vec<Segment>,
    /// Current point.
    cur: Vec2,
    /// Start of the current subpath.
    start: Vec2,
    /// Where the current subpath was begun (its `M`, or the command after `Z`).
    start_at: usize,
    /// Subpaths begun so far (1-based number of the current one).
    count: usize,
    /// True between a `Z` and the next command.
    closed: bool,
    /// Second control point of the previous `C`/`S`, for the reflection of `S`.
    last_cubic: Option<Vec2>,
    /// Control point of the previous `Q`/`T`, for the reflection of `T`.
    last_quad: Option<Vec2>,
}

impl PathBuilder {
    fn push(&mut self, s: Segment) {
        let degenerate = match s {
            Segment::Line { a, b } => a == b,
            Segment::Cubic { p0, p1, p2, p3 } => p0 == p1 && p1 == p2 && p2 == p3,
        };
        if !degenerate {
            self.segments.push(s);
        }
        self.cur = s.end();
    }

    /// Ends the current subpath: `Z` (`close_at` = its offset) closes it with a line;
    /// otherwise (a new `M`, or the end) it must already end where it started.
    fn end_subpath(&mut self, close_at: Option<usize>) -> Result<(), GeometryError> {
        if self.segments.is_empty() {
            self.cur = self.start;
            return Ok(());
        }
        let gap = self.cur.dist(self.start);
        if close_at.is_some() {
            if gap > 0.0 {
                self.segments.push(Segment::Line {
                    a: self.cur,
                    b: self.start,
                });
            }
        } else {
            let size = self
                .segments
                .iter()
                .flat_map(|s| [s.start(), s.end()])
                .fold(0.0_f64, |m, p| m.max(p.dist(self.start)))
                .max(1.0);
            if gap > CLOSE_EPS * size {
                return Err(err(
                    self.start_at,
                    format!(
                        "subpath {} is open: it starts at ({}, {}) but ends at ({}, {}); \
                         end it with Z or return to its start",
                        self.count, self.start.x, self.start.y, self.cur.x, self.cur.y
                    ),
                ));
            }
            // Snap the rounding gap shut.
            if let Some(last) = self.segments.last_mut() {
                let s = self.start;
                *last = match *last {
                    Segment::Line { a, .. } => Segment::Line { a, b: s },
                    Segment::Cubic { p0, p1, p2, .. } => Segment::Cubic { p0, p1, p2, p3: s },
                };
            }
        }
        let segs = std::mem::take(&mut self.segments);
        let contour = Contour::new(segs).map_err(|e| {
            err(
                self.start_at,
                format!("subpath {} could not be closed: {e}", self.count),
            )
        })?;
        self.contours.push(contour);
        self.cur = self.start;
        Ok(())
    }

    fn command(&mut self, p: &mut Parser, c: char, at: usize) -> Result<(), GeometryError> {
        let rel = c.is_ascii_lowercase();
        let base = if rel { self.cur } else { Vec2::ZERO };
        let upper = c.to_ascii_uppercase();
        if upper == 'M' {
            let to = p.pair(c, "the point")? + base;
            self.end_subpath(None)?;
            self.start = to;
            self.cur = to;
            self.start_at = at;
            self.count += 1;
            self.closed = false;
            self.last_cubic = None;
            self.last_quad = None;
            return Ok(());
        }
        if upper == 'Z' {
            self.end_subpath(Some(at))?;
            self.closed = true;
            self.last_cubic = None;
            self.last_quad = None;
            return Ok(());
        }
        // Drawing after `Z` without an `M` starts a new subpath at the old start.
        if self.closed {
            self.closed = false;
            self.start_at = at;
            self.count += 1;
        }
        let from = self.cur;
        let (mut cubic_ctrl, mut quad_ctrl) = (None, None);
        match upper {
            'L' => {
                let to = p.pair(c, "the end point")? + base;
                self.push(Segment::Line { a: from, b: to });
            }
            'H' => {
                let x = p.number(c, "x")? + base.x;
                self.push(Segment::Line {
                    a: from,
                    b: Vec2::new(x, from.y),
                });
            }
            'V' => {
                let y = p.number(c, "y")? + base.y;
                self.push(Segment::Line {
                    a: from,
                    b: Vec2::new(from.x, y),
                });
            }
            'C' => {
                let p1 = p.pair(c, "the first control point")? + base;
                let p2 = p.pair(c, "the second control point")? + base;
                let p3 = p.pair(c, "the end point")? + base;
                self.push(Segment::Cubic {
                    p0: from,
                    p1,
                    p2,
                    p3,
                });
                cubic_ctrl = Some(p2);
            }
            'S' => {
                let p1 = self.last_cubic.map_or(from, |q| from * 2.0 - q);
                let p2 = p.pair(c, "the second control point")? + base;
                let p3 = p.pair(c, "the end point")? + base;
                self.push(Segment::Cubic {
                    p0: from,
                    p1,
                    p2,
                    p3,
                });
                cubic_ctrl = Some(p2);
            }
            'Q' => {
                let q = p.pair(c, "the control point")? + base;
                let to = p.pair(c, "the end point")? + base;
                self.push(Segment::quad(from, q, to));
                quad_ctrl = Some(q);
            }
            'T' => {
                let q = self.last_quad.map_or(from, |q| from * 2.0 - q);
                let to = p.pair(c, "the end point")? + base;
                self.push(Segment::quad(from, q, to));
                quad_ctrl = Some(q);
            }
            _ => return Err(err(at, format!("unknown path command `{c}`"))),
        }
        self.last_cubic = cubic_ctrl;
        self.last_quad = quad_ctrl;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{build_shape, ShapeSource};

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    fn same(a: &[Contour], b: &[Contour]) {
        assert_eq!(a.len(), b.len());
        for (ca, cb) in a.iter().zip(b) {
            assert_eq!(ca.segments.len(), cb.segments.len());
            for (sa, sb) in ca.segments.iter().zip(&cb.segments) {
                let pa = match *sa {
                    Segment::Line { a, b } => vec![a, b],
                    Segment::Cubic { p0, p1, p2, p3 } => vec![p0, p1, p2, p3],
                };
                let pb = match *sb {
                    Segment::Line { a, b } => vec![a, b],
                    Segment::Cubic { p0, p1, p2, p3 } => vec![p0, p1, p2, p3],
                };
                assert_eq!(pa.len(), pb.len(), "{sa:?} vs {sb:?}");
                for (x, y) in pa.iter().zip(&pb) {
                    assert!(x.dist(*y) < 1e-12, "{sa:?} vs {sb:?}");
                }
            }
        }
    }

    fn svg_err(d: &str) -> (usize, String) {
        match parse_path(d) {
            Err(GeometryError::Svg { offset, message }) => (offset, message),
            other => panic!("{d}: expected an SVG error, got {other:?}"),
        }
    }

    #[test]
    fn absolute_and_relative_agree() {
        let abs = "M10 10 L50 10 H60 V40 C60 60 40 60 30 50 S 10 50 10 40 \
                   Q 0 30 5 25 T 10 10 Z M20 20 L25 20 L25 25 Z";
        let rel = "m10 10 l40 0 h10 v30 c0 20 -20 20 -30 10 s -20 0 -20 -10 \
                   q -10 -10 -5 -15 t 5 -15 z m10 10 l5 0 l0 5 z";
        let a = parse_path(abs).expect("abs");
        let r = parse_path(rel).expect("rel");
        assert_eq!(a.len(), 2);
        same(&a, &r);
        // S reflects C's second control point (40, 60) about (30, 50).
        match a[0].segments[4] {
            Segment::Cubic { p1, .. } => assert_eq!(p1, v(20.0, 40.0)),
            s => panic!("{s:?}"),
        }
        // T reflects Q's control (0, 30) about (5, 25): the quadratic's control is
        // (10, 20), so the raised cubic's first control is 5 + 2/3·(10 − 5) etc.
        let t = a[0].segments[6];
        let want = Segment::quad(v(5.0, 25.0), v(10.0, 20.0), v(10.0, 10.0));
        assert_eq!(t, want);
    }

    #[test]
    fn numbers_and_implicit_repetition() {
        let compact = parse_path("M0,0L1.5.5-1e-3 10-5 0-1e1,0z").expect("compact");
        let spaced = parse_path("M 0 0 L 1.5 0.5 L -0.001 10 L -5 0 L -10 0 Z").expect("spaced");
        same(&compact, &spaced);
        // Pairs after M are L; after m they are l.
        same(
            &parse_path("M0 0 10 0 10 10z").expect("M"),
            &parse_path("M0 0 L10 0 L10 10 Z").expect("L"),
        );
        same(
            &parse_path("m5 5 10 0 0 10z").expect("m"),
            &parse_path("M5 5 L15 5 L15 15 Z").expect("L"),
        );
        // Drawing after Z without M starts at the closed subpath's start.
        let after_z = parse_path("M0 0 H10 V10 Z l -5 0 l 0 -5 z").expect("after z");
        assert_eq!(after_z.len(), 2);
        assert_eq!(after_z[1].segments[0].start(), v(0.0, 0.0));
        // Ending at the start without Z closes the subpath too.
        assert_eq!(
            parse_path("M0 0 L10 0 L10 10 L0 0").expect("closed").len(),
            1
        );
        assert_eq!(
            parse_path("m0 0 l.1 0 l0 .2 l-.1 -.2")
                .expect("closed")
                .len(),
            1
        );
    }

    #[test]
    fn square_with_square_hole() {
        let shape = build_shape(&ShapeSource::SvgPath {
            d: "M0 0 H100 V100 H0 Z M25 25 H75 V75 H25 Z".into(),
            height: Some(50.0),
            origin: v(5.0, 7.0),
        })
        .expect("shape");
        assert_eq!(shape.regions.len(), 1);
        let r = &shape.regions[0];
        assert_eq!(r.name, "path");
        assert!((r.outline.signed_area() - 2500.0).abs() < 1e-9);
        assert_eq!(r.counters.len(), 1);
        assert!((r.counters[0].signed_area() + 625.0).abs() < 1e-9);
        let (lo, hi) = shape.bbox().expect("bbox");
        assert!(lo.dist(v(5.0, 7.0)) < 1e-12 && hi.dist(v(55.0, 57.0)) < 1e-12);
    }

    #[test]
    fn y_is_flipped_and_height_uses_the_curve() {
        // A triangle with its apex at the bottom of the SVG picture (y = 10).
        let shape = svg_shape("M0 0 L10 0 L5 10 Z", None, Vec2::ZERO).expect("tri");
        let r = &shape.regions[0];
        assert!(r.outline.is_ccw());
        let apex = r
            .outline
            .segments
            .iter()
            .map(Segment::start)
            .find(|p| (p.x - 5.0).abs() < 1e-12)
            .expect("apex");
        assert_eq!(apex.y, 0.0);
        assert_eq!(shape.bbox().expect("bbox").1.y, 10.0);
        // A cubic bump: control points reach y = −20, the curve only −15.
        let bump = svg_shape("M0 0 C0 -20 10 -20 10 0 Z", Some(30.0), v(1.0, 2.0)).expect("bump");
        let (lo, hi) = bump.tight_bbox().expect("bbox");
        assert!((hi.y - lo.y - 30.0).abs() < 1e-12, "{}", hi.y - lo.y);
        assert!(lo.dist(v(1.0, 2.0)) < 1e-12);
        assert!((hi.x - lo.x - 20.0).abs() < 1e-12);
    }

    #[test]
    fn arcs_are_refused_with_the_position() {
        let e = parse_path("M0 0 L10 0 A5 5 0 0 1 0 0 Z").expect_err("arc");
        assert_eq!(
            e.to_string(),
            "SVG path data: elliptical arcs are not supported yet, at character 11"
        );
        let e = parse_path("M0 0 a5 5 0 0 1 0 0").expect_err("arc");
        assert!(e.to_string().contains("at character 5"), "{e}");
    }

    #[test]
    fn open_subpaths_are_named() {
        let (at, msg) = svg_err("M0 0 L10 0 L10 10 M 20 20 L 30 20 L 30 30 Z");
        assert_eq!(at, 0);
        assert!(msg.contains("subpath 1 is open"), "{msg}");
        assert!(
            msg.contains("starts at (0, 0) but ends at (10, 10)"),
            "{msg}"
        );
        let (at, msg) = svg_err("M0 0 H10 V10 Z M 20 20 L 30 20 L 30 30");
        assert_eq!(at, 15);
        assert!(msg.contains("subpath 2 is open"), "{msg}");
    }

    #[test]
    fn malformed_data_errors() {
        let cases: [(&str, usize, &str); 10] = [
            (
                "M0 0 L10 x",
                9,
                "expected a number (y of the end point) for `L`, found 'x'",
            ),
            (
                "M0 0 L10",
                8,
                "expected a number (y of the end point) for `L`, found the end",
            ),
            ("L0 0", 0, "must start with a moveto"),
            ("10 10", 0, "must start with a moveto"),
            ("M0 0 X 1", 5, "unknown path command `X`"),
            ("M0 0 L1 1e+ Z", 11, "digits of an exponent"),
            ("M0 0 L1 1 Z 5", 12, "expected a command after `Z`"),
            ("M0 0 L1 1 # Z", 10, "unexpected character '#'"),
            ("M0 0 C1 1 2 2 3", 15, "y of the end point"),
            ("M0 0 L- 3", 6, "expected a number"),
        ];
        for (d, at, want) in cases {
            let (got_at, msg) = svg_err(d);
            assert_eq!(got_at, at, "{d}: {msg}");
            assert!(msg.contains(want), "{d}: {msg}");
        }
        assert!(svg_err("").1.contains("empty"));
        assert!(svg_err("  ,").1.contains("empty"));
        assert!(svg_err("M0 0 L1e999 0 z").1.contains("out of range"));
        // Nothing enclosed, or no height to scale.
        let flat = svg_shape("M0 0 H10 Z", Some(5.0), Vec2::ZERO).expect_err("flat");
        assert!(flat.to_string().contains("encloses any area"), "{flat}");
        let line = svg_shape("M0 0 L10 10 Z", None, Vec2::ZERO).expect_err("line");
        assert!(line.to_string().contains("encloses"), "{line}");
        assert!(svg_shape("M0 0", None, Vec2::ZERO).is_err());
    }

    /// Found by tests/inputs.rs: a subpath drawn forth and back along a line
    /// encloses nothing and is dropped, but it stretched the box that the height
    /// and origin apply to (the square was placed at x = 7, not 5, and scaled
    /// to 2/3 of the height asked for).
    #[test]
    fn a_subpath_without_area_does_not_stretch_the_box() {
        let d = "M0 0 H20 0 0 1 10 5 Z M2 1 h3 v2 h-3 z";
        let shape = svg_shape(d, Some(10.0), Vec2::new(5.0, -5.0)).expect("shape");
        let (lo, hi) = shape.bbox().expect("box");
        assert!((lo - Vec2::new(5.0, -5.0)).norm() < 1e-12, "{lo:?}");
        assert!((hi - Vec2::new(20.0, 5.0)).norm() < 1e-12, "{hi:?}");
        let e = svg_shape("M0 0 H20 0 Z M1 1 L3 3 Z", Some(10.0), Vec2::ZERO).unwrap_err();
        assert!(e.to_string().contains("encloses any area"), "{e}");
    }

    #[test]
    fn random_data_never_panics() {
        // Fixed-seed LCG. Inputs are random commands with (mostly) the right number
        // of random numbers, mutated now and then by junk characters (one of them
        // multi-byte): every input must give Ok or a positioned error.
        let mut seed = 3u64;
        let mut next = |n: usize| {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((seed >> 33) as usize) % n
        };
        let commands = [
            "L", "l", "H", "h", "V", "v", "C", "c", "S", "s", "Q", "q", "T", "t", "Z", "z", "M",
            "m", "A",
        ];
        let arity = [2, 2, 1, 1, 1, 1, 6, 6, 4, 4, 4, 4, 2, 2, 0, 0, 2, 2, 7];
        let junk = [",", " ", ".", "-", "e", "x", "€", "1e", "+.", "\t"];
        let d_of = |next: &mut dyn FnMut(usize) -> usize| {
            let mut d = String::from("M1 2");
            for _ in 0..next(8) {
                let k = next(commands.len());
                d.push_str(commands[k]);
                let n = if next(10) == 0 { next(8) } else { arity[k] };
                for _ in 0..n {
                    let x = next(2001) as f64 / 100.0 - 10.0;
                    d.push_str(&format!("{}{x}", [" ", ",", ""][next(3)]));
                }
            }
            if next(3) > 0 {
                d.push('z');
            }
            if next(8) == 0 {
                let at = next(d.len() + 1);
                if d.is_char_boundary(at) {
                    d.insert_str(at, junk[next(junk.len())]);
                }
            }
            d
        };
        let (mut ok, mut bad) = (0, 0);
        for _ in 0..20_000 {
            let d = d_of(&mut next);
            match svg_shape(&d, Some(10.0), Vec2::ZERO) {
                Ok(shape) => {
                    ok += 1;
                    assert!(shape.regions.iter().all(|r| r.outline.is_ccw()));
                }
                Err(GeometryError::Svg { offset, .. }) => {
                    bad += 1;
                    assert!(offset <= d.chars().count(), "{d:?}: offset {offset}");
                }
                Err(e) => panic!("{d:?}: unexpected error kind {e:?}"),
            }
        }
        assert!(bad > 0);
        // Some random inputs are valid paths that enclose area.
        assert!(ok > 0, "no valid input among {bad} errors");
    }
}
