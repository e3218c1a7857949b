//! The command line: argument definitions (clap) and one function per command.
//! Everything here is front end: it calls the library, shows progress, prints
//! results and turns errors into exit codes (see [`exit_code`]).

use anyhow::{anyhow, bail, Context, Result};
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use pfcam::gcode::{format_duration, write_gcode_on};
use pfcam::geometry::glyphs::paper_chars;
use pfcam::job::{load_job, Job, JobError};
use pfcam::output::{check_target, check_writable, write_atomic, OutputError};
use pfcam::pipeline::{self, Progress, RunOutput};
use pfcam::preview::colormap::ColourMap;
use pfcam::preview::{field_png, preview_svg, section_svg, PreviewOptions};
use pfcam::report::RunReport;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// A line on standard error that never panics: `eprintln!` does when stderr
/// is closed (`pfcam run job.toml 2>&1 | head -1` exited 101 at the next
/// progress line); a note nobody can read is dropped.
macro_rules! note {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

mod batch;
mod harmonic;
mod simulate;
mod stream;
mod stream_args;

/// Exit status: success.
pub const EXIT_OK: u8 = 0;
/// Exit status: the job, its shape or the run failed (the message says where).
pub const EXIT_FAILED: u8 = 1;
/// Exit status: the command line itself is wrong (clap's usage errors).
pub const EXIT_USAGE: u8 = 2;
/// Exit status: the output file could not be written or would overwrite a file
/// pfcam did not write (without `--force`).
pub const EXIT_OUTPUT: u8 = 3;

/// pfcam: potential-field (MFS) CNC tool paths, as G-code for GRBL 1.1.
#[derive(Debug, Parser)]
#[command(name = "pfcam", version, about, long_about = None)]
pub struct Args {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Generate the tool path of a job and write it as G-code to DIR/<name>.nc.
    /// Several jobs run in parallel and end with one table; a failing job does
    /// not stop the others.
    Run {
        /// The job files (TOML, see docs/job-format.md).
        #[arg(required = true, num_args = 1..)]
        job: Vec<PathBuf>,
        /// Directory for the output files (created if missing).
        #[arg(
            long,
            short = 'o',
            visible_alias = "output",
            value_name = "DIR",
            default_value = "out"
        )]
        out: PathBuf,
        /// Overwrite DIR/<name>.nc even if pfcam did not write it.
        #[arg(long)]
        force: bool,
        /// Print nothing but errors: no progress, no summary, no warnings (they
        /// are in the JSON report and the preview).
        #[arg(long, short)]
        quiet: bool,
        /// Lay the field's colour map under the SVG preview (a larger file).
        #[arg(long)]
        field_image: bool,
    },
    /// Run a job and write only its SVG preview (no G-code, no report).
    Preview {
        /// The job file.
        job: PathBuf,
        /// The SVG file to write (default: out/<name>.svg).
        #[arg(long, short, value_name = "FILE.svg")]
        output: Option<PathBuf>,
        /// Overwrite FILE even if pfcam did not write it.
        #[arg(long)]
        force: bool,
        /// Print nothing but errors.
        #[arg(long, short)]
        quiet: bool,
        /// Lay the field's colour map under the drawing (a larger file).
        #[arg(long)]
        field_image: bool,
        /// Equipotential values s to draw, comma separated, each in (0, 1)
        /// (default: a boss's or cavity's top edge and foot, Γ(s1) and Γ(s2);
        /// for a profile 0.9,0.95,0.98,0.99).
        #[arg(long, value_delimiter = ',')]
        levels: Option<Vec<f64>>,
    },
    /// Run a job and write its potential field as the paper's colour map (PNG).
    Field {
        /// The job file.
        job: PathBuf,
        /// The PNG file to write (default: out/<name>.png).
        #[arg(long, short, value_name = "FILE.png")]
        output: Option<PathBuf>,
        /// Overwrite FILE even if pfcam did not write it.
        #[arg(long)]
        force: bool,
        /// Print nothing but errors.
        #[arg(long, short)]
        quiet: bool,
        /// Resolution, pixels per mm.
        #[arg(long, default_value_t = 8.0)]
        px_per_mm: f64,
        /// Colours: `red-cyan` (the paper's R = uⁿ, G = B = 1 − R, material
        /// yellow), `paper` (the same with the paper's banded n, Section 3.2) or
        /// `grey` (Appendix II's col(u) = uⁿ).
        #[arg(long, default_value = "red-cyan", value_parser = ["red-cyan", "paper", "grey"])]
        map: String,
        /// The exponent n for `red-cyan` and `grey` (default: fitted so the
        /// colours span the picture).
        #[arg(long, value_name = "N")]
        power: Option<f64>,
    },
    /// Write the modelled part of a boss or cavity job (the surface S2: walls
    /// from the level curves, flat top and floor, closed by side walls and a
    /// bottom) as a watertight binary STL.
    Surface {
        /// The job file (operation.kind = "boss" or "cavity").
        job: PathBuf,
        /// The STL file to write (default: out/<name>.stl).
        #[arg(long, short, value_name = "FILE.stl")]
        output: Option<PathBuf>,
        /// Overwrite FILE even if pfcam did not write it.
        #[arg(long)]
        force: bool,
        /// Print nothing but errors.
        #[arg(long, short)]
        quiet: bool,
        /// Grid spacing, mm (the walls also get a vertex on every level curve
        /// the grid edges cross).
        #[arg(long, value_name = "MM", default_value_t = pfcam::surface::DEFAULT_RESOLUTION)]
        resolution: f64,
    },
    /// The part's cross-section at machine height Z: its rings (outlines and
    /// holes) as text, JSON or an SVG drawing. Boss and cavity jobs solve
    /// their field as `run` does; a profile's part is its shape at every z.
    Sections {
        /// The job file.
        job: PathBuf,
        /// The height, mm, machine z (the part spans stock.top − depth to
        /// stock.top).
        #[arg(long, allow_hyphen_values = true, value_name = "Z")]
        z: f64,
        /// Print the section as JSON (rings as arrays of [x, y] in mm, holes
        /// marked) instead of text.
        #[arg(long, conflicts_with = "output")]
        json: bool,
        /// Write an SVG drawing of the section instead (mm, y up).
        #[arg(long, short, value_name = "FILE.svg")]
        output: Option<PathBuf>,
        /// Overwrite FILE even if pfcam did not write it.
        #[arg(long)]
        force: bool,
    },
    /// Check a job file and its shape without running it; prints `ok: <name>`.
    Validate {
        /// The job file.
        job: PathBuf,
        /// Print nothing but errors (the exit status says whether it is valid).
        #[arg(long, short)]
        quiet: bool,
    },
    /// List the glyphs of the built-in `paper` font.
    Glyphs,
    /// The convergence study of the paper's Table 3.2 for a built-in glyph.
    Convergence {
        /// The glyph (one of `pfcam glyphs`).
        #[arg(long)]
        glyph: char,
        /// Numbers of singularities N, comma separated (M = 2N).
        #[arg(long, value_delimiter = ',', default_value = "78,148,272,396,516")]
        n: Vec<usize>,
        /// Print a JSON array of {n, m, distance, max_error} instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// The harmonic Bézier mould of a degree (Arnal–Monterde; docs/method.md
    /// §14): each inner control point P_ij of a harmonic patch as a fixed
    /// combination of the two boundary rows (P_00…P_0n | P_m0…P_mn).
    HarmonicMould {
        /// The degree n along the rows (1 to the cap, 10).
        #[arg(long)]
        degree: usize,
        /// square: n × n (for even n exact only on rows with equal n-th
        /// differences); raised: (n + 1) × n, even n only. Default: square
        /// for odd n, raised for even n.
        #[arg(long, value_parser = ["square", "raised"])]
        form: Option<String>,
        /// Print JSON: each inner point's i, j and coefficients.
        #[arg(long)]
        json: bool,
    },
    /// Stream a G-code file to a GRBL 1.1 controller over a serial port
    /// (character counting, status, feed hold on Ctrl-C, resume with --from-line).
    /// Exit codes: docs/grbl.md.
    Stream(stream_args::StreamArgs),
    /// Check a G-code file against GRBL 1.1's rules (line numbers and GRBL's
    /// error numbers), then print its bounds, lengths and estimated time.
    /// Exit 0: no errors (warnings allowed); 1: errors; 2: usage or unreadable file.
    Check {
        /// The G-code file.
        file: PathBuf,
        /// A job file or a machine file (only a `[machine]` table): rapid rate for
        /// the time, and `travel` / `work_offset` for the limit checks.
        #[arg(long, value_name = "JOB_OR_MACHINE_TOML")]
        machine: Option<PathBuf>,
        /// Print the findings and totals as JSON.
        #[arg(long)]
        json: bool,
        /// Print only the errors (no warnings, no totals).
        #[arg(long, short)]
        quiet: bool,
    },
    /// Dry-run G-code files, in order, on one height-map stock (flat, ball or
    /// bull nose end mill): rapids into material, straight plunges,
    /// engagement, air cutting and, with --job, gouges and material left
    /// against the part (docs/simulate.md). Exit 0: clean;
    /// 1: a collision, plunge, too deep a slot or a gouge; 2: usage; 3: output.
    Simulate(simulate::SimulateArgs),
}

