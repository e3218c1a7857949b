//! The check `pfcam run` makes of the program it is about to write: its own
//! simulation, on the stock the header names, must find no rapid into
//! material, no straight plunge and no full-width cut deeper than the
//! stepdown. The simulation reads the G-code text, not the tool path, so it
//! catches what the writer (arc fitting, rounding) changed as well as what the
//! linker planned.

use super::{simulate, simulate_programs, Finding, SimError, SimOptions};

/// A program its own simulation finds unsafe: how many findings, and the
/// first (by line).
#[derive(Debug, thiserror::Error)]
#[error(
    "the program's own simulation finds {count} collision(s); the first, line {}: {}",
    first.line,
    first.message
)]
pub struct UnsafeProgram {
    /// Number of findings.
    pub(crate) count: usize,
    /// The first finding, by line.
    pub(crate) first: Finding,
}

/// Simulates `text` with a flat end mill of `tool_diameter` mm and the slot
/// check at `stepdown` mm, on the stock its header names (else the extent of
/// its feed moves): `Ok` when clean, else the findings as [`UnsafeProgram`].
pub fn verify_program(
    text: &str,
    tool_diameter: f64,
    stepdown: f64,
) -> Result<Result<(), UnsafeProgram>, SimError> {
    let opts = SimOptions {
        tool_diameter: Some(tool_diameter),
        stepdown: Some(stepdown),
        ..SimOptions::default()
    };
    let sim = simulate(text, &opts)?;
    Ok(verdict(&sim.report.findings))
}

/// `Ok` without findings, else their count and the first.
fn verdict(findings: &[Finding]) -> Result<(), UnsafeProgram> {
    match findings.first() {
        None => Ok(()),
        Some(first) => Err(UnsafeProgram {
            count: findings.len(),
            first: first.clone(),
        }),
    }
}

/// The finishing program's own check: simulated with the tool its header
/// names, on the stock the roughing program `rough` left (the two headers
/// name the stock and the tools; the finish's findings only are returned).
pub fn verify_finish(rough: &str, finish: &str) -> Result<Result<(), UnsafeProgram>, SimError> {
    let seq = simulate_programs(
        &[("rough", rough), ("finish", finish)],
        &SimOptions::default(),
    )?;
    Ok(seq
        .programs
        .get(1)
        .map_or(Ok(()), |p| verdict(&p.report.findings)))
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEAD: &str = "(stock: X0..30 Y0..30, top 0, safe z 5 mm)\nG21 G90\nG0 Z5\nG0 X15 Y15\n";

    #[test]
    fn a_straight_plunge_is_refused_at_its_line_and_a_ramp_is_not() {
        let plunge = format!("{HEAD}G1 Z-1 F100\nG1 X20\nM2\n");
        let e = verify_program(&plunge, 3.0, 1.0).unwrap().unwrap_err();
        assert_eq!((e.count, e.first.line), (1, 5));
        assert!(e.to_string().contains("line 5: straight plunge"), "{e}");
        let ramp = format!("{HEAD}G0 Z0.5\nG1 X25 Z-1 F100\nG1 X15\nM2\n");
        assert!(verify_program(&ramp, 3.0, 1.0).unwrap().is_ok());
    }

    #[test]
    fn a_finish_is_checked_on_what_the_rough_left() {
        let rough = "(tool: 3 mm end mill, feed 100, plunge 100 mm/min, spindle 0 rpm)\n(stock: X0..30 Y0..30, top 0, safe z 5 mm)\n(operation: boss outside climb, depth 1, stepdown 1, tol 0.01 mm)\nG21 G90\nG0 Z5\nG0 X5 Y15\nG0 Z0.5\nG1 X25 Z-1 F100\nG1 X5\nG0 Z5\nM2\n";
        let ball = "(tool: 2 mm ball end mill, feed 100, plunge 100 mm/min, spindle 0 rpm)\n(stock: X0..30 Y0..30, top 0, safe z 5 mm)\nG21 G90\nG0 Z5\n";
        // Down into the groove the rough cut: clean.
        let inside = format!("{ball}G0 X15 Y15\nG0 Z-0.5\nG1 Z-1 F100\nG1 X20\nG0 Z5\nM2\n");
        assert!(verify_finish(rough, &inside).unwrap().is_ok());
        // Beside it, into uncut stock: refused at the finish's line.
        let beside = format!("{ball}G0 X15 Y25\nG0 Z-0.5\nM2\n");
        let e = verify_finish(rough, &beside).unwrap().unwrap_err();
        assert_eq!(e.first.line, 6);
        // Alone, on a fresh stock, the same inside move would be a collision.
        assert!(verify_program(&inside, 2.0, 1.0).unwrap().is_err());
    }

    #[test]
    fn a_rapid_into_the_stock_is_refused() {
        let rapid = format!("{HEAD}G0 Z-0.5\nM2\n");
        let e = verify_program(&rapid, 3.0, 1.0).unwrap().unwrap_err();
        assert_eq!(e.first.line, 5);
        assert!(e.to_string().contains("rapid (G0) into material"), "{e}");
    }
}
