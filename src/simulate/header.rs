//! What a pfcam G-code header says about the tool, the stock and the
//! operation: the comments `(tool: ...)`, `(stock: ..40 Y-3..60, top
//! 0, ...)` or `(stock: top 0, ...)`, and `(operation: ... stepdown 1.5, tol
//! 0.01 mm)`. The tool line names one of three tools (what follows the
//! tool's words is not read):
//! - `(tool: 3.175 mm end mill, feed 800, plunge 200 mm/min, spindle 18000 rpm)`:
//!   a flat end mill;
//! - `(tool: 3.175 mm ball end mill, feed ...)`: a ball end mill;
//! - `(tool: 6 mm bull nose end mill, corner 1.5 mm, feed ...)`: a bull nose
//!   of corner radius 1.5 mm.
//!
//! Only the leading comment lines are read; another program's comments are
//! ignored unless they say exactly this.

use super::tool::{Tool, ToolShape};

/// What the header gives (each `None` when not said).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Header {
    /// The tool.
    pub tool: Option<Tool>,
    /// A `tool:` line that names none of the three tools (or one that cannot
    /// be: a bull nose without its corner, a corner not below the radius):
    /// its text, for a note.
    pub(crate) tool_unread: Option<String>,
    /// Stock rectangle (x0, y0, x1, y1), mm.
    pub(crate) stock_rect: Option<[f64; 4]>,
    /// Stock top, mm.
    pub(crate) stock_top: Option<f64>,
    /// Stepdown, mm.
    pub(crate) stepdown: Option<f64>,
}

/// Reads the comment lines at the start of `text` (see the module docs).
pub fn read_header(text: &str) -> Header {
    let mut h = Header::default();
    for line in text.lines().take(200) {
        let line = line.trim();
        let Some(body) = line.strip_prefix('(').and_then(|l| l.strip_suffix(')')) else {
            break;
        };
        if let Some(rest) = body.strip_prefix("tool: ") {
            h.tool = read_tool(rest);
            h.tool_unread = h.tool.is_none().then(|| body.to_string());
        } else if let Some(rest) = body.strip_prefix("stock: ") {
            for part in rest.split(", ") {
                if let Some(t) = part.strip_prefix("top ") {
                    h.stock_top = t.parse().ok().filter(|t: &f64| t.is_finite());
                } else if let Some(r) = rect(part) {
                    h.stock_rect = Some(r);
                }
            }
        } else if body.starts_with("operation: ") {
            for part in body.split(", ") {
                if let Some(s) = part.strip_prefix("stepdown ") {
                    h.stepdown = s.parse().ok().filter(|s: &f64| *s > 0.0 && s.is_finite());
                }
            }
        }
    }
    h
}

/// The tool of a `tool:` line (what follows `tool: `; see the module docs).
fn read_tool(rest: &str) -> Option<Tool> {
    let mut parts = rest.split(", ");
    let (d, kind) = parts.next()?.split_once(" mm ")?;
    let d: f64 = d.parse().ok()?;
    let shape = match kind {
        "end mill" => ToolShape::Flat,
        "ball end mill" => ToolShape::Ball,
        "bull nose end mill" => ToolShape::Bull,
        _ => return None,
    };
    let corner = match shape {
        ToolShape::Bull => Some(
            parts
                .next()?
                .strip_prefix("corner ")?
                .strip_suffix(" mm")?
                .parse()
                .ok()?,
        ),
        _ => None,
    };
    Tool::new(shape, d, corner).ok()
}

/// `X-12.5..40 Y-3..60` as [x0, y0, x1, y1].
fn rect(s: &str) -> Option<[f64; 4]> {
    let (x, y) = s.split_once(' ')?;
    let (x0, x1) = x.strip_prefix('X')?.split_once("..")?;
    let (y0, y1) = y.strip_prefix('Y')?.split_once("..")?;
    let v = [
        x0.parse().ok()?,
        y0.parse().ok()?,
        x1.parse().ok()?,
        y1.parse().ok()?,
    ];
    (v.iter().all(|c: &f64| c.is_finite()) && v[0] < v[2] && v[1] < v[3]).then_some(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_pfcam_headers_old_and_new() {
        let old = "(pfcam 0.1.0 job q-mould)\n(tool: 3.175 mm end mill, feed 800, plunge 200 mm/min, spindle 18000 rpm)\n(stock: top 0, safe z 5 mm)\n(operation: cavity outside climb, depth 3, stepdown 1.5, tol 0.01 mm)\nG21\n(tool: 6 mm end mill)\n";
        let h = read_header(old);
        assert_eq!(h.tool, Tool::new(ToolShape::Flat, 3.175, None).ok());
        assert_eq!(h.tool_unread, None);
        assert_eq!(h.stock_top, Some(0.0));
        assert_eq!(h.stock_rect, None);
        assert_eq!(h.stepdown, Some(1.5));
        let new = "(pfcam 0.1.0 job x)\n(stock: X-12.5..40 Y-3..60, top -1, safe z 5 mm)\n";
        let h = read_header(new);
        assert_eq!(h.stock_rect, Some([-12.5, -3.0, 40.0, 60.0]));
        assert_eq!(h.stock_top, Some(-1.0));
        assert_eq!(h.tool, None);
        assert_eq!(
            read_header("G0 X0\n(tool: 3 mm end mill)\n"),
            Header::default()
        );
    }

    #[test]
    fn reads_the_three_tool_lines() {
        let tool = |line: &str| {
            let h = read_header(&format!("(pfcam 0.1.0 job x)\n({line})\nG21\n"));
            (h.tool, h.tool_unread.is_some())
        };
        let flat = Tool::new(ToolShape::Flat, 3.175, None).ok();
        let ball = Tool::new(ToolShape::Ball, 3.175, None).ok();
        let bull = Tool::new(ToolShape::Bull, 6.0, Some(1.5)).ok();
        let tail = "feed 800, plunge 200 mm/min, spindle 18000 rpm";
        assert_eq!(
            tool(&format!("tool: 3.175 mm end mill, {tail}")),
            (flat, false)
        );
        assert_eq!(
            tool(&format!("tool: 3.175 mm ball end mill, {tail}")),
            (ball, false)
        );
        assert_eq!(
            tool(&format!(
                "tool: 6 mm bull nose end mill, corner 1.5 mm, {tail}"
            )),
            (bull, false)
        );
        assert_eq!(
            tool("tool: 6 mm bull nose end mill, corner 1.5 mm"),
            (bull, false)
        );
        // Lines that name no tool pfcam simulate can model: noted, not guessed.
        for line in [
            "tool: 6 mm bull nose end mill, feed 800",
            "tool: 6 mm bull nose end mill, corner 3 mm, feed 800",
            "tool: 6 mm bull nose end mill, corner -1 mm",
            "tool: 6 mm v-bit, feed 800",
            "tool: -3 mm end mill",
            "tool: T1",
        ] {
            assert_eq!(tool(line), (None, true), "{line}");
        }
    }
}