/// Run a parsed command line. `Ok` is the exit status: `EXIT_OK`, or, for
/// `stream`, whatever its outcome maps to (it prints its own messages; see
/// `stream::ExitStatus`).
pub fn run(args: Args) -> Result<ExitCode> {
    let done = match args.command {
        Command::Run {
            job,
            out,
            force,
            quiet,
            field_image,
        } => match job.as_slice() {
            [one] => cmd_run(one, &out, force, quiet, field_image).map(|_| ()),
            many => batch::run_all(many, &out, force, quiet, field_image),
        },
        Command::Preview {
            job,
            output,
            force,
            quiet,
            field_image,
            levels,
        } => cmd_preview(&job, output, force, quiet, field_image, levels),
        Command::Field {
            job,
            output,
            force,
            quiet,
            px_per_mm,
            map,
            power,
        } => cmd_field(&job, output, force, quiet, px_per_mm, &map, power),
        Command::Surface {
            job,
            output,
            force,
            quiet,
            resolution,
        } => cmd_surface(&job, output, force, quiet, resolution),
        Command::Sections {
            job,
            z,
            json,
            output,
            force,
        } => cmd_sections(&job, z, json, output, force),
        Command::Validate { job, quiet } => cmd_validate(&job, quiet),
        Command::Glyphs => cmd_glyphs(),
        Command::Convergence { glyph, n, json } => cmd_convergence(glyph, &n, json),
        Command::Check {
            file,
            machine,
            json,
            quiet,
        } => cmd_check(&file, machine.as_deref(), json, quiet),
        Command::HarmonicMould { degree, form, json } => {
            harmonic::cmd_harmonic_mould(degree, form.as_deref(), json)
        }
        Command::Simulate(a) => simulate::cmd_simulate(&a),
        Command::Stream(a) => return Ok(stream::stream_command(&a.into())),
    };
    done.map(|()| ExitCode::from(EXIT_OK))
}

