//! A DXF drawing (`shape.dxf_file`), read by the `dxf` crate (ixmilia's
//! dxf-rs, ASCII or binary DXF). The entities (`entities.rs`) become paths in
//! drawing units, flattened within the job's tolerance (`curves.rs`); open
//! pieces are chained into closed contours where their ends meet within
//! `shape.join_tolerance` (`chain.rs`). Each contour is split where it
//! crosses itself into the loops it fills (nonzero, `fill.rs`, as SVG
//! subpaths and polygon parts are), and the contours are then combined by the
//! even-odd rule, as a CAM program reads a drawing: a contour inside another is
//! a hole, one inside that an island.
//!
//! Units: `$INSUNITS` (inches, feet, mm, cm, m, ... 1 to 24); unset or 0
//! ("unitless") is taken as millimetres. The result is moved so the bottom-left
//! corner of its box is at `origin`.

mod chain;
mod curves;
mod entities;

use std::path::{Path, PathBuf};

use super::fill::{fill_outlines, FillRule};
use super::{
    polygons_bbox, regions_from_contours, Cause, Contour, GeometryError, Region, Shape, Vec2,
};

/// Largest DXF file read, bytes.
pub(crate) const MAX_DXF_BYTES: u64 = 64 << 20;

/// Curves are flattened within this fraction of `operation.tolerance`: the
/// part then lies within a quarter of the tolerance of the drawing, and the
/// tracer and the arc fitter keep the rest. At the whole tolerance the chords'
/// kinks cost the arc fitter: jobs/dxf-plate.toml traced 3482 G-code lines and
/// fitted only 114 arcs (1920 lines); at a quarter 2055 and 49 arcs (983 lines)
/// (`cargo test --release --test all -- --nocapture arcs::measure_every_job`).
pub const FLATTEN_FRACTION: f64 = 0.25;

/// Most vertices of the flattened contours.
pub(crate) const MAX_VERTICES: usize = 500_000;

/// A DXF drawing as a shape source (`shape.dxf_file`).
#[derive(Clone, Debug, PartialEq)]
pub struct DxfFileSource {
    /// The file, resolved against the job's directory.
    pub path: PathBuf,
    /// `shape.layer`: only the entities on this layer.
    pub layer: Option<String>,
    /// `shape.join_tolerance`, mm: ends closer than this are joined.
    pub join_tolerance: f64,
    /// Where the bottom-left corner of the outline's box goes, mm.
    pub origin: Vec2,
    /// Curves are flattened within this, mm (`operation.tolerance`).
    pub tolerance: f64,
    /// The largest width or height accepted, mm (the job's bound for its tool).
    pub max_size: f64,
}

const FILE: &str = "shape.dxf_file";

fn fail(key: &str, message: impl Into<String>) -> GeometryError {
    GeometryError::DxfFile {
        key: key.to_string(),
        message: message.into(),
    }
}

/// The shape a drawing gives (see the module documentation).
pub fn dxf_file_shape(src: &DxfFileSource) -> Result<Shape, GeometryError> {
    let drawing = read_drawing(&src.path)?;
    let (mm, unit) = mm_per_unit(drawing.header.default_drawing_units);
    let read = entities::read(&drawing, src.layer.as_deref()).map_err(|m| fail(FILE, m))?;
    if read.paths.is_empty() {
        return Err(nothing(src, &read.layers));
    }
    let tol = src.tolerance * FLATTEN_FRACTION / mm;
    let mut budget = curves::Budget(MAX_VERTICES);
    let mut closed = Vec::new();
    let mut open = Vec::new();
    for p in &read.paths {
        let pts = p.flatten(tol, &mut budget).map_err(|()| too_detailed())?;
        if pts.iter().any(|q| !q.is_finite()) {
            return Err(fail(
                FILE,
                "has a coordinate, radius, angle or scale that is not a finite number",
            ));
        }
        if pts.len() < 2 {
            continue;
        }
        if p.closed {
            closed.push(pts);
        } else {
            open.push(pts);
        }
    }
    // The size first: the chaining's grid and the fill's work grow with it.
    if let Some((lo, hi)) = polygons_bbox(&closed)
        .into_iter()
        .chain(polygons_bbox(&open))
        .reduce(|(a, b), (c, d)| {
            (
                Vec2::new(a.x.min(c.x), a.y.min(c.y)),
                Vec2::new(b.x.max(d.x), b.y.max(d.y)),
            )
        })
    {
        check_size((hi - lo) * mm, src)?;
    }
    let (loops, ends) = chain::chain(open, src.join_tolerance / mm);
    if !ends.is_empty() {
        return Err(fail(FILE, open_message(&ends, src.join_tolerance, unit)));
    }
    closed.extend(loops);
    let closed: Vec<Vec<Vec2>> = closed
        .into_iter()
        .map(|l| l.into_iter().map(|p| p * mm).collect())
        .collect();
    let outlines = outlines(&closed)?;
    let regions = place(&outlines, src);
    if regions.is_empty() {
        return Err(nothing(src, &read.layers));
    }
    Ok(Shape { regions })
}

