//! SVG path data (the `d` attribute), read by svgtypes (the parser usvg and
//! resvg use): `M L H V C S Q T A Z`, absolute (upper case) and relative
//! (lower case), implicit repetition, smooth reflections, compact numbers and
//! elliptical arcs. Arcs become cubic Béziers within [`ARC_TOL`] of their
//! radius (kurbo's conversion).
//!
//! Every subpath must be closed: by `Z`, or by ending where it started. A
//! subpath that crosses itself (a bow-tie) is replaced by the outline of what it
//! fills under SVG's default rule, `nonzero` (`fill.rs`), flattened within
//! [`UNTANGLE_TOL`] of its size. The result is flipped (SVG y points down,
//! machine y up), scaled so that the tight bounding box is `height` mm high when
//! a height is given (else 1 unit = 1 mm), moved so the box's bottom-left corner
//! is at `origin`, then nested into outlines and counters by
//! [`regions_from_contours`].

use svgtypes::{PathParser, PathSegment};

use super::fill::{crosses, fill_outlines, FillRule};
use super::{regions_from_contours, Contour, GeometryError, Segment, Shape, Vec2};

/// A subpath whose end is within this distance (relative to the size of the path's
/// control-point box, at least 1 unit) of its start counts as closed; the gap is then
/// snapped shut. Relative coordinates summed in floating point leave ~1e-15.
const CLOSE_EPS: f64 = 1e-9;

/// An elliptical arc becomes cubics within this fraction of its larger radius
/// (kurbo's estimate; about 15 cubics a full turn).
pub(crate) const ARC_TOL: f64 = 1e-7;

/// A subpath that crosses itself is flattened within this fraction of its
/// bounding box's diagonal before it is split into loops.
pub(crate) const UNTANGLE_TOL: f64 = 1e-5;

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
    let contours = path_contours(d)?;
    // Flip y, nest, then scale and place by the tight box of the regions (the
    // contours that enclose no area, or that nesting leaves out, are no part of
    // the shape: a line drawn forth and back would otherwise stretch the box
    // the height and origin apply to).
    let flipped: Vec<Contour> = contours
        .iter()
        .map(|c| c.map(|p| Vec2::new(p.x, -p.y)))
        .filter(crate::geometry::nesting::encloses_area)
        .collect();
    if flipped.is_empty() && !contours.is_empty() {
        return Err(err(0, NO_AREA));
    }
    if flipped.is_empty() {
        return Err(err(
            0,
            "the path data draws nothing; expected at least one closed subpath",
        ));
    }
    let shape = Shape {
        regions: regions_from_contours("path", flipped),
    };
    let Some((lo, hi)) = shape.tight_bbox() else {
        return Err(err(0, NO_AREA));
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
    Ok(shape.map(|p| origin + (p - lo) * scale))
}

/// The closed contours of `d` in SVG coordinates (y down), a subpath that crosses
/// itself split into the loops it fills (nonzero).
pub(crate) fn path_contours(d: &str) -> Result<Vec<Contour>, GeometryError> {
    let mut out = Vec::new();
    for (k, c) in parse_path(d)?.into_iter().enumerate() {
        let loops = untangle(c).map_err(|_| {
            err(
                0,
                format!(
                    "subpath {} crosses itself too often to be split into loops",
                    k + 1
                ),
            )
        })?;
        out.extend(loops);
    }
    Ok(out)
}

/// `c` as it is when it does not cross itself, else the loops it fills under
/// the nonzero rule (flattened within [`UNTANGLE_TOL`] of its size).
fn untangle(c: Contour) -> Result<Vec<Contour>, super::arrangement::TooComplex> {
    let diag = c.bbox().map_or(0.0, |(lo, hi)| (hi - lo).norm());
    if !(diag > 0.0 && diag.is_finite()) {
        return Ok(vec![c]);
    }
    let flat = c.flatten(UNTANGLE_TOL * diag);
    let one = std::slice::from_ref(&flat);
    if !crosses(one)? {
        return Ok(vec![c]);
    }
    Ok(fill_outlines(one, FillRule::NonZero)?
        .iter()
        .filter_map(|l| Contour::polygon(l).ok())
        .collect())
}

