//! `pfcam simulate`: arguments, the run, what is printed, the exit status.

use super::{check_output, load, read_gcode_file, stdout_line, UsageError};
use anyhow::{anyhow, bail, Context, Result};
use pfcam::output::write_atomic;
use pfcam::simulate::{self, png::stock_png, SimOptions, StockBox};
use std::path::PathBuf;

/// Findings printed before the summary; the rest are counted (all are in --json).
const SHOWN_FINDINGS: usize = 30;

/// `pfcam simulate FILE.nc [options]`.
#[derive(Debug, clap::Args)]
pub struct SimulateArgs {
    /// The G-code file.
    file: PathBuf,
    /// The job the file was made from: tool, stepdown, stock and the part to
    /// measure gouges and material left against.
    #[arg(long, value_name = "JOB.toml")]
    job: Option<PathBuf>,
    /// The stock block: lower-left and upper-right corner and top, mm
    /// (default: the job's, the file header's, or the feed moves' extent grown
    /// by the tool radius, top 0).
    #[arg(
        long,
        value_name = "X0,Y0,X1,Y1,TOP",
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    stock: Option<Vec<f64>>,
    /// Cell side of the height map, mm.
    #[arg(long, value_name = "MM", default_value_t = simulate::DEFAULT_RESOLUTION)]
    resolution: f64,
    /// Flat end mill diameter, mm (default: the job's, else the file header's).
    #[arg(long, value_name = "MM")]
    tool_diameter: Option<f64>,
    /// Stepdown for the slot check, mm (default: the job's, else the header's).
    #[arg(long, value_name = "MM")]
    stepdown: Option<f64>,
    /// Write the final stock as a colour height map with collisions marked.
    #[arg(long, value_name = "FILE.png")]
    png: Option<PathBuf>,
    /// Overwrite the PNG even if pfcam did not write it.
    #[arg(long)]
    force: bool,
    /// Print the figures and findings as JSON.
    #[arg(long)]
    json: bool,
}

/// Runs `pfcam simulate`; an unclean program is an error (exit 1) after its
/// report is printed.
pub fn cmd_simulate(a: &SimulateArgs) -> Result<()> {
    if let Some(p) = &a.png {
        check_output(p, "png", a.force)?;
    }
    let bytes = read_gcode_file(&a.file)?;
    let text = String::from_utf8_lossy(&bytes);
    let name = a.file.display().to_string();
    let mut opts = SimOptions {
        resolution: a.resolution,
        tool_diameter: a.tool_diameter,
        stepdown: a.stepdown,
        ..SimOptions::default()
    };
    if let Some(s) = &a.stock {
        let [x0, y0, x1, y1, top] = s[..] else {
            return Err(UsageError("--stock takes X0,Y0,X1,Y1,TOP".into()).into());
        };
        opts.stock = Some(StockBox {
            lo: [x0, y0],
            hi: [x1, y1],
            top,
        });
    }
    if let Some(path) = &a.job {
        let job = load(path)?;
        let res = a.resolution.clamp(0.05, pfcam::surface::DEFAULT_RESOLUTION);
        opts.job =
            Some(simulate::job_facts(&job, res).with_context(|| path.display().to_string())?);
    }
    let sim = simulate::simulate(&text, &opts).map_err(|e| anyhow!(e).context(name.clone()))?;
    let r = &sim.report;
    if let Some(p) = &a.png {
        let png = stock_png(&sim, &format!("pfcam simulate {name}"))?;
        write_atomic(p, &png, a.force)?;
    }
    if a.json {
        let v = serde_json::json!({
            "file": name,
            "clean": r.is_clean(),
            "report": r,
        });
        stdout_line(&serde_json::to_string_pretty(&v)?)?;
    } else {
        let mut s = String::new();
        for f in r.findings.iter().take(SHOWN_FINDINGS) {
            s += &format!("{name}:{}: error: {}\n", f.line, f.message);
        }
        if r.findings.len() > SHOWN_FINDINGS {
            s += &format!(
                "... and {} more (all in --json)\n",
                r.findings.len() - SHOWN_FINDINGS
            );
        }
        for n in &r.notes {
            s += &format!("note: {n}\n");
        }
        s += &r.summary();
        if let Some(p) = &a.png {
            s += &format!("\nwrote {}", p.display());
        }
        stdout_line(&s)?;
    }
    if !r.is_clean() {
        bail!(
            "{name}: {} finding(s): {} rapid(s) into material, {} straight plunge(s), {} slot(s) deeper than the stepdown, {} gouge(s)",
            r.findings.len(),
            r.rapids_into_material,
            r.straight_plunges,
            r.deep_slots,
            r.findings.iter().filter(|f| f.kind == simulate::Kind::Gouge).count()
        );
    }
    Ok(())
}