/// Whether the error is only that our reader went away (`pfcam glyphs | head -1`),
/// which, as in ripgrep, is not a failure.
pub fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// The error as one line: each cause after the first is added only when the
/// text so far does not already say it (`anyhow`'s `{:#}` repeats an I/O
/// error that a message quotes as well as holds as its source).
pub fn message(e: &anyhow::Error) -> String {
    let mut text = e.to_string();
    for cause in e.chain().skip(1) {
        let c = cause.to_string();
        if !text.contains(&c) {
            text += ": ";
            text += &c;
        }
    }
    // Whatever a message echoes (a part name, a path), never 600 kB of it.
    pfcam::job::echo::clip_message(&text)
}

/// The exit status for an error from [`run`].
pub fn exit_code(e: &anyhow::Error) -> u8 {
    if let Some(b) = e.downcast_ref::<batch::BatchFailed>() {
        b.code
    } else if e.chain().any(|c| c.is::<OutputError>()) {
        EXIT_OUTPUT
    } else if e.chain().any(|c| c.is::<UsageError>()) {
        EXIT_USAGE
    } else {
        EXIT_FAILED
    }
}

/// Load a job; errors without the file's name in them get it as context.
fn load(path: &Path) -> Result<Job> {
    load_job(path).map_err(|e| match e {
        JobError::Parse { .. } | JobError::Read { .. } | JobError::NotAJob { .. } => anyhow!(e),
        e => anyhow!(e).context(path.display().to_string()),
    })
}

fn stdout_line(s: &str) -> Result<()> {
    let mut out = std::io::stdout().lock();
    writeln!(out, "{s}").context("writing to standard output")
}

/// `pfcam sections`: text or JSON on standard output, or an SVG file
/// written atomically (a file pfcam did not write only with `--force`).
fn cmd_sections(
    path: &Path,
    z: f64,
    json: bool,
    output: Option<PathBuf>,
    force: bool,
) -> Result<()> {
    if let Some(o) = &output {
        check_output(o, "svg", force)?;
    }
    let job = load(path)?;
    let view = pipeline::section_view(&job, z, &mut |_| {})
        .map_err(|e| anyhow!("{e}"))
        .with_context(|| path.display().to_string())?;
    match output {
        Some(target) => {
            write_atomic(&target, section_svg(&view).as_bytes(), force)?;
            stdout_line(&format!(
                "wrote {}: {}, net area {:.3} mm²",
                target.display(),
                view.ring_count(),
                view.area
            ))
        }
        None if json => write_stdout(&view.json()),
        None => write_stdout(&view.text()),
    }
}

fn write_stdout(s: &str) -> Result<()> {
    let mut out = std::io::stdout().lock();
    out.write_all(s.as_bytes())
        .context("writing to standard output")
}

fn cmd_validate(path: &Path, quiet: bool) -> Result<()> {
    let job = load(path)?;
    // A composition is built by solving fields, as `run` would. The error as one
    // line: `{:#}` would repeat its source after it.
    pipeline::job_shape(&job, &mut |_| {})
        .map_err(|e| anyhow!("{e}"))
        .with_context(|| path.display().to_string())?;
    if quiet {
        return Ok(());
    }
    stdout_line(&format!("ok: {}", job.name))
}

/// What a finished run gives the batch table.
pub struct Done {
    /// The job's name.
    pub name: String,
    /// Z-levels (1 for a profile).
    pub levels: usize,
    /// Estimated machining time, s.
    pub machining_s: f64,
    /// Warnings of the run.
    pub warnings: usize,
}

