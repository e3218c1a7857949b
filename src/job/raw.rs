//! The job file as written ([`RawJob`]): every table and key optional,
//! unknown keys rejected, nothing checked. `RawJob::resolve` (in `resolve.rs`)
//! turns it into a [`Job`](super::Job); `[machine]` is in `machine.rs`,
//! `[finish]` in `finish.rs`.

use super::machine::RawMachine;
use super::{exact, finish};
use serde::Deserialize;

/// The job file as written: every key optional, unknown keys rejected.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawJob {
    /// `[job]`
    pub job: Option<RawJobTable>,
    /// `[shape]`
    pub shape: Option<RawShape>,
    /// `[tool]`
    pub tool: Option<RawTool>,
    /// `[stock]`
    pub stock: Option<RawStock>,
    /// `[operation]`
    pub operation: Option<RawOperation>,
    /// `[field]`
    pub field: Option<RawField>,
    /// `[machine]`
    pub machine: Option<RawMachine>,
    /// `[output]`
    pub output: Option<RawOutput>,
    /// `[profile]`
    pub profile: Option<RawProfile>,
    /// `[finish]`
    pub finish: Option<finish::RawFinish>,
}

/// `[profile]`: the depth profile φ(s) of a boss or cavity.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawProfile {
    /// `kind`: linear, sigmoid, power, spline or table
    pub kind: Option<String>,
    /// `s_bottom` (linear)
    pub s_bottom: Option<f64>,
    /// `s1` (sigmoid: top edge)
    pub s1: Option<f64>,
    /// `s2` (sigmoid: foot of the wall)
    pub s2: Option<f64>,
    /// `steepness` (sigmoid)
    pub steepness: Option<f64>,
    /// `exponent` (power)
    pub exponent: Option<f64>,
    /// `points`: [[s, z], ...] (spline, table), z in mm relative to stock.top
    #[serde(default, deserialize_with = "exact::opt_vec")]
    pub points: Option<Vec<[f64; 2]>>,
}

/// `[job]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawJobTable {
    /// `name`
    pub name: Option<String>,
}

