//! Render an SVG (e.g. a pfcam preview) to PNG with resvg, to look at it or to
//! make the README's image:
//!
//! ```sh
//! cargo run --release --example render_svg -- out/mfs-sign.svg docs/preview.png 6
//! ```
//!
//! The last argument is pixels per mm (default 6). Fonts: the system's DejaVu
//! Sans if present, else the test font `tests/data/DejaVuSerif.ttf`.

use pfcam::preview::colormap::{encode_png, Rgb8};
use resvg::{tiny_skia, usvg};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [svg_path, png_path, rest @ ..] = args.as_slice() else {
        return Err("usage: render_svg IN.svg OUT.png [px_per_mm]".into());
    };
    let px_per_mm: f32 = rest.first().map_or(Ok(6.0), |s| s.parse())?;
    let svg = std::fs::read_to_string(svg_path)?;
    let mut opt = usvg::Options::default();
    let db = opt.fontdb_mut();
    for f in ["DejaVuSans.ttf", "DejaVuSans-Bold.ttf"] {
        if let Ok(bytes) = std::fs::read(format!("/usr/share/fonts/truetype/dejavu/{f}")) {
            db.load_font_data(bytes);
        }
    }
    db.load_font_data(std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/DejaVuSerif.ttf"
    ))?);
    let family = if db
        .faces()
        .any(|f| f.families.iter().any(|(n, _)| n == "DejaVu Sans"))
    {
        "DejaVu Sans"
    } else {
        "DejaVu Serif"
    };
    db.set_sans_serif_family(family);
    let tree = usvg::Tree::from_str(&svg, &opt)?;
    // usvg sizes the tree in CSS px (96 per inch); scale to the wanted px per mm.
    let k = px_per_mm / (96.0 / 25.4);
    let size = tree.size();
    let (w, h) = (
        (size.width() * k).ceil() as u32,
        (size.height() * k).ceil() as u32,
    );
    let mut pixmap = tiny_skia::Pixmap::new(w, h).ok_or("empty image")?;
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        tiny_skia::Transform::from_scale(k, k),
        &mut pixmap.as_mut(),
    );
    let data: Vec<u8> = pixmap
        .data()
        .chunks(4)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    let png = encode_png(
        &Rgb8 {
            width: w,
            height: h,
            data,
        },
        svg_path,
    )?;
    std::fs::write(png_path, png)?;
    println!("{png_path}: {w} x {h} px");
    Ok(())
}
