//! A harmonic Bézier patch's control net and height range (docs/method.md §14):
//! `cargo run --release --example harmonic_patch -- DEGREE X Y ROW0 ROW1`,
//! rows as comma-separated heights in mm, e.g.
//! `-- 3 40 40 0,0,0,0 0,10,10,0`. Even degrees use the raised form.

use pfcam::sources::harmonic_bezier::{Form, HarmonicPatch};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [degree, x, y, row0, row1] = args.as_slice() else {
        return Err("usage: DEGREE X Y ROW0 ROW1 (rows comma-separated)".into());
    };
    let degree: usize = degree.parse()?;
    let row = |s: &str| -> Result<Vec<f64>, std::num::ParseFloatError> {
        s.split(',').map(str::parse).collect()
    };
    let form = if degree % 2 == 0 {
        Form::Raised
    } else {
        Form::Square
    };
    let p = HarmonicPatch::new(
        degree,
        form,
        [x.parse()?, y.parse()?],
        &row(row0)?,
        &row(row1)?,
    )?;
    println!("control net (row i = 0 is y = 0):");
    for r in p.heights().chunks(degree + 1) {
        let cells: Vec<String> = r.iter().map(|h| format!("{h:9.4}")).collect();
        println!("  {}", cells.join(" "));
    }
    let r = p.height_range();
    println!(
        "height range: {:.4} at ({:.3}, {:.3}) to {:.4} at ({:.3}, {:.3}) mm",
        r.min, r.argmin[0], r.argmin[1], r.max, r.argmax[0], r.argmax[1]
    );
    Ok(())
}