/// Run one job and write its G-code, preview and report; with `quiet` nothing
/// is printed but errors.
fn cmd_run(
    path: &Path,
    out_dir: &Path,
    force: bool,
    quiet: bool,
    field_image: bool,
) -> Result<Done> {
    let job = load(path)?;
    let targets = RunTargets::of(&job, out_dir);
    targets.check(force)?;
    let mut progress = Reporter::new(quiet);
    let result = pipeline::run(&job, &mut |p| progress.event(p));
    let output = match result {
        Ok(o) => o,
        Err(e) => {
            progress.finish();
            return Err(anyhow!(e)).with_context(|| path.display().to_string());
        }
    };
    let report = RunReport::new(&job, &output);
    let (svg, gcode) = draw_and_verify(path, &job, &output, &report, field_image, &mut progress)?;
    let finish_gcode = match (&output.finish, job.finishing(), &targets.finish) {
        (Some(f), Some(fj), Some(_)) => Some(finish_program(
            path,
            &job,
            &fj,
            f,
            output.stock,
            &report,
            &gcode,
        )?),
        _ => None,
    };
    write_atomic(&targets.gcode, gcode.as_bytes(), force)?;
    if let (Some(g), Some(t)) = (&finish_gcode, &targets.finish) {
        write_atomic(t, g.as_bytes(), force)?;
    }
    write_atomic(&targets.svg, svg.as_bytes(), force)?;
    write_atomic(&targets.json, report.to_json().as_bytes(), force)?;
    if !quiet {
        for w in &output.warnings {
            note!("warning: {w}");
        }
        let mut s = summary(&job, &output, &report, out_dir);
        s += &format!(
            "\nwrote {} and {}\n{}",
            targets.svg.display(),
            targets.json.display(),
            report.table()
        );
        stdout_line(&s)?;
    }
    Ok(Done {
        name: job.name.clone(),
        // As the G-code header counts them: the distinct depths cut (a
        // profile's passes, a boss's or cavity's z-levels).
        levels: pfcam::gcode::writer::levels(&output.toolpath).len(),
        machining_s: report.programs.iter().map(|p| p.time_s).sum(),
        warnings: output.warnings.len(),
    })
}

/// The files `pfcam run` writes for a job in `DIR`: the G-code (the roughing
/// program's with a finish), the finishing program's, the SVG and the JSON.
struct RunTargets {
    gcode: PathBuf,
    finish: Option<PathBuf>,
    svg: PathBuf,
    json: PathBuf,
}

impl RunTargets {
    /// The files of `job` in `out_dir`.
    fn of(job: &Job, out_dir: &Path) -> RunTargets {
        let files = pfcam::report::program_files(job);
        RunTargets {
            gcode: out_dir.join(&files[0]),
            finish: files.get(1).map(|f| out_dir.join(f)),
            svg: out_dir.join(format!("{}.svg", job.name)),
            json: out_dir.join(format!("{}.json", job.name)),
        }
    }

    /// Refuses a file pfcam did not write (without `force`) and an unwritable
    /// directory, before the (long) run; writing checks again.
    fn check(&self, force: bool) -> Result<()> {
        for t in [&self.gcode, &self.svg, &self.json]
            .into_iter()
            .chain(self.finish.as_ref())
        {
            check_target(t, force)?;
        }
        check_writable(&self.gcode)?;
        Ok(())
    }
}

/// The preview and the G-code of a finished run, all in memory: the G-code
/// within the machine's limits and simulated (`simulate::verify_program`)
/// before any file is written; an error (nothing written) if it collides.
fn draw_and_verify(
    path: &Path,
    job: &Job,
    output: &RunOutput,
    report: &RunReport,
    field_image: bool,
    progress: &mut Reporter,
) -> Result<(String, String)> {
    progress.event(Progress::Stage {
        name: "drawing the preview and simulating the program".into(),
        total: 1,
    });
    let opts = PreviewOptions {
        levels: pfcam::preview::levels_for(job),
        field_image,
        ..PreviewOptions::default()
    };
    // The preview and the program's simulation read the same output and are
    // independent: rayon runs them side by side (a rayon join, not an OS
    // thread: a worker waiting in it keeps taking work, where a plain thread
    // join inside a batch's rayon jobs deadlocked the pool).
    let (svg, checked) = rayon::join(
        || preview_svg(job, output, report, &opts),
        || write_and_simulate(job, output, report),
    );
    let (gcode, verdict) = match checked {
        Ok(done) => done,
        Err(limit) => {
            progress.finish();
            return Err(anyhow!(limit))
                .with_context(|| format!("{}: nothing written", path.display()));
        }
    };
    progress.event(Progress::Step);
    progress.finish();
    let svg = svg.context("drawing the preview")?;
    let gcode = gcode?;
    if let Some(v) = verdict {
        v.context("simulating the program")?
            .map_err(|e| anyhow!(e))
            .with_context(|| format!("{}: nothing written", path.display()))?;
    }
    Ok((svg, gcode))
}