/// `[shape]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawShape {
    /// `text`
    pub text: Option<String>,
    /// `lines`: several lines of text, top to bottom
    pub lines: Option<Vec<String>>,
    /// `align`: left, centre (center) or right
    pub align: Option<String>,
    /// `line_spacing`, em
    pub line_spacing: Option<f64>,
    /// `svg_path`
    pub svg_path: Option<String>,
    /// `svg_file`: an SVG document, relative to the job file's directory
    pub svg_file: Option<String>,
    /// `id`: the one element of `svg_file` to use
    pub id: Option<String>,
    /// `scale`: the `svg_file` drawing's size times this
    pub scale: Option<f64>,
    /// `width`, mm: the `svg_file` drawing's width
    pub width: Option<f64>,
    /// `dxf_file`: a DXF drawing, relative to the job file's directory
    pub dxf_file: Option<String>,
    /// `layer`: only this layer of `dxf_file`
    pub layer: Option<String>,
    /// `join_tolerance`, mm: `dxf_file` pieces whose ends are closer join
    pub join_tolerance: Option<f64>,
    /// `font`
    pub font: Option<String>,
    /// `height`, mm
    pub height: Option<f64>,
    /// `letter_spacing`, mm
    pub letter_spacing: Option<f64>,
    /// `origin`, mm
    #[serde(default, deserialize_with = "exact::opt")]
    pub origin: Option<[f64; 2]>,
    /// `result`: the name of the part that is the shape (with `[[shape.part]]`)
    pub result: Option<String>,
    /// `[[shape.part]]`: the parts of a composition
    pub part: Option<Vec<RawPart>>,
    /// `kind`: a surface source, `"harmonic-bezier"`
    pub kind: Option<String>,
    /// `degree` (harmonic patch): n, the degree along the rows
    pub degree: Option<i64>,
    /// `form` (harmonic patch): `"square"` or `"raised"`
    pub form: Option<String>,
    /// `size` (harmonic patch), mm: [X, Y]
    #[serde(default, deserialize_with = "exact::opt")]
    pub size: Option<[f64; 2]>,
    /// `row0` (harmonic patch), mm: heights of the edge y = 0
    pub row0: Option<Vec<f64>>,
    /// `row1` (harmonic patch), mm: heights of the edge y = Y
    pub row1: Option<Vec<f64>>,
    /// `points` (polyharmonic), mm: [[x, y, z], ...] on the surface
    #[serde(default, deserialize_with = "exact::opt_vec")]
    pub points: Option<Vec<[f64; 3]>>,
    /// `inside` (polyharmonic), mm: points inside the solid
    #[serde(default, deserialize_with = "exact::opt_vec")]
    pub inside: Option<Vec<[f64; 3]>>,
    /// `outside` (polyharmonic), mm: points outside the solid (separators)
    #[serde(default, deserialize_with = "exact::opt_vec")]
    pub outside: Option<Vec<[f64; 3]>>,
    /// `points_file` (polyharmonic): a CSV or XYZ file of the points
    pub points_file: Option<String>,
    /// `kernel` (polyharmonic): `"T2A"` or `"T2"`
    pub kernel: Option<String>,
    /// `a`: the T2A kernel's ball radius A, mm (polyharmonic), or the PDE's
    /// parameter (PDE tube)
    pub a: Option<f64>,
    /// `box` (polyharmonic), mm: [[x0, y0, z0], [x1, y1, z1]]
    #[serde(rename = "box", default, deserialize_with = "exact::opt_vec")]
    pub box_: Option<Vec<[f64; 3]>>,
    /// `elements` (polyharmonic): elements per box edge
    pub elements: Option<i64>,
    /// `base` (polyharmonic), mm: the height of the block's foot
    pub base: Option<f64>,
    /// `solid` (polyharmonic): `"relief"` or `"closed"`
    pub solid: Option<String>,
    /// `bottom_size` (PDE tube), mm: [X, Y] of the curve at u = 0
    #[serde(default, deserialize_with = "exact::opt")]
    pub bottom_size: Option<[f64; 2]>,
    /// `bottom_exponent` (PDE tube): the superellipse's p at u = 0
    pub bottom_exponent: Option<f64>,
    /// `top_size` (PDE tube), mm: [X, Y] of the curve at u = 1
    #[serde(default, deserialize_with = "exact::opt")]
    pub top_size: Option<[f64; 2]>,
    /// `top_exponent` (PDE tube): the superellipse's p at u = 1
    pub top_exponent: Option<f64>,
    /// `flare` (PDE tube), mm per unit u: [bottom, top]
    #[serde(default, deserialize_with = "exact::opt")]
    pub flare: Option<[f64; 2]>,
    /// `rise` (PDE tube), mm per unit u: [bottom, top]
    #[serde(default, deserialize_with = "exact::opt")]
    pub rise: Option<[f64; 2]>,
    /// `modes` (PDE tube): N
    pub modes: Option<i64>,
    /// `samples` (PDE tube): K
    pub samples: Option<i64>,
    /// `[[shape.trim]]` (PDE tube): the trims cut out of the tube
    pub trim: Option<Vec<RawTrim>>,
}

/// `[[shape.trim]]`: one trim of a PDE tube, a rectangle in (angle, z).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawTrim {
    /// `angles`, degrees: [from, to] counter-clockwise from +x
    #[serde(default, deserialize_with = "exact::opt")]
    pub angles: Option<[f64; 2]>,
    /// `z`, mm (machine z): [bottom, top]
    #[serde(default, deserialize_with = "exact::opt")]
    pub z: Option<[f64; 2]>,
}

