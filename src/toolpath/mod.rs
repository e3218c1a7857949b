//! Tool paths: the one intermediate representation that G-code, previews, time
//! estimates and the gouge check all read (see `docs/architecture.md`).

pub(crate) mod air;
pub mod arcfit;
pub(crate) mod band;
pub(crate) mod bays;
pub(crate) mod clearing;
pub mod dropcutter;
pub(crate) mod entry;
pub(crate) mod farthest;
pub mod gouge;
pub(crate) mod inverse;
pub mod profile;
pub(crate) mod runs;
pub(crate) mod spot;
pub(crate) mod stock;
pub(crate) mod trace;
pub(crate) mod zlevel;

/// How a finishing program's sections are labelled (`finish pass k s X`):
/// the writer's header counts them as passes along the surface, not as
/// z-levels.
pub(crate) const FINISH_PASS: &str = "finish pass";

/// The label's end of a finishing pass of a raster (parallel passes along
/// x, `patch::raster`) rather than along the surface's level curves.
pub(crate) const RASTER_PASS: &str = "along x";

/// A point in machine coordinates, millimetres.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Vec3 {
    /// X
    pub x: f64,
    /// Y
    pub y: f64,
    /// Z
    pub z: f64,
}

impl Vec3 {
    /// A new point.
    pub const fn new(x: f64, y: f64, z: f64) -> Self {
        Vec3 { x, y, z }
    }
    /// Distance to another point.
    pub(crate) fn dist(self, o: Vec3) -> f64 {
        ((self.x - o.x).powi(2) + (self.y - o.y).powi(2) + (self.z - o.z).powi(2)).sqrt()
    }
    /// The point's X and Y.
    pub(crate) fn xy(self) -> crate::geometry::Vec2 {
        crate::geometry::Vec2::new(self.x, self.y)
    }
}

/// One move of the tool centre. Every move starts where the previous one ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Move {
    /// Rapid (G0) to `to`.
    Rapid {
        /// end point
        to: Vec3,
    },
    /// Straight feed move (G1) to `to` at `feed` mm/min.
    Linear {
        /// end point
        to: Vec3,
        /// feed rate, mm/min
        feed: f64,
    },
    /// Circular feed move in the XY plane (G2 clockwise, G3 counter-clockwise) to
    /// `to`, about the absolute centre (`cx`, `cy`), with a linear change of Z.
    Arc {
        /// end point
        to: Vec3,
        /// centre X, absolute
        cx: f64,
        /// centre Y, absolute
        cy: f64,
        /// true for counter-clockwise (G3)
        ccw: bool,
        /// feed rate, mm/min
        feed: f64,
    },
}

impl Move {
    /// End point of the move.
    pub fn to(&self) -> Vec3 {
        match *self {
            Move::Rapid { to } | Move::Linear { to, .. } | Move::Arc { to, .. } => to,
        }
    }

    /// The feed rate, mm/min; `None` for a rapid.
    pub(crate) fn feed(&self) -> Option<f64> {
        match *self {
            Move::Rapid { .. } => None,
            Move::Linear { feed, .. } | Move::Arc { feed, .. } => Some(feed),
        }
    }

    /// Length of the move from `from`, mm: straight for a rapid or a line,
    /// the helix for an arc ([`crate::geometry::arc::length`]).
    pub(crate) fn length(&self, from: Vec3) -> f64 {
        match *self {
            Move::Rapid { to } | Move::Linear { to, .. } => from.dist(to),
            Move::Arc {
                to, cx, cy, ccw, ..
            } => crate::geometry::arc::length(
                from.xy(),
                to.xy(),
                crate::geometry::Vec2::new(cx, cy),
                ccw,
                to.z - from.z,
            ),
        }
    }
}