/// What a written program's own simulation says: `Ok(Err(_))` names the
/// unsafe moves, `Err(_)` is a simulation that could not run.
type Verdict = Result<Result<(), pfcam::simulate::UnsafeProgram>, pfcam::simulate::SimError>;

/// The roughing program's G-code and, once it is written, its simulation;
/// `Err` when the program passes the machine's limits (checked before the
/// simulation and before any file).
fn write_and_simulate(
    job: &Job,
    output: &RunOutput,
    report: &RunReport,
) -> std::result::Result<
    (
        std::result::Result<String, pfcam::gcode::GcodeError>,
        Option<Verdict>,
    ),
    pfcam::estimate::GuardError,
> {
    let gcode = write_gcode_on(&output.toolpath, job, output.stock);
    let Ok(g) = &gcode else {
        return Ok((gcode, None));
    };
    let time_s = report.programs.first().map_or(0.0, |p| p.time_s);
    pfcam::estimate::check_program(time_s, g.len(), &job.machine)?;
    let verdict = pfcam::simulate::verify_program(g, job.tool.diameter, job.tool.stepdown);
    Ok((gcode, Some(verdict)))
}

/// The finishing program `finish` of `job` (its tool's job `fj`) on the
/// run's `stock`, within the machine's limits and simulated with its own tool
/// on the stock the roughing program `rough` leaves (as `pfcam simulate
/// ROUGH FINISH` would).
fn finish_program(
    path: &Path,
    job: &Job,
    fj: &Job,
    finish: &pfcam::finish::Finished,
    stock: Option<(pfcam::geometry::Vec2, pfcam::geometry::Vec2)>,
    report: &RunReport,
    rough: &str,
) -> Result<String> {
    let g = write_gcode_on(&finish.toolpath, fj, stock)?;
    let time_s = report.programs.get(1).map_or(0.0, |p| p.time_s);
    pfcam::estimate::check_program(time_s, g.len(), &job.machine)
        .map_err(|e| anyhow!(e))
        .with_context(|| format!("{}: nothing written", path.display()))?;
    pfcam::simulate::verify_finish(rough, &g)
        .context("simulating the finishing program")?
        .map_err(|e| anyhow!(e))
        .with_context(|| format!("{}: the finishing program: nothing written", path.display()))?;
    Ok(g)
}

/// Run a job for a command that writes one file derived from the run.
fn run_quietly(path: &Path, quiet: bool) -> Result<(Job, RunOutput)> {
    let job = load(path)?;
    let mut progress = Reporter::new(quiet);
    let result = pipeline::run(&job, &mut |p| progress.event(p));
    progress.finish();
    let output = result
        .map_err(|e| anyhow!(e))
        .with_context(|| path.display().to_string())?;
    if !quiet {
        for w in &output.warnings {
            note!("warning: {w}");
        }
    }
    Ok((job, output))
}

/// A file named for another format would hold the wrong bytes: `preview -o
/// x.png` would write SVG into a `.png`.
fn require_extension(target: &Path, ext: &str) -> Result<()> {
    let given = target
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    if given.as_deref() == Some(ext) {
        return Ok(());
    }
    Err(UsageError(format!(
        "--output {}: this command writes a .{ext} file; name it *.{ext}{}",
        target.display(),
        if ext == "svg" {
            " (to get a PNG, render the SVG: cargo run --release --example render_svg -- IN.svg OUT.png 5)"
        } else {
            ""
        }
    ))
    .into())
}

/// Before a run: the output name fits the format, may be replaced, and its
/// directory takes files.
fn check_output(target: &Path, ext: &str, force: bool) -> Result<()> {
    require_extension(target, ext)?;
    check_target(target, force)?;
    check_writable(target)?;
    Ok(())
}

/// `FILE` as given, or `out/<name>.<ext>`; the job is loaded to know the name.
fn output_path(path: &Path, given: Option<PathBuf>, ext: &str) -> Result<PathBuf> {
    match given {
        Some(p) => Ok(p),
        None => Ok(Path::new("out").join(format!("{}.{ext}", load(path)?.name))),
    }
}

/// A command that writes one drawing of a run (`preview`, `field`): the
/// file (`FILE`, or out/<name>.<ext>) checked before the run, so a name
/// that cannot be written costs no run; the job run; `draw`'s bytes written
/// and, unless `quiet`, named.
fn write_drawing(
    path: &Path,
    (output, ext): (Option<PathBuf>, &str),
    (force, quiet): (bool, bool),
    draw: impl FnOnce(&Job, &RunOutput) -> Result<Vec<u8>>,
) -> Result<()> {
    let target = output_path(path, output, ext)?;
    check_output(&target, ext, force)?;
    let (job, out) = run_quietly(path, quiet)?;
    let bytes = draw(&job, &out)?;
    write_atomic(&target, &bytes, force)?;
    if !quiet {
        stdout_line(&format!("wrote {}", target.display()))?;
    }
    Ok(())
}

