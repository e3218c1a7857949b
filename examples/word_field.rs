//! The field of a word solved letter by letter (`field::blocks`), with the
//! time, each letter's N and errors, the coupling's sweeps and the word's
//! max boundary error.
//! `cargo run --release --example word_field -- FONT.ttf|paper "TEXT" [TARGET] [HEIGHT]`
use std::path::Path;
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let font = args
        .next()
        .expect("usage: word_field FONT TEXT [TARGET] [HEIGHT]");
    let text = args.next().expect("TEXT");
    let target: f64 = args.next().map_or(1e-6, |s| s.parse().expect("TARGET"));
    let height: f64 = args.next().map_or(50.0, |s| s.parse().expect("HEIGHT"));
    let font_key = if font == "paper" {
        "\"paper\"".to_string()
    } else {
        let abs = std::fs::canonicalize(&font).expect("font file");
        format!("{:?}", abs.display().to_string())
    };
    let toml = format!(
        "[shape]\ntext = {text:?}\nfont = {font_key}\nheight = {height}\n[tool]\ndiameter = 3.175\n[operation]\nkind = \"profile\"\ndepth = 3.0\n"
    );
    let job = pfcam::job::parse_job(&toml, "word", Path::new(".")).expect("job");
    let (shape, _) = pfcam::pipeline::job_shape(&job, &mut |_| {}).expect("shape");
    let t = Instant::now();
    let solved = pfcam::pipeline::solve_word(&shape, 0.25 * job.operation.tolerance, target, None)
        .expect("solve");
    let dt = t.elapsed().as_secs_f64();
    for (i, l) in solved.letters.iter().enumerate() {
        println!(
            "{:>4}  N {:5}  alone {:.2e}  in the word {:.2e}",
            i + 1,
            l.n,
            l.alone,
            l.in_word
        );
    }
    println!(
        "{} letters, N {} in all, M {}, {} sweeps, residual {:.2e}, max boundary error {:.2e}, {:.2} s",
        solved.letters.len(),
        solved.n,
        solved.m,
        solved.sweeps,
        solved.residual,
        solved.solution.max_error,
        dt
    );
}
