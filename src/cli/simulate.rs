//! `pfcam simulate`: arguments, the run, what is printed, the exit status.

use super::{check_output, load, read_gcode_file, stdout_line, UsageError};
use anyhow::{anyhow, bail, Context, Result};
use pfcam::output::write_atomic;
use pfcam::simulate::{self, png::sequence_png, SimError, SimOptions, StockBox, ToolShape};
use std::path::PathBuf;

/// Findings printed before each program's summary; the rest are counted (all
/// are in --json).
const SHOWN_FINDINGS: usize = 30;

/// `--tool-shape`.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
enum ShapeArg {
    /// Flat end mill.
    Flat,
    /// Ball end mill (corner radius = radius).
    Ball,
    /// Bull nose end mill (give --corner-radius).
    Bull,
}

/// `pfcam simulate FILE.nc [FILE.nc ...] [options]`.
#[derive(Debug, clap::Args)]
pub struct SimulateArgs {
    /// The G-code files, run in this order on one stock (a rough program,
    /// then a finish program): each starts from the stock the one before left.
    #[arg(required = true, num_args = 1..)]
    files: Vec<PathBuf>,
    /// The job the files were made from: tool (of the first file, unless its
    /// header names another), stepdown, stock and the part to measure gouges
    /// and material left against.
    #[arg(long, value_name = "JOB.toml")]
    job: Option<PathBuf>,
    /// The stock block: lower-left and upper-right corner and top, mm
    /// (default: the job's, the first file's header's, or the feed moves'
    /// extent grown by the tool radius, top 0).
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
    /// Tool diameter, mm, for every file (default: each file's header's, else
    /// for the first file the job's).
    #[arg(long, value_name = "MM")]
    tool_diameter: Option<f64>,
    /// Tool shape, for every file (default: the header's, else flat).
    #[arg(long, value_name = "SHAPE")]
    tool_shape: Option<ShapeArg>,
    /// Corner radius of a bull nose, mm, for every file (needed with
    /// --tool-shape bull unless the header names it).
    #[arg(long, value_name = "MM")]
    corner_radius: Option<f64>,
    /// Stepdown for the slot check, mm, for every file (default: the job's
    /// for the job's tool, else the header's).
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

/// Runs `pfcam simulate`; an unclean program is an error (exit 1) after the
/// report is printed.
pub fn cmd_simulate(a: &SimulateArgs) -> Result<()> {
    if let Some(p) = &a.png {
        check_output(p, "png", a.force)?;
    }
    let texts = read_files(&a.files)?;
    let names: Vec<&str> = texts.iter().map(|(n, _)| n.as_str()).collect();
    let all = names.join(", ");
    let opts = sim_options(a)?;
    let programs: Vec<(&str, &str)> = texts
        .iter()
        .map(|(n, t)| (n.as_str(), t.as_str()))
        .collect();
    let seq = simulate::simulate_programs(&programs, &opts).map_err(|e| match e {
        SimError::Program { name, error } => anyhow!(*error).context(name),
        e => anyhow!(e).context(all.clone()),
    })?;
    if let Some(p) = &a.png {
        let png = sequence_png(&seq, &format!("pfcam simulate {}", names.join(" ")))?;
        write_atomic(p, &png, a.force)?;
    }
    if a.json {
        stdout_line(&json_text(&seq, &names)?)?;
    } else {
        let mut s = summary_text(&seq);
        if let Some(p) = &a.png {
            s += &format!("\nwrote {}", p.display());
        }
        stdout_line(&s)?;
    }
    if !seq.is_clean() {
        bail!("{all}: {}", findings_count(&seq));
    }
    Ok(())
}

/// The G-code files, each as (name, text; not UTF-8 read lossily).
fn read_files(files: &[PathBuf]) -> Result<Vec<(String, String)>> {
    let mut texts = Vec::with_capacity(files.len());
    for file in files {
        let bytes = read_gcode_file(file)?;
        texts.push((
            file.display().to_string(),
            String::from_utf8_lossy(&bytes).into_owned(),
        ));
    }
    Ok(texts)
}

/// The simulation's options from the flags, with the job's facts read at
/// the resolution clamped to 0.05 mm .. the surface's default.
fn sim_options(a: &SimulateArgs) -> Result<SimOptions> {
    let mut opts = SimOptions {
        resolution: a.resolution,
        tool_diameter: a.tool_diameter,
        tool_shape: a.tool_shape.map(|s| match s {
            ShapeArg::Flat => ToolShape::Flat,
            ShapeArg::Ball => ToolShape::Ball,
            ShapeArg::Bull => ToolShape::Bull,
        }),
        corner_radius: a.corner_radius,
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
    Ok(opts)
}

/// `--json`: every program's report, and the part; with one file also its
/// report with the part in it under `file` and `report`, as before several
/// files could be given.
fn json_text(seq: &simulate::Sequence, names: &[&str]) -> Result<String> {
    let programs: Vec<_> = seq
        .programs
        .iter()
        .map(|p| {
            serde_json::json!({
                "file": p.name,
                "clean": p.report.is_clean(),
                "report": p.report,
            })
        })
        .collect();
    let mut v = serde_json::json!({
        "files": names,
        "clean": seq.is_clean(),
        "programs": programs,
        "part": seq.part,
    });
    if seq.programs.len() == 1 {
        let mut report = seq.programs[0].report.clone();
        report.part = seq.part.clone();
        v["file"] = serde_json::json!(names[0]);
        v["report"] = serde_json::to_value(&report)?;
    }
    Ok(serde_json::to_string_pretty(&v)?)
}

/// The printed report: for each program (headed by its number when there are
/// several) its first [`SHOWN_FINDINGS`] findings as `FILE:LINE: error: ...`,
/// its notes and its summary; then the part's summary.
fn summary_text(seq: &simulate::Sequence) -> String {
    let single = seq.programs.len() == 1;
    let mut s = String::new();
    for (k, p) in seq.programs.iter().enumerate() {
        let r = &p.report;
        if !single {
            s += &format!("program {} of {}: {}\n", k + 1, seq.programs.len(), p.name);
        }
        for f in r.findings.iter().take(SHOWN_FINDINGS) {
            s += &format!("{}:{}: error: {}\n", p.name, f.line, f.message);
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
        if !single || seq.part.is_some() {
            s.push('\n');
        }
    }
    if let Some(part) = &seq.part {
        s += &part.summary();
    }
    s.trim_end_matches('\n').to_string()
}

/// The findings of an unclean sequence, counted by kind over all programs.
fn findings_count(seq: &simulate::Sequence) -> String {
    let count = |f: &dyn Fn(&simulate::Report) -> usize| -> usize {
        seq.programs.iter().map(|p| f(&p.report)).sum()
    };
    format!(
        "{} finding(s): {} rapid(s) into material, {} straight plunge(s), {} slot(s) deeper than the stepdown, {} gouge(s)",
        count(&|r| r.findings.len()),
        count(&|r| r.rapids_into_material),
        count(&|r| r.straight_plunges),
        count(&|r| r.deep_slots),
        seq.findings().filter(|(_, f)| f.kind == simulate::Kind::Gouge).count()
    )
}