fn cmd_preview(
    path: &Path,
    output: Option<PathBuf>,
    force: bool,
    quiet: bool,
    field_image: bool,
    levels: Option<Vec<f64>>,
) -> Result<()> {
    if let Some(s) = levels.iter().flatten().find(|s| !(**s > 0.0 && **s < 1.0)) {
        bail!("--levels: every value must lie strictly between 0 and 1, got {s}");
    }
    // Each level is a traced curve (about 1 ms each on the letter I).
    let most = pfcam::job::limits::MAX_PREVIEW_LEVELS;
    if let Some(n) = levels.as_ref().map(Vec::len).filter(|&n| n > most) {
        bail!("--levels: give at most {most} values, got {n}");
    }
    write_drawing(path, (output, "svg"), (force, quiet), |job, out| {
        let report = RunReport::new(job, out);
        let opts = PreviewOptions {
            levels: levels.unwrap_or_else(|| pfcam::preview::levels_for(job)),
            field_image,
            ..PreviewOptions::default()
        };
        let svg = preview_svg(job, out, &report, &opts).context("drawing the preview")?;
        Ok(svg.into_bytes())
    })
}

fn cmd_field(
    path: &Path,
    output: Option<PathBuf>,
    force: bool,
    quiet: bool,
    px_per_mm: f64,
    map: &str,
    power: Option<f64>,
) -> Result<()> {
    if !(px_per_mm > 0.0 && px_per_mm <= 100.0) {
        bail!("--px-per-mm must be a number in (0, 100], got {px_per_mm}");
    }
    match (map, power) {
        (_, Some(n)) if !(n > 0.0 && n.is_finite()) => {
            bail!("--power must be a positive number, got {n}")
        }
        ("paper", Some(_)) => bail!("--power: the paper map has its own exponents"),
        _ => {}
    }
    let pick = |auto: f64| match map {
        "paper" => ColourMap::Paper,
        "grey" => ColourMap::Grey(power.unwrap_or(auto)),
        _ => ColourMap::RedCyan(power.unwrap_or(auto)),
    };
    write_drawing(path, (output, "png"), (force, quiet), |job, out| {
        field_png(job, out, px_per_mm, pick).context("drawing the field")
    })
}

fn cmd_surface(
    path: &Path,
    output: Option<PathBuf>,
    force: bool,
    quiet: bool,
    resolution: f64,
) -> Result<()> {
    use pfcam::surface::{self, SurfaceError, SurfaceOptions};
    if !(resolution > 0.0 && resolution.is_finite()) {
        bail!("--resolution must be a positive number of mm, got {resolution}");
    }
    if let Some(o) = &output {
        require_extension(o, "stl")?;
    }
    let t0 = std::time::Instant::now();
    let job = load(path)?;
    if job.operation.kind == pfcam::job::OperationKind::Profile {
        return Err(anyhow!(SurfaceError::ProfileJob)).with_context(|| path.display().to_string());
    }
    let target = output.unwrap_or_else(|| Path::new("out").join(format!("{}.stl", job.name)));
    // Refuse before the solve, and again when writing.
    let own = surface::check_stl_target(&target, force)?;
    check_writable(&target)?;
    let mut progress = Reporter::new(quiet);
    let result = surface::job_part_surface(&job, &SurfaceOptions { resolution }, &mut |p| {
        progress.event(p)
    });
    progress.finish();
    let built = result
        .map_err(|e| anyhow!(e))
        .with_context(|| path.display().to_string())?;
    let mesh = &built.mesh;
    // Never write a mesh that is not closed (it would be a pfcam bug).
    mesh.check().map_err(|e| {
        anyhow!("internal error: the surface mesh is not watertight: {e} (please report this pfcam bug)")
    })?;
    let bytes = surface::stl_bytes(mesh, &job.name);
    // And the file as a viewer will read it: its 32-bit vertices welded.
    surface::read_stl(&bytes)
        .and_then(|(_, tris)| surface::weld(&tris).check())
        .map_err(|e| {
            anyhow!("internal error: the STL is not watertight: {e} (please report this pfcam bug)")
        })?;
    write_atomic(&target, &bytes, force || own)?;
    if !quiet {
        let (lo, hi) = mesh.bbox().unwrap_or(([0.0; 3], [0.0; 3]));
        stdout_line(&format!(
            "wrote {}: {} triangles, {} vertices, box x {:.3}..{:.3} y {:.3}..{:.3} z {:.3}..{:.3} mm, volume {:.1} mm³, watertight, {:.2} s",
            target.display(),
            mesh.triangles.len(),
            mesh.vertices.len(),
            lo[0],
            hi[0],
            lo[1],
            hi[1],
            lo[2],
            hi[2],
            mesh.volume(),
            t0.elapsed().as_secs_f64()
        ))?;
    }
    Ok(())
}

