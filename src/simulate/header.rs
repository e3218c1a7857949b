//! What a pfcam G-code header says about the tool, the stock and the
//! operation, for a file simulated without `--job`: the comments
//! `(tool: 3.175 mm end mill, ...)`, `(stock: ..40 Y-3..60, top 0, ...)`
//! or `(stock: top 0, ...)`, and `(operation: ... stepdown 1.5, tol 0.01 mm)`.
//! Only the leading comment lines are read; another program's comments are
//! ignored unless they say exactly this.

/// What the header gives (each `None` when not said).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Header {
    /// Tool diameter, mm.
    pub tool_diameter: Option<f64>,
    /// Stock rectangle (x0, y0, x1, y1), mm.
    pub stock_rect: Option<[f64; 4]>,
    /// Stock top, mm.
    pub stock_top: Option<f64>,
    /// Stepdown, mm.
    pub stepdown: Option<f64>,
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
            h.tool_diameter = rest
                .split_once(" mm end mill")
                .and_then(|(d, _)| d.parse().ok())
                .filter(|d: &f64| *d > 0.0 && d.is_finite());
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
        assert_eq!(h.tool_diameter, Some(3.175));
        assert_eq!(h.stock_top, Some(0.0));
        assert_eq!(h.stock_rect, None);
        assert_eq!(h.stepdown, Some(1.5));
        let new = "(pfcam 0.1.0 job x)\n(stock: X-12.5..40 Y-3..60, top -1, safe z 5 mm)\n";
        let h = read_header(new);
        assert_eq!(h.stock_rect, Some([-12.5, -3.0, 40.0, 60.0]));
        assert_eq!(h.stock_top, Some(-1.0));
        assert_eq!(h.tool_diameter, None);
        assert_eq!(
            read_header("G0 X0\n(tool: 3 mm end mill)\n"),
            Header::default()
        );
    }
}