/// The drawing in the file, refused past [`MAX_DXF_BYTES`].
fn read_drawing(path: &Path) -> Result<dxf::Drawing, GeometryError> {
    let shown = path.display();
    let bytes = super::capped::read_capped(path, "a DXF", MAX_DXF_BYTES)
        .map_err(|reason| GeometryError::FileRead { key: FILE, reason })?;
    if !looks_like_dxf(&bytes) {
        return Err(fail(
            FILE,
            format!(
                "is not a DXF file (it does not begin with a DXF group code and SECTION): {shown}"
            ),
        ));
    }
    let bytes = without_dates(bytes);
    // dxf-rs panics on some malformed values (a date past chrono's range);
    // such a panic is the file's fault, so it becomes this error.
    let loaded = std::panic::catch_unwind(|| dxf::Drawing::load(&mut std::io::Cursor::new(bytes)));
    match loaded {
        Ok(Ok(d)) => Ok(d),
        Ok(Err(e)) => Err(GeometryError::DxfLoad {
            path: path.to_path_buf(),
            source: Cause::new(e),
        }),
        Err(_) => Err(fail(FILE, format!("is not a readable DXF file: the DXF reader (dxf-rs) failed on a malformed value: {shown}"))),
    }
}

/// An ASCII DXF without what pfcam does not read and dxf-rs may panic on:
/// the header's dates and times (`$TD...`: a value past chrono's range
/// panics) and the CLASSES, OBJECTS, THUMBNAILIMAGE and ACDSDATA sections
/// (object timestamps). A binary DXF, or one whose lines do not pair into
/// group code and value, is returned as it is.
fn without_dates(bytes: Vec<u8>) -> Vec<u8> {
    let Ok(text) = std::str::from_utf8(&bytes) else {
        return bytes;
    };
    let lines: Vec<&str> = text.split_inclusive('\n').collect();
    if bytes.starts_with(b"AutoCAD Binary DXF") || lines.len() % 2 != 0 {
        return bytes;
    }
    let mut out = String::with_capacity(text.len());
    let (mut section, mut skip_var) = (String::new(), false);
    let mut opening: Option<&[&str]> = None;
    for pair in lines.chunks(2) {
        let (code, value) = (pair[0].trim(), pair[1].trim());
        if code == "0" && value == "SECTION" {
            opening = Some(pair);
            continue;
        }
        if let Some(open) = opening.take() {
            section = if code == "2" {
                value.to_string()
            } else {
                String::new()
            };
            if !DROPPED.contains(&section.as_str()) {
                out.extend(open.iter().copied());
            }
        }
        match code {
            "0" => skip_var = false,
            "9" => skip_var = value.starts_with("$TD"),
            _ => {}
        }
        let dropped = DROPPED.contains(&section.as_str());
        if code == "0" && value == "ENDSEC" {
            section.clear();
        }
        if dropped || (section == "HEADER" && skip_var) {
            continue;
        }
        out.extend(pair.iter().copied());
    }
    out.into_bytes()
}

/// Sections pfcam drops before reading (see [`without_dates`]).
const DROPPED: [&str; 4] = ["CLASSES", "OBJECTS", "THUMBNAILIMAGE", "ACDSDATA"];

/// A binary DXF's sentinel, or an ASCII DXF's first group: code 0 then
/// `SECTION`, or a 999 comment.
fn looks_like_dxf(bytes: &[u8]) -> bool {
    if bytes.starts_with(b"AutoCAD Binary DXF") {
        return true;
    }
    let head = String::from_utf8_lossy(&bytes[..bytes.len().min(4096)]);
    let mut lines = head.lines().map(str::trim).skip_while(|l| l.is_empty());
    matches!(
        (lines.next(), lines.next()),
        (Some("0"), Some("SECTION")) | (Some("999"), Some(_))
    )
}