/// The report printed after a run.
fn summary(job: &Job, out: &RunOutput, report: &RunReport, out_dir: &Path) -> String {
    let mut s = String::new();
    for p in &report.programs {
        s += &format!("wrote {}\n", out_dir.join(&p.file).display());
    }
    s += &format!("glyphs: {}\n", out.glyphs.join(", "));
    for font in job.shape.font_files() {
        s += &format!("font: {}\n", font.describe());
    }
    for r in &out.solves {
        s += &format!(
            "solve {}: N {}, M {}, pseudo-boundary {:.3} mm, max boundary error {:.2e}\n",
            r.label, r.n, r.m, r.distance, r.max_error
        );
    }
    for p in &report.programs {
        s += &program_line(p, job.machine.rapid_rate);
    }
    s += &format!(
        "gouge check: min clearance {:.4} mm (tolerance {} mm)",
        out.min_clearance, job.operation.tolerance
    );
    if !out.warnings.is_empty() {
        s += &format!("\n{} warning(s), see above", out.warnings.len());
    }
    s
}

/// A program's lengths and time (its header's), its lower bound and their ratio.
fn program_line(p: &pfcam::report::ProgramReport, rapid_rate: f64) -> String {
    let ratio = p
        .time_over_bound
        .map_or("-".to_string(), |r| format!("{r:.2}"));
    format!(
        "program {}: {:.1} mm cutting, {:.1} mm rapid, estimated time {} (rapids at {rapid_rate} mm/min, acceleration ignored); lower bound {} (clearing {}, outlines {}), estimate / bound {ratio}\n",
        p.file,
        p.cut_length_mm,
        p.rapid_length_mm,
        format_duration(p.time_s),
        format_duration(p.lower_bound_s),
        format_duration(p.lower_bound_clearing_s),
        format_duration(p.lower_bound_outline_s),
    )
}

/// Shows `Progress` events: a bar with an ETA when stderr is a terminal;
/// otherwise plain lines (a stage's start, then its progress at most every
/// [`LINE_EVERY`] seconds and at its end, with the time left); nothing when quiet.
struct Reporter {
    quiet: bool,
    terminal: bool,
    bar: Option<ProgressBar>,
    stage: Option<Stage>,
}

/// The stage being shown as plain lines.
struct Stage {
    name: String,
    total: u64,
    done: u64,
    started: std::time::Instant,
    last_line: std::time::Instant,
}

/// Seconds between plain progress lines.
const LINE_EVERY: f64 = 5.0;

impl Reporter {
    fn new(quiet: bool) -> Self {
        Reporter {
            quiet,
            terminal: std::io::stderr().is_terminal(),
            bar: None,
            stage: None,
        }
    }

