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
pub(crate) struct RawJob {
    /// `[job]`
    pub(crate) job: Option<RawJobTable>,
    /// `[shape]`
    pub(crate) shape: Option<RawShape>,
    /// `[tool]`
    pub(crate) tool: Option<RawTool>,
    /// `[stock]`
    pub(crate) stock: Option<RawStock>,
    /// `[operation]`
    pub(crate) operation: Option<RawOperation>,
    /// `[field]`
    pub(crate) field: Option<RawField>,
    /// `[machine]`
    pub(crate) machine: Option<RawMachine>,
    /// `[output]`
    pub(crate) output: Option<RawOutput>,
    /// `[profile]`
    pub(crate) profile: Option<RawProfile>,
    /// `[finish]`
    pub(crate) finish: Option<finish::RawFinish>,
}

/// `[profile]`: the depth profile φ(s) of a boss or cavity.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawProfile {
    /// `kind`: linear, sigmoid, power, spline or table
    pub(crate) kind: Option<String>,
    /// `s_bottom` (linear)
    pub(crate) s_bottom: Option<f64>,
    /// `s1` (sigmoid: top edge)
    pub(crate) s1: Option<f64>,
    /// `s2` (sigmoid: foot of the wall)
    pub(crate) s2: Option<f64>,
    /// `steepness` (sigmoid)
    pub(crate) steepness: Option<f64>,
    /// `exponent` (power)
    pub(crate) exponent: Option<f64>,
    /// `points`: [[s, z], ...] (spline, table), z in mm relative to stock.top
    #[serde(default, deserialize_with = "exact::opt_vec")]
    pub(crate) points: Option<Vec<[f64; 2]>>,
}

/// `[job]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawJobTable {
    /// `name`
    pub(crate) name: Option<String>,
}

/// `[shape]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawShape {
    /// `text`
    pub(crate) text: Option<String>,
    /// `lines`: several lines of text, top to bottom
    pub(crate) lines: Option<Vec<String>>,
    /// `align`: left, centre (center) or right
    pub(crate) align: Option<String>,
    /// `line_spacing`, em
    pub(crate) line_spacing: Option<f64>,
    /// `svg_path`
    pub(crate) svg_path: Option<String>,
    /// `svg_file`: an SVG document, relative to the job file's directory
    pub(crate) svg_file: Option<String>,
    /// `id`: the one element of `svg_file` to use
    pub(crate) id: Option<String>,
    /// `scale`: the `svg_file` drawing's size times this
    pub(crate) scale: Option<f64>,
    /// `width`, mm: the `svg_file` drawing's width
    pub(crate) width: Option<f64>,
    /// `dxf_file`: a DXF drawing, relative to the job file's directory
    pub(crate) dxf_file: Option<String>,
    /// `layer`: only this layer of `dxf_file`
    pub(crate) layer: Option<String>,
    /// `join_tolerance`, mm: `dxf_file` pieces whose ends are closer join
    pub(crate) join_tolerance: Option<f64>,
    /// `font`
    pub(crate) font: Option<String>,
    /// `height`, mm
    pub(crate) height: Option<f64>,
    /// `letter_spacing`, mm
    pub(crate) letter_spacing: Option<f64>,
    /// `origin`, mm
    #[serde(default, deserialize_with = "exact::opt")]
    pub(crate) origin: Option<[f64; 2]>,
    /// `result`: the name of the part that is the shape (with `[[shape.part]]`)
    pub(crate) result: Option<String>,
    /// `[[shape.part]]`: the parts of a composition
    pub(crate) part: Option<Vec<RawPart>>,
    /// `kind`: a surface source, `"harmonic-bezier"`
    pub(crate) kind: Option<String>,
    /// `degree` (harmonic patch): n, the degree along the rows
    pub(crate) degree: Option<i64>,
    /// `form` (harmonic patch): `"square"` or `"raised"`
    pub(crate) form: Option<String>,
    /// `size` (harmonic patch), mm: [X, Y]
    #[serde(default, deserialize_with = "exact::opt")]
    pub(crate) size: Option<[f64; 2]>,
    /// `row0` (harmonic patch), mm: heights of the edge y = 0
    pub(crate) row0: Option<Vec<f64>>,
    /// `row1` (harmonic patch), mm: heights of the edge y = Y
    pub(crate) row1: Option<Vec<f64>>,
    /// `points` (polyharmonic), mm: [[x, y, z], ...] on the surface
    #[serde(default, deserialize_with = "exact::opt_vec")]
    pub(crate) points: Option<Vec<[f64; 3]>>,
    /// `inside` (polyharmonic), mm: points inside the solid
    #[serde(default, deserialize_with = "exact::opt_vec")]
    pub(crate) inside: Option<Vec<[f64; 3]>>,
    /// `outside` (polyharmonic), mm: points outside the solid (separators)
    #[serde(default, deserialize_with = "exact::opt_vec")]
    pub(crate) outside: Option<Vec<[f64; 3]>>,
    /// `points_file` (polyharmonic): a CSV or XYZ file of the points
    pub(crate) points_file: Option<String>,
    /// `kernel` (polyharmonic): `"T2A"` or `"T2"`
    pub(crate) kernel: Option<String>,
    /// `a`: the T2A kernel's ball radius A, mm (polyharmonic), or the PDE's
    /// parameter (PDE tube)
    pub(crate) a: Option<f64>,
    /// `box` (polyharmonic), mm: [[x0, y0, z0], [x1, y1, z1]]
    #[serde(rename = "box", default, deserialize_with = "exact::opt_vec")]
    pub(crate) box_: Option<Vec<[f64; 3]>>,
    /// `elements` (polyharmonic): elements per box edge
    pub(crate) elements: Option<i64>,
    /// `base` (polyharmonic), mm: the height of the block's foot
    pub(crate) base: Option<f64>,
    /// `solid` (polyharmonic): `"relief"` or `"closed"`
    pub(crate) solid: Option<String>,
    /// `bottom_size` (PDE tube), mm: [X, Y] of the curve at u = 0
    #[serde(default, deserialize_with = "exact::opt")]
    pub(crate) bottom_size: Option<[f64; 2]>,
    /// `bottom_exponent` (PDE tube): the superellipse's p at u = 0
    pub(crate) bottom_exponent: Option<f64>,
    /// `top_size` (PDE tube), mm: [X, Y] of the curve at u = 1
    #[serde(default, deserialize_with = "exact::opt")]
    pub(crate) top_size: Option<[f64; 2]>,
    /// `top_exponent` (PDE tube): the superellipse's p at u = 1
    pub(crate) top_exponent: Option<f64>,
    /// `flare` (PDE tube), mm per unit u: [bottom, top]
    #[serde(default, deserialize_with = "exact::opt")]
    pub(crate) flare: Option<[f64; 2]>,
    /// `rise` (PDE tube), mm per unit u: [bottom, top]
    #[serde(default, deserialize_with = "exact::opt")]
    pub(crate) rise: Option<[f64; 2]>,
    /// `modes` (PDE tube): N
    pub(crate) modes: Option<i64>,
    /// `samples` (PDE tube): K
    pub(crate) samples: Option<i64>,
    /// `[[shape.trim]]` (PDE tube): the trims cut out of the tube
    pub(crate) trim: Option<Vec<RawTrim>>,
}