/// Parses `d` into closed contours, in SVG coordinates (y down), one per subpath
/// that draws something.
pub(crate) fn parse_path(d: &str) -> Result<Vec<Contour>, GeometryError> {
    if d.chars().all(|c| c.is_ascii_whitespace() || c == ',') {
        return Err(err(
            0,
            "the path data is empty; expected a moveto (`M` or `m`)",
        ));
    }
    let marks = Marks::of(d);
    let mut b = PathBuilder::default();
    for seg in PathParser::from(d) {
        let seg = seg.map_err(|e| parse_error(d, e))?;
        b.segment(seg, &marks)
            .map_err(|e| finite_error(d).unwrap_or(e))?;
    }
    b.end_subpath(None)?;
    Ok(b.contours)
}

/// Where subpaths begin, in characters from 0: each `M`/`m`, and the command
/// after each `Z`/`z` (a subpath drawn on from a closed one's start).
#[derive(Default)]
struct Marks {
    moves: Vec<usize>,
    after_close: Vec<usize>,
}

impl Marks {
    fn of(d: &str) -> Marks {
        let mut m = Marks::default();
        let mut after_z = false;
        for (i, c) in d.chars().enumerate() {
            if !"MmZzLlHhVvCcSsQqTtAa".contains(c) {
                continue;
            }
            if after_z {
                m.after_close.push(i);
                after_z = false;
            }
            match c {
                'M' | 'm' => m.moves.push(i),
                'Z' | 'z' => after_z = true,
                _ => {}
            }
        }
        m
    }
}

/// An svgtypes error in pfcam's words, at a character offset from 0.
fn parse_error(d: &str, e: svgtypes::Error) -> GeometryError {
    let chars: Vec<char> = d.chars().collect();
    let found = |at: usize| {
        let word: String = chars[at.min(chars.len())..]
            .iter()
            .take_while(|c| !c.is_ascii_whitespace() && **c != ',')
            .take(8)
            .collect();
        match word.chars().next() {
            None if at >= chars.len() => "found the end of the data".to_string(),
            None => format!("found {:?}", chars[at]),
            Some(c) if c.is_ascii_digit() || ".+-".contains(c) => format!("found {word:?}"),
            Some(c) => format!("found {c:?}"),
        }
    };
    // The command in force: the last command letter before `at`, and where.
    let command = |at: usize| {
        chars[..at.min(chars.len())]
            .iter()
            .enumerate()
            .rev()
            .find(|(_, c)| "MmZzLlHhVvCcSsQqTtAa".contains(**c))
            .map(|(i, c)| (i, *c))
    };
    // `for `L``, with the argument's number when the command has several.
    let wanted = |at: usize| match command(at) {
        Some((i, c)) if arity(c) > 1 => {
            let before = number_tokens(&chars[i..at.min(chars.len())]).len();
            format!(
                " (argument {} of {}) for `{c}`",
                before % arity(c) + 1,
                arity(c)
            )
        }
        Some((_, c)) => format!(" for `{c}`"),
        None => String::new(),
    };
    match e {
        svgtypes::Error::UnexpectedData(pos) => {
            let at = pos.saturating_sub(1);
            let c = chars.get(at).copied().unwrap_or(' ');
            let message = match command(at).map(|(_, c)| c) {
                None if c.is_ascii_alphabetic() => {
                    format!("path data must start with a moveto (`M` or `m`), found `{c}`")
                }
                None => "path data must start with a moveto (`M` or `m`), found a number".into(),
                Some('Z' | 'z') if c.is_ascii_digit() || ".-+".contains(c) => {
                    "expected a command after `Z`, found a number".into()
                }
                Some('A' | 'a') if c.is_ascii_digit() => {
                    format!("expected an arc flag (0 or 1) for `A`, {}", found(at))
                }
                _ if c.is_ascii_alphabetic() => format!(
                    "unknown path command `{c}`; expected one of M L H V C S Q T A Z (or lower case)"
                ),
                _ => format!("unexpected character {c:?}; expected a path command or a number"),
            };
            err(at, message)
        }
        svgtypes::Error::InvalidNumber(pos) => {
            let at = pos.saturating_sub(1);
            match finite_error(d) {
                Some(e @ GeometryError::Svg { offset, .. }) if offset == at => e,
                _ => err(
                    at,
                    format!("expected a number{}, {}", wanted(at), found(at)),
                ),
            }
        }
        svgtypes::Error::UnexpectedEndOfStream => err(
            chars.len(),
            format!(
                "expected a number{}, found the end of the data",
                wanted(chars.len())
            ),
        ),
        other => err(0, other.to_string()),
    }
}

