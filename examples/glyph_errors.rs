//! The shape field's solve for single characters of a font, one by one, with
//! the tightest target (1e-6, a boss whose top is the glyph): N reached, the
//! max boundary error on the check points, and the time.
//! `cargo run --release --example glyph_errors -- tests/data/DejaVuSerif.ttf [CHARS]`
//! (CHARS defaults to A-Z a-z 0-9; the font `paper` gives the paper's letters).
use std::path::Path;
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let font = args
        .next()
        .expect("usage: glyph_errors FONT.ttf|paper [CHARS]");
    let chars: String = args.next().unwrap_or_else(|| {
        ('A'..='Z')
            .chain('a'..='z')
            .chain('0'..='9')
            .collect::<String>()
    });
    let font_key = if font == "paper" {
        "\"paper\"".to_string()
    } else {
        let abs = std::fs::canonicalize(&font).unwrap_or_else(|e| panic!("{font}: {e}"));
        format!("{:?}", abs.display().to_string())
    };
    let mut worst: f64 = 0.0;
    let mut times = Vec::new();
    for c in chars.chars() {
        let text = format!(
            "[shape]\ntext = {:?}\nfont = {font_key}\nheight = 50.0\n[tool]\ndiameter = 3.175\n[operation]\nkind = \"boss\"\ndepth = 3.0\n[profile]\nkind = \"linear\"\ns_bottom = 0.9\n",
            c.to_string()
        );
        let job = pfcam::job::parse_job(&text, "glyph", Path::new("."))
            .unwrap_or_else(|e| panic!("{c}: {e}"));
        let t = Instant::now();
        let (shape, _) =
            pfcam::pipeline::job_shape(&job, &mut |_| {}).unwrap_or_else(|e| panic!("{c}: {e}"));
        let tol = job.operation.tolerance * 0.25;
        match pfcam::pipeline::solve_shape(&shape, &job, tol, &mut |_| {}) {
            Ok((_, rep, _)) => {
                let dt = t.elapsed().as_secs_f64();
                times.push(dt);
                worst = worst.max(rep.max_error);
                println!(
                    "{c}  N {:5}  max error {:.2e}  {:.2} s",
                    rep.n, rep.max_error, dt
                );
            }
            Err(e) => println!("{c}  failed: {e}"),
        }
    }
    times.sort_by(f64::total_cmp);
    if !times.is_empty() {
        println!(
            "worst max error {worst:.2e}; median time {:.2} s over {} glyphs",
            times[times.len() / 2],
            times.len()
        );
    }
}