/// `[[shape.trim]]`: one trim of a PDE tube, a rectangle in (angle, z).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawTrim {
    /// `angles`, degrees: [from, to] counter-clockwise from +x
    #[serde(default, deserialize_with = "exact::opt")]
    pub(crate) angles: Option<[f64; 2]>,
    /// `z`, mm (machine z): [bottom, top]
    #[serde(default, deserialize_with = "exact::opt")]
    pub(crate) z: Option<[f64; 2]>,
}

/// `[[shape.part]]`: one part of a composition, in design units.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawPart {
    /// `name`
    pub(crate) name: Option<String>,
    /// `polygon`: [[x, y], ...]
    #[serde(default, deserialize_with = "exact::opt_vec")]
    pub(crate) polygon: Option<Vec<[f64; 2]>>,
    /// `svg`: path data
    pub(crate) svg: Option<String>,
    /// `text`
    pub(crate) text: Option<String>,
    /// `font` (with `text`)
    pub(crate) font: Option<String>,
    /// `size`: cap height, design units (with `text`)
    pub(crate) size: Option<f64>,
    /// `of`: names of earlier parts
    pub(crate) of: Option<Names>,
    /// `op`: union, intersect, subtract or invert
    pub(crate) op: Option<String>,
    /// `level`: the part is Γ(level) of its source's field
    pub(crate) level: Option<f64>,
    /// `singularities`: `"auto"` or a count
    pub(crate) singularities: Option<AutoOr>,
}

/// One name or a list of names (`of = "m1"` is `of = ["m1"]`).
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct Names(pub Vec<String>);

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
pub(crate) struct RawTool {
    /// `diameter`, mm
    pub(crate) diameter: Option<f64>,
    /// `feed`, mm/min
    pub(crate) feed: Option<f64>,
    /// `plunge_feed`, mm/min
    pub(crate) plunge_feed: Option<f64>,
    /// `spindle`, rev/min
    pub(crate) spindle: Option<f64>,
    /// `stepdown`, mm
    pub(crate) stepdown: Option<f64>,
    /// `stepover`, mm
    pub(crate) stepover: Option<f64>,
    /// `ramp_angle`, degrees
    pub(crate) ramp_angle: Option<f64>,
}

/// `[stock]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawStock {
    /// `top`, mm
    pub(crate) top: Option<f64>,
    /// `safe_z`, mm
    pub(crate) safe_z: Option<f64>,
    /// `retract_z`, mm
    pub(crate) retract_z: Option<f64>,
    /// `margin`, mm
    pub(crate) margin: Option<f64>,
}

/// `[operation]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawOperation {
    /// `kind`
    pub(crate) kind: Option<String>,
    /// `side`
    pub(crate) side: Option<String>,
    /// `depth`, mm
    pub(crate) depth: Option<f64>,
    /// `tolerance`, mm
    pub(crate) tolerance: Option<f64>,
    /// `direction`
    pub(crate) direction: Option<String>,
    /// `max_scallop`, mm
    pub(crate) max_scallop: Option<f64>,
    /// `stock_to_leave`, mm
    pub(crate) stock_to_leave: Option<f64>,
}

/// `[field]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawField {
    /// `singularities`: `"auto"` or a count
    pub(crate) singularities: Option<AutoOr>,
    /// `pseudo_boundary`: `"auto"` or a distance in mm
    pub(crate) pseudo_boundary: Option<AutoOr>,
}

/// `[output]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawOutput {
    /// `arcs`
    pub(crate) arcs: Option<bool>,
    /// `max_arc_radius`, mm
    pub(crate) max_arc_radius: Option<f64>,
}

/// A number, or a word (only `"auto"` is accepted; any other word is reported
/// with its key by [`RawJob::resolve_with`]).
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum AutoOr {
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