/// The first number in `d` too large for a double (`1e999`), as an error at
/// its place.
fn finite_error(d: &str) -> Option<GeometryError> {
    let chars: Vec<char> = d.chars().collect();
    number_tokens(&chars).into_iter().find_map(|(start, end)| {
        let text: String = chars[start..end].iter().collect();
        text.parse::<f64>()
            .is_ok_and(f64::is_infinite)
            .then(|| err(start, format!("the number {text} is out of range")))
    })
}

/// Where the numbers of path data are, as character ranges: sign, digits,
/// fraction, exponent (the compact forms `1.5.5` and `10-5` are two each).
fn number_tokens(chars: &[char]) -> Vec<(usize, usize)> {
    let digits = |j: &mut usize| {
        let s = *j;
        while *j < chars.len() && chars[*j].is_ascii_digit() {
            *j += 1;
        }
        *j - s
    };
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let mut j = i;
        if matches!(chars[j], '+' | '-') {
            j += 1;
        }
        let mut n = digits(&mut j);
        if j < chars.len() && chars[j] == '.' {
            j += 1;
            n += digits(&mut j);
        }
        if n == 0 {
            i += 1;
            continue;
        }
        if j < chars.len() && matches!(chars[j], 'e' | 'E') {
            let mut k = j + 1;
            if k < chars.len() && matches!(chars[k], '+' | '-') {
                k += 1;
            }
            if digits(&mut k) > 0 {
                j = k;
            }
        }
        out.push((i, j));
        i = j;
    }
    out
}