/// `[[shape.part]]`: one part of a composition, in design units.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawPart {
    /// `name`
    pub name: Option<String>,
    /// `polygon`: [[x, y], ...]
    #[serde(default, deserialize_with = "exact::opt_vec")]
    pub polygon: Option<Vec<[f64; 2]>>,
    /// `svg`: path data
    pub svg: Option<String>,
    /// `text`
    pub text: Option<String>,
    /// `font` (with `text`)
    pub font: Option<String>,
    /// `size`: cap height, design units (with `text`)
    pub size: Option<f64>,
    /// `of`: names of earlier parts
    pub of: Option<Names>,
    /// `op`: union, intersect, subtract or invert
    pub op: Option<String>,
    /// `level`: the part is Γ(level) of its source's field
    pub level: Option<f64>,
    /// `singularities`: `"auto"` or a count
    pub singularities: Option<AutoOr>,
}

/// One name or a list of names (`of = "m1"` is `of = ["m1"]`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Names(pub Vec<String>);

impl<'de> Deserialize<'de> for Names {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = Names;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a part name or a list of part names")
            }
            fn visit_str<E>(self, v: &str) -> Result<Names, E> {
                Ok(Names(vec![v.to_string()]))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut a: A) -> Result<Names, A::Error> {
                let mut v = Vec::new();
                while let Some(n) = a.next_element::<String>()? {
                    v.push(n);
                }
                Ok(Names(v))
            }
        }
        d.deserialize_any(V)
    }
}

/// `[tool]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawTool {
    /// `diameter`, mm
    pub diameter: Option<f64>,
    /// `feed`, mm/min
    pub feed: Option<f64>,
    /// `plunge_feed`, mm/min
    pub plunge_feed: Option<f64>,
    /// `spindle`, rev/min
    pub spindle: Option<f64>,
    /// `stepdown`, mm
    pub stepdown: Option<f64>,
    /// `stepover`, mm
    pub stepover: Option<f64>,
    /// `ramp_angle`, degrees
    pub ramp_angle: Option<f64>,
}

/// `[stock]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawStock {
    /// `top`, mm
    pub top: Option<f64>,
    /// `safe_z`, mm
    pub safe_z: Option<f64>,
    /// `retract_z`, mm
    pub retract_z: Option<f64>,
    /// `margin`, mm
    pub margin: Option<f64>,
}

/// `[operation]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawOperation {
    /// `kind`
    pub kind: Option<String>,
    /// `side`
    pub side: Option<String>,
    /// `depth`, mm
    pub depth: Option<f64>,
    /// `tolerance`, mm
    pub tolerance: Option<f64>,
    /// `direction`
    pub direction: Option<String>,
    /// `max_scallop`, mm
    pub max_scallop: Option<f64>,
    /// `stock_to_leave`, mm
    pub stock_to_leave: Option<f64>,
}

/// `[field]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawField {
    /// `singularities`: `"auto"` or a count
    pub singularities: Option<AutoOr>,
    /// `pseudo_boundary`: `"auto"` or a distance in mm
    pub pseudo_boundary: Option<AutoOr>,
}

/// `[output]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawOutput {
    /// `arcs`
    pub arcs: Option<bool>,
    /// `max_arc_radius`, mm
    pub max_arc_radius: Option<f64>,
}

/// A number, or a word (only `"auto"` is accepted; any other word is reported
/// with its key by [`RawJob::resolve`]).
#[derive(Debug, Clone, PartialEq)]
pub enum AutoOr {
    /// An integer.
    Int(i64),
    /// A float.
    Float(f64),
    /// A word.
    Word(String),
}

impl<'de> Deserialize<'de> for AutoOr {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = AutoOr;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("\"auto\" or a number")
            }
            fn visit_i64<E>(self, v: i64) -> Result<AutoOr, E> {
                Ok(AutoOr::Int(v))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<AutoOr, E> {
                i64::try_from(v)
                    .map(AutoOr::Int)
                    .map_err(|_| E::custom(format!("{v} is too large")))
            }
            fn visit_f64<E>(self, v: f64) -> Result<AutoOr, E> {
                Ok(AutoOr::Float(v))
            }
            fn visit_str<E>(self, v: &str) -> Result<AutoOr, E> {
                Ok(AutoOr::Word(v.to_string()))
            }
        }
        d.deserialize_any(V)
    }
}