    fn event(&mut self, p: Progress) {
        if self.quiet {
            return;
        }
        match (p, self.terminal) {
            (Progress::Stage { name, total }, true) => {
                if let Some(b) = self.bar.take() {
                    b.finish_and_clear();
                }
                let style = ProgressStyle::with_template(
                    "{msg:32} [{bar:32}] {pos}/{len} {elapsed_precise}, about {eta} left",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> ");
                self.bar = Some(ProgressBar::new(total).with_style(style).with_message(name));
            }
            (Progress::Step, true) => {
                if let Some(b) = &self.bar {
                    b.inc(1);
                }
            }
            (Progress::Stage { name, total }, false) => {
                note!("{name} ({total} steps)");
                let now = std::time::Instant::now();
                self.stage = Some(Stage {
                    name,
                    total,
                    done: 0,
                    started: now,
                    last_line: now,
                });
            }
            (Progress::Step, false) => {
                if let Some(st) = &mut self.stage {
                    st.done += 1;
                    let now = std::time::Instant::now();
                    let last = st.done == st.total;
                    if st.total > 1 && (last || (now - st.last_line).as_secs_f64() >= LINE_EVERY) {
                        st.last_line = now;
                        let spent = (now - st.started).as_secs_f64();
                        let left = spent / st.done as f64 * st.total.saturating_sub(st.done) as f64;
                        note!(
                            "{}: {}/{} after {:.0} s, about {:.0} s left",
                            st.name,
                            st.done,
                            st.total,
                            spent,
                            left
                        );
                    }
                }
            }
        }
    }

    fn finish(&mut self) {
        if let Some(b) = self.bar.take() {
            b.finish_and_clear();
        }
        self.stage = None;
    }
}

/// Largest G-code file `check` reads: far above any program GRBL could run in
/// a day, and a bound for `/dev/zero` or a disk image given by mistake.
const MAX_GCODE_BYTES: u64 = 2 << 30;

/// The bytes of a G-code file, bounded by [`MAX_GCODE_BYTES`]; a file that
/// cannot be read is a usage error (exit 2).
fn read_gcode_file(file: &Path) -> Result<Vec<u8>> {
    use std::io::Read;
    let unreadable = |e: std::io::Error| UsageError(format!("cannot read {}: {e}", file.display()));
    if file.is_dir() {
        return Err(UsageError(format!(
            "{} is a directory, not a G-code file",
            file.display()
        ))
        .into());
    }
    let mut bytes = Vec::new();
    std::fs::File::open(file)
        .map_err(unreadable)?
        .take(MAX_GCODE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(unreadable)?;
    if bytes.len() as u64 > MAX_GCODE_BYTES {
        return Err(UsageError(format!(
            "{} is larger than {} GiB: not a G-code file pfcam will read",
            file.display(),
            MAX_GCODE_BYTES >> 30
        ))
        .into());
    }
    Ok(bytes)
}

/// A command given something it cannot use (an unreadable file): exit 2.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
struct UsageError(String);

fn cmd_check(file: &Path, machine: Option<&Path>, json: bool, quiet: bool) -> Result<()> {
    use pfcam::gcode::check::{check_gcode, CheckOptions, Limits, Severity};
    use pfcam::job::{load_machine, MachineSource};

    let mut opts = CheckOptions::default();
    if let Some(path) = machine {
        let (m, source) = load_machine(path).map_err(|e| UsageError(format!("--machine: {e}")))?;
        opts.rapid_rate = m.rapid_rate;
        opts.limits = m.travel.map(|travel| Limits {
            travel,
            work_offset: m.work_offset,
        });
        if m.travel.is_none() && !quiet {
            let what = match source {
                MachineSource::Job => "job file",
                MachineSource::MachineFile => "machine file",
            };
            note!(
                "note: {what} {} has no machine.travel: travel limits not checked",
                path.display()
            );
        }
    }
    let bytes = read_gcode_file(file)?;
    // GRBL reads bytes; a stray non-UTF-8 byte becomes U+FFFD and then error 1.
    let text = String::from_utf8_lossy(&bytes);
    let name = file.display().to_string();
    if text.trim().is_empty() {
        bail!("{name} is empty: there is no G-code to check");
    }
    let report = check_gcode(&text, &opts);
    if json {
        let v = serde_json::json!({
            "file": name,
            "errors": report.errors(),
            "warnings": report.warnings(),
            "findings": report.findings,
            "totals": report.totals,
        });
        stdout_line(&serde_json::to_string_pretty(&v)?)?;
    } else if quiet {
        let mut s = String::new();
        for f in report
            .findings
            .iter()
            .filter(|f| f.severity == Severity::Error)
        {
            s += &format!("{name}:{}: {f}\n", f.line);
        }
        if !s.is_empty() {
            stdout_line(s.trim_end())?;
        }
    } else {
        let mut s = String::new();
        for f in &report.findings {
            s += &format!("{name}:{}: {f}\n", f.line);
        }
        s += &report.totals.to_string();
        s += &format!(
            "\n{name}: {} error(s), {} warning(s)",
            report.errors(),
            report.warnings()
        );
        stdout_line(&s)?;
    }
    if report.errors() > 0 {
        bail!("{name}: {} error(s)", report.errors());
    }
    Ok(())
}

fn cmd_glyphs() -> Result<()> {
    let chars = paper_chars();
    if chars.is_empty() {
        bail!(
            "internal error: the built-in paper font did not load (please report this pfcam bug)"
        );
    }
    let mut s = String::from("font paper (the paper's Times letters, cap height 662 units):");
    for c in chars {
        s += &format!("\n{c}");
    }
    stdout_line(&s)
}

fn cmd_convergence(glyph: char, ns: &[usize], json: bool) -> Result<()> {
    let have = paper_chars();
    if !have.contains(&glyph) {
        let list: String = have.iter().collect();
        bail!("--glyph: the paper font has no glyph {glyph:?} (it has {list})");
    }
    let max = pfcam::job::limits::MAX_SINGULARITIES;
    if ns.is_empty() || ns.iter().any(|&n| n == 0 || n > max) {
        bail!("--n: give one or more counts in [1, {max}], e.g. --n 78,148,272");
    }
    // Each count is a dense solve (minutes near the largest N): a study is a
    // handful of them, not a list pasted by mistake.
    let most = pfcam::job::limits::MAX_STUDY_COUNTS;
    if ns.len() > most {
        bail!("--n: give at most {most} counts, got {}", ns.len());
    }
    let rows = pfcam::field::convergence_table(glyph, ns)
        .with_context(|| format!("convergence study of {glyph:?}"))?;
    if json {
        return stdout_line(&serde_json::to_string_pretty(&rows)?);
    }
    let mut s = format!(
        "{:>6} {:>6} {:>14} {:>12}",
        "N", "M", "distance (fu)", "max error"
    );
    for r in rows {
        s += &format!(
            "\n{:>6} {:>6} {:>14.2} {:>12.3e}",
            r.n, r.m, r.distance, r.max_error
        );
    }
    stdout_line(&s)
}