/// How many numbers command letter `c` takes.
fn arity(c: char) -> usize {
    match c.to_ascii_uppercase() {
        'H' | 'V' => 1,
        'M' | 'L' | 'T' => 2,
        'S' | 'Q' => 4,
        'C' => 6,
        'A' => 7,
        _ => 0,
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
    /// Movetos and closepaths seen so far.
    moves: usize,
    closes: usize,
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

    fn segment(&mut self, seg: PathSegment, marks: &Marks) -> Result<(), GeometryError> {
        let base = if seg.is_abs() { Vec2::ZERO } else { self.cur };
        let pt = |x: f64, y: f64| base + Vec2::new(x, y);
        let (mut cubic_ctrl, mut quad_ctrl) = (None, None);
        match seg {
            PathSegment::MoveTo { x, y, .. } => {
                let to = pt(x, y);
                self.end_subpath(None)?;
                self.start = to;
                self.cur = to;
                self.start_at = marks.moves.get(self.moves).copied().unwrap_or(0);
                self.moves += 1;
                self.count += 1;
                self.closed = false;
                self.last_cubic = None;
                self.last_quad = None;
                return finite(to);
            }
            PathSegment::ClosePath { .. } => {
                let at = self.start_at;
                self.end_subpath(Some(at))?;
                self.closed = true;
                self.closes += 1;
                self.last_cubic = None;
                self.last_quad = None;
                return Ok(());
            }
            _ => {}
        }
        // Drawing after `Z` without an `M` starts a new subpath at the old start.
        if self.closed {
            self.closed = false;
            self.start_at = marks.after_close.get(self.closes - 1).copied().unwrap_or(0);
            self.count += 1;
        }
        let from = self.cur;
        match seg {
            PathSegment::LineTo { x, y, .. } => self.push(Segment::Line {
                a: from,
                b: pt(x, y),
            }),
            PathSegment::HorizontalLineTo { x, .. } => self.push(Segment::Line {
                a: from,
                b: Vec2::new(base.x + x, from.y),
            }),
            PathSegment::VerticalLineTo { y, .. } => self.push(Segment::Line {
                a: from,
                b: Vec2::new(from.x, base.y + y),
            }),
            PathSegment::CurveTo {
                x1,
                y1,
                x2,
                y2,
                x,
                y,
                ..
            } => {
                let p2 = pt(x2, y2);
                self.push(Segment::Cubic {
                    p0: from,
                    p1: pt(x1, y1),
                    p2,
                    p3: pt(x, y),
                });
                cubic_ctrl = Some(p2);
            }
            PathSegment::SmoothCurveTo { x2, y2, x, y, .. } => {
                let p1 = self.last_cubic.map_or(from, |q| from * 2.0 - q);
                let p2 = pt(x2, y2);
                self.push(Segment::Cubic {
                    p0: from,
                    p1,
                    p2,
                    p3: pt(x, y),
                });
                cubic_ctrl = Some(p2);
            }
            PathSegment::Quadratic { x1, y1, x, y, .. } => {
                let q = pt(x1, y1);
                self.push(Segment::quad(from, q, pt(x, y)));
                quad_ctrl = Some(q);
            }
            PathSegment::SmoothQuadratic { x, y, .. } => {
                let q = self.last_quad.map_or(from, |q| from * 2.0 - q);
                self.push(Segment::quad(from, q, pt(x, y)));
                quad_ctrl = Some(q);
            }
            PathSegment::EllipticalArc {
                rx,
                ry,
                x_axis_rotation,
                large_arc,
                sweep,
                x,
                y,
                ..
            } => {
                let to = pt(x, y);
                finite(to)?;
                for s in arc_segments(from, to, rx, ry, x_axis_rotation, large_arc, sweep) {
                    self.push(s);
                }
            }
            PathSegment::MoveTo { .. } | PathSegment::ClosePath { .. } => {}
        }
        self.last_cubic = cubic_ctrl;
        self.last_quad = quad_ctrl;
        finite(self.cur)
    }
}

/// An error when `p` is not finite (a number past the range of a double, or a
/// sum of huge relative steps).
fn finite(p: Vec2) -> Result<(), GeometryError> {
    if p.is_finite() {
        Ok(())
    } else {
        Err(err(0, "a coordinate is out of range"))
    }
}

/// The SVG arc from `from` to `to` as cubics (kurbo's conversion, within
/// [`ARC_TOL`] of the larger radius), ending exactly at `to`. Zero radii give
/// the straight line, as SVG says; equal ends give nothing.
fn arc_segments(
    from: Vec2,
    to: Vec2,
    rx: f64,
    ry: f64,
    rotation_deg: f64,
    large_arc: bool,
    sweep: bool,
) -> Vec<Segment> {
    let kp = |p: Vec2| kurbo::Point::new(p.x, p.y);
    let vp = |p: kurbo::Point| Vec2::new(p.x, p.y);
    let svg_arc = kurbo::SvgArc {
        from: kp(from),
        to: kp(to),
        radii: kurbo::Vec2::new(rx.abs(), ry.abs()),
        x_rotation: rotation_deg.to_radians(),
        large_arc,
        sweep,
    };
    if from == to {
        return Vec::new();
    }
    let Some(arc) = kurbo::Arc::from_svg_arc(&svg_arc) else {
        return vec![Segment::Line { a: from, b: to }];
    };
    let tol = ARC_TOL * arc.radii.x.max(arc.radii.y);
    let mut out = Vec::new();
    let mut p0 = from;
    arc.to_cubic_beziers(tol, |p1, p2, p3| {
        let p3 = vp(p3);
        out.push(Segment::Cubic {
            p0,
            p1: vp(p1),
            p2: vp(p2),
            p3,
        });
        p0 = p3;
    });
    if let Some(Segment::Cubic { p3, .. }) = out.last_mut() {
        *p3 = to;
    }
    out
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

    /// The area of a contour's flattening within `tol`.
    fn flat_area(c: &Contour, tol: f64) -> f64 {
        let p = c.flatten(tol);
        let n = p.len();
        (0..n).map(|i| p[i].cross(p[(i + 1) % n])).sum::<f64>() / 2.0
    }

    #[test]
    fn arcs_make_circles_ellipses_and_rounded_corners() {
        use std::f64::consts::PI;
        // A circle of radius 10 from two half-turn arcs, absolute and relative.
        let abs = parse_path("M-10 0 A10 10 0 0 1 10 0 A10 10 0 0 1 -10 0 Z").expect("abs");
        let rel = parse_path("m-10 0 a10 10 0 0 1 20 0 a10 10 0 0 1 -20 0 z").expect("rel");
        same(&abs, &rel);
        let c = &abs[0];
        // Every point of every cubic lies on the circle within ARC_TOL · r.
        let worst = c
            .segments
            .iter()
            .flat_map(|s| (0..=50).map(move |k| s.eval(k as f64 / 50.0)))
            .map(|p| (p.norm() - 10.0).abs())
            .fold(0.0, f64::max);
        assert!(worst < 10.0 * ARC_TOL, "radial error {worst}");
        assert!(
            (c.signed_area().abs() - 100.0 * PI).abs() < 1e-4,
            "{}",
            c.signed_area()
        );
        // The sweep flag picks the side: sweep 1 in SVG's y-down space is
        // clockwise on screen, so the upper half (y < 0) is drawn first.
        let mid = c.segments[0].eval(1.0);
        assert!(mid.y < 0.0 || c.segments.len() > 1, "{mid:?}");
        // An ellipse (radii 20, 10) turned 30°: area π·20·10.
        let e = parse_path(
            "M17.320508075688775 10 A20 10 30 0 1 -17.320508075688775 -10 \
             A20 10 30 0 1 17.320508075688775 10 Z",
        )
        .expect("ellipse");
        assert!(
            (e[0].signed_area().abs() - 200.0 * PI).abs() < 1e-3,
            "{}",
            e[0].signed_area()
        );
        // A rounded rectangle 40 × 30 with corner radius 5: 40·30 − (4 − π)·25.
        let r = parse_path(
            "M5 0 H35 A5 5 0 0 1 40 5 V25 A5 5 0 0 1 35 30 H5 A5 5 0 0 1 0 25 V5 A5 5 0 0 1 5 0 Z",
        )
        .expect("rounded");
        let want = 1200.0 - (4.0 - PI) * 25.0;
        assert!(
            (r[0].signed_area().abs() - want).abs() < 1e-5,
            "{}",
            r[0].signed_area()
        );
        // Flags: the large arc of radius 10 between points 10 apart is the
        // larger part of the circle.
        let small = parse_path("M0 0 A10 10 0 0 1 10 0 Z").expect("small");
        let large = parse_path("M0 0 A10 10 0 1 1 10 0 Z").expect("large");
        let (a_small, a_large) = (small[0].signed_area().abs(), large[0].signed_area().abs());
        assert!(
            (a_small + a_large - 100.0 * PI).abs() < 1e-4,
            "{a_small} + {a_large}"
        );
        assert!(a_large > 30.0 * a_small);
        // Flags may be written together.
        same(
            &parse_path("M0 0 a5 5 0 01 10 0 z").expect("packed"),
            &parse_path("M0 0 a5 5 0 0 1 10 0 z").expect("spaced"),
        );
        // Radii too small to reach are scaled up (SVG's rule): a half circle.
        let half = parse_path("M0 0 A1 1 0 0 1 10 0 Z").expect("half");
        assert!((half[0].signed_area().abs() - 12.5 * PI).abs() < 1e-4);
        // Zero radii draw a straight line; a flat result encloses nothing.
        let line = svg_shape("M0 0 A0 5 0 0 1 10 0 L10 10 Z", None, Vec2::ZERO).expect("line");
        assert!((flat_area(&line.regions[0].outline, 1e-3) - 50.0).abs() < 1e-9);
    }

    #[test]
    fn a_bow_tie_is_split_into_its_two_triangles() {
        let shape = svg_shape("M0 0 L20 20 L20 0 L0 20 Z", None, Vec2::ZERO).expect("bow-tie");
        assert_eq!(shape.regions.len(), 2);
        for r in &shape.regions {
            assert!(r.outline.is_ccw());
            assert!(
                (r.outline.signed_area() - 100.0).abs() < 1e-6,
                "{}",
                r.outline.signed_area()
            );
            assert!(r.counters.is_empty());
        }
        // A curved figure eight crosses itself where two cubics meet: two
        // lobes, one drawn each way, both filled (nonzero), area kept within
        // the flattening's bound (perimeter × UNTANGLE_TOL × diagonal).
        let d =
            "M0 0 C10 10 20 10 20 0 C20 -10 10 -10 0 0 C-10 10 -20 10 -20 0 C-20 -10 -10 -10 0 0 Z";
        let whole = parse_path(d).expect("eight");
        let lobe = Contour::new(whole[0].segments[..2].to_vec()).expect("lobe");
        let eight = svg_shape(d, None, Vec2::ZERO).expect("eight");
        assert_eq!(eight.regions.len(), 2);
        for r in &eight.regions {
            let a = r.outline.signed_area();
            assert!(
                (a - lobe.signed_area().abs()).abs() < 0.05,
                "{a} vs {}",
                lobe.signed_area()
            );
        }
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
        let cases: [(&str, usize, &str); 11] = [
            (
                "M0 0 L10 x",
                9,
                "expected a number (argument 2 of 2) for `L`, found 'x'",
            ),
            (
                "M0 0 L10",
                8,
                "expected a number (argument 2 of 2) for `L`, found the end",
            ),
            ("L0 0", 0, "must start with a moveto"),
            ("10 10", 0, "must start with a moveto"),
            ("M0 0 X 1", 5, "unknown path command `X`"),
            (
                "M0 0 L1 1e+ Z",
                8,
                "expected a number (argument 2 of 2) for `L`, found \"1e+\"",
            ),
            ("M0 0 L1 1 Z 5", 12, "expected a command after `Z`"),
            ("M0 0 L1 1 # Z", 10, "unexpected character '#'"),
            ("M0 0 C1 1 2 2 3", 15, "(argument 6 of 6) for `C`"),
            ("M0 0 L- 3", 6, "expected a number"),
            (
                "M0 0 A5 5 0 2 1 10 0 Z",
                12,
                "expected an arc flag (0 or 1) for `A`",
            ),
        ];
        for (d, at, want) in cases {
            let (got_at, msg) = svg_err(d);
            assert_eq!(got_at, at, "{d}: {msg}");
            assert!(msg.contains(want), "{d}: {msg}");
        }
        assert!(svg_err("").1.contains("empty"));
        assert!(svg_err("  ,").1.contains("empty"));
        let huge = svg_err("M0 0 L1e999 0 z");
        assert!(huge.1.contains("out of range") && huge.0 == 6, "{huge:?}");
        // Nothing enclosed, or no height to scale.
        let flat = svg_shape("M0 0 H10 Z", Some(5.0), Vec2::ZERO).expect_err("flat");
        assert!(flat.to_string().contains("encloses any area"), "{flat}");
        let line = svg_shape("M0 0 L10 10 Z", None, Vec2::ZERO).expect_err("line");
        assert!(line.to_string().contains("encloses"), "{line}");
        assert!(svg_shape("M0 0", None, Vec2::ZERO).is_err());
    }

    /// Found by tests/all/inputs.rs: a subpath drawn forth and back along a line
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
        let mut g = crate::num::testing::Lcg(3u64);
        let mut next = |n: usize| g.below(n);
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