/// Millimetres per drawing unit, and the unit's name, from `$INSUNITS`;
/// unitless (0, also what an unset header gives) is taken as mm.
fn mm_per_unit(u: dxf::enums::Units) -> (f64, &'static str) {
    use dxf::enums::Units as U;
    match u {
        U::Unitless => (1.0, "mm (the drawing gives no unit)"),
        U::Inches => (25.4, "inches"),
        U::Feet => (304.8, "feet"),
        U::Miles => (1_609_344.0, "miles"),
        U::Millimeters => (1.0, "mm"),
        U::Centimeters => (10.0, "cm"),
        U::Meters => (1000.0, "m"),
        U::Kilometers => (1e6, "km"),
        U::Microinches => (25.4e-6, "microinches"),
        U::Mils => (0.0254, "mils"),
        U::Yards => (914.4, "yards"),
        U::Angstroms => (1e-7, "ångströms"),
        U::Nanometers => (1e-6, "nm"),
        U::Microns => (1e-3, "µm"),
        U::Decimeters => (100.0, "dm"),
        U::Decameters => (1e4, "dam"),
        U::Hectometers => (1e5, "hm"),
        U::Gigameters => (1e12, "Gm"),
        U::AstronomicalUnits => (1.495_978_707e14, "astronomical units"),
        U::LightYears => (9.460_730_472_580_8e18, "light years"),
        U::Parsecs => (3.085_677_581_491_367e19, "parsecs"),
        U::USSurveyFeet => (1_200_000.0 / 3937.0, "US survey feet"),
        U::USSurveyInch => (100_000.0 / 3937.0, "US survey inches"),
        U::USSurveyYard => (3_600_000.0 / 3937.0, "US survey yards"),
        U::USSurveyMile => (6_336_000_000.0 / 3937.0, "US survey miles"),
    }
}

fn too_detailed() -> GeometryError {
    fail(FILE, format!("is too detailed or too large: flattened within operation.tolerance its contours have more than {MAX_VERTICES} vertices (or cross each other too often); simplify it or raise operation.tolerance"))
}

/// The open chains, by their ends in the drawing's own coordinates.
fn open_message(ends: &[chain::OpenChain], join: f64, unit: &str) -> String {
    const SHOWN: usize = 6;
    let list: Vec<String> = ends
        .iter()
        .take(SHOWN)
        .map(|c| {
            format!(
                "one with its ends at ({}, {}) and ({}, {})",
                num(c.start.x),
                num(c.start.y),
                num(c.end.x),
                num(c.end.y)
            )
        })
        .collect();
    let more = if ends.len() > SHOWN {
        format!(" and {} more", ends.len() - SHOWN)
    } else {
        String::new()
    };
    format!(
        "has {} open contour{} (in the drawing's coordinates, {unit}): {}{more}; every contour must close, its pieces' ends meeting within shape.join_tolerance = {} mm",
        ends.len(),
        if ends.len() == 1 { "" } else { "s" },
        list.join(", "),
        num(join)
    )
}

/// A coordinate to at most 6 decimals, without trailing zeros.
fn num(x: f64) -> String {
    let s = format!("{x:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

/// An error when the drawing, `size` mm, is larger than the job allows.
fn check_size(size: Vec2, src: &DxfFileSource) -> Result<(), GeometryError> {
    if size.x <= src.max_size && size.y <= src.max_size {
        return Ok(());
    }
    Err(fail(
        FILE,
        format!(
            "makes the drawing {:.1} × {:.1} mm, larger than the {} mm this job allows for its tool (is $INSUNITS right? the drawing's units are taken from it)",
            size.x, size.y, src.max_size
        ),
    ))
}

/// Each contour split into what it fills (nonzero), then all of them by
/// even-odd: a contour inside another is a hole.
fn outlines(contours: &[Vec<Vec2>]) -> Result<Vec<Vec<Vec2>>, GeometryError> {
    let mut all = Vec::new();
    for c in contours {
        all.extend(
            fill_outlines(std::slice::from_ref(c), FillRule::NonZero)
                .map_err(|_| too_detailed())?,
        );
    }
    fill_outlines(&all, FillRule::EvenOdd).map_err(|_| too_detailed())
}

/// The outlines moved so their box's bottom-left corner is at the origin, as
/// regions (named by the layer, or `dxf`).
fn place(outlines: &[Vec<Vec2>], src: &DxfFileSource) -> Vec<Region> {
    let Some((lo, _)) = polygons_bbox(outlines) else {
        return Vec::new();
    };
    let contours: Vec<Contour> = outlines
        .iter()
        .filter_map(|l| {
            let pts: Vec<Vec2> = l.iter().map(|&p| src.origin + (p - lo)).collect();
            Contour::polygon(&pts).ok()
        })
        .collect();
    regions_from_contours(src.layer.as_deref().unwrap_or("dxf"), contours)
}

/// The error for a drawing (or layer) with no closed geometry.
fn nothing(src: &DxfFileSource, layers: &std::collections::BTreeSet<String>) -> GeometryError {
    let have = if layers.is_empty() {
        "it has no LINE, ARC, CIRCLE, ELLIPSE, LWPOLYLINE, POLYLINE, SPLINE or INSERT in model space".to_string()
    } else {
        let list: Vec<&str> = layers.iter().map(String::as_str).take(12).collect();
        let more = match layers.len() {
            n if n > 12 => format!(" and {} more", n - 12),
            _ => String::new(),
        };
        format!(
            "layers with entities pfcam reads: {}{more}",
            list.join(", ")
        )
    };
    match &src.layer {
        Some(l) => fail(
            "shape.layer",
            format!("\"{l}\" has no closed geometry in the drawing ({have})"),
        ),
        None => fail(FILE, format!("has no closed geometry ({have})")),
    }
}