/// A labelled run of moves (one pass of one contour at one depth, or a link).
#[derive(Clone, Debug, PartialEq)]
pub struct Section {
    /// What this is, for G-code comments and reports, e.g. `outside M (1), z -1.000`.
    pub label: String,
    /// The cutting depth of this section (mm).
    pub z: f64,
    /// The moves.
    pub moves: Vec<Move>,
}

/// A whole tool path in machine coordinates.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Toolpath {
    /// Where the tool is when the program starts (XY at the origin, Z at safe height).
    pub start: Vec3,
    /// The sections, in cutting order.
    pub sections: Vec<Section>,
}

/// Lengths and time of a tool path.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub(crate) struct PathStats {
    /// Length of feed moves, mm.
    pub(crate) cut_length: f64,
    /// Length of rapid moves, mm.
    pub(crate) rapid_length: f64,
    /// Estimated time in seconds: feed moves at their feed, rapids at the given
    /// rapid rate, acceleration ignored.
    pub(crate) time_s: f64,
}

impl Toolpath {
    /// Every move in order.
    pub fn moves(&self) -> impl Iterator<Item = &Move> {
        self.sections.iter().flat_map(|s| s.moves.iter())
    }

    /// Every feed move in order, with where it starts (rapids skipped).
    pub(crate) fn feed_moves(&self) -> impl Iterator<Item = (Vec3, Move)> + '_ {
        self.moves()
            .scan(self.start, |at, m| {
                let from = std::mem::replace(at, m.to());
                Some((from, *m))
            })
            .filter(|(_, m)| !matches!(m, Move::Rapid { .. }))
    }

    /// Lengths and estimated time, with rapids at `rapid_rate` mm/min.
    pub(crate) fn stats(&self, rapid_rate: f64) -> PathStats {
        let mut st = PathStats::default();
        let mut at = self.start;
        for m in self.moves() {
            if m.feed().is_none() {
                let l = m.length(at);
                st.rapid_length += l;
                st.time_s += l / rapid_rate * 60.0;
            } else {
                let (l, t) = feed_length_time(at, m);
                st.cut_length += l;
                st.time_s += t;
            }
            at = m.to();
        }
        st
    }
}

/// Length (mm) and time (s) of a feed move from `from`; (0, 0) for a rapid.
pub(crate) fn feed_length_time(from: Vec3, m: &Move) -> (f64, f64) {
    match m.feed() {
        None => (0.0, 0.0),
        Some(feed) => {
            let l = m.length(from);
            (l, l / feed * 60.0)
        }
    }
}

/// Points along the (helical) arc from `a` (excluded) to `b` (included,
/// exactly) about (`cx`, `cy`): equal chords within `tol` of it in XY
/// ([`crate::geometry::arc::chords`]), z linear in the angle.
pub(crate) fn arc_flatten(a: Vec3, b: Vec3, cx: f64, cy: f64, ccw: bool, tol: f64) -> Vec<Vec3> {
    use crate::geometry::arc;
    let c = crate::geometry::Vec2::new(cx, cy);
    let n = arc::chords(
        arc::radius(a.xy(), c),
        arc::sweep(a.xy(), b.xy(), c, ccw),
        tol,
    );
    arc_points(a, b, cx, cy, ccw, n)
}

/// The ends of `n` equal pieces of the (helical) arc from `a` to `b` about
/// (`cx`, `cy`): [`crate::geometry::arc::divide`] in XY, z linear in the
/// angle; the last exactly `b`.
pub(crate) fn arc_points(a: Vec3, b: Vec3, cx: f64, cy: f64, ccw: bool, n: usize) -> Vec<Vec3> {
    let c = crate::geometry::Vec2::new(cx, cy);
    let pts = crate::geometry::arc::divide(a.xy(), b.xy(), c, ccw, n);
    pts.into_iter()
        .enumerate()
        .map(|(k, p)| {
            if k + 1 == n {
                b
            } else {
                let f = (k + 1) as f64 / n as f64;
                Vec3::new(p.x, p.y, a.z + (b.z - a.z) * f)
            }
        })
        .collect()
}
