//! The field as a colour image (the paper's Appendix II) and its PNG encoding.
//!
//! The plane is covered by a grid; u is evaluated at the grid vertices and turned
//! into a colour col(u); a pixel at parameters (t, s) of its cell with vertices
//! P0 (lower left), P1 (lower right), P2 (upper right), P3 (upper left) gets
//!
//! C = (1 − s)[(1 − t) col(u(P0)) + t col(u(P1))] + s[(1 − t) col(u(P3)) + t col(u(P2))],
//!
//! the bilinear interpolation of the vertex colours. The paper's col is a power
//! col(u) = uⁿ; its colour figures (Section 3.2) use R = uⁿ, G = B = 1 − R for
//! u < 0.9999 and yellow (R = G = 1, B = 0) above, with n = 500 for
//! 0.995 < u ≤ 1, 100 for 0.99 < u ≤ 0.995, 50 for 0.989 < u ≤ 0.99 and 5
//! otherwise ([`ColourMap::Paper`]). Those bands resolve u to 1e-4 near the part,
//! finer than our fields' boundary error, so the default is the same colours
//! with one exponent fitted to the picture ([`ColourMap::RedCyan`] with
//! [`auto_exponent`]). Grid vertices inside the material are not evaluated (the
//! MFS singularities are there) and take the material colour.

use crate::field::isolines::material_mask;
use crate::field::Field;
use crate::geometry::Vec2;
use rayon::prelude::*;

/// How u becomes a colour. Grid vertices in the material (not evaluated) show
/// [`ColourMap::material`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ColourMap {
    /// The paper's colour figures: R = uⁿ with n by band (5, 50, 100, 500, see
    /// [`paper_exponent`]), G = B = 1 − R, the material yellow. The paper paints
    /// every u ≥ 0.9999 yellow, which on its fields is the letter; here yellow is
    /// kept for the material (a field whose error passes 1e-4 would otherwise
    /// paint void, e.g. a counter, as material), and void with u ≥ 0.9999 takes
    /// the colour of u = 0.9999, the reddest band.
    Paper,
    /// The paper's colours with one exponent: R = uⁿ, G = B = 1 − R, the material
    /// yellow. [`auto_exponent`] picks n for the pictured rectangle.
    RedCyan(f64),
    /// Appendix II's grey scale col(u) = (uⁿ, uⁿ, uⁿ) (the paper found
    /// 1 ≤ n ≤ 50 useful); the material white (u = 1).
    Grey(f64),
}

/// The u from which the paper paints yellow (its letters).
const PAPER_YELLOW_FROM: f64 = 0.9999;

impl ColourMap {
    /// The colour of u (RGB in [0, 1]) at a point outside the material; u is
    /// clamped to [0, 1], a non-finite u is taken as 0.
    pub(crate) fn colour(self, u: f64) -> [f64; 3] {
        let u = if u.is_finite() {
            u.clamp(0.0, 1.0)
        } else {
            0.0
        };
        match self {
            ColourMap::Paper => {
                let u = u.min(PAPER_YELLOW_FROM);
                let r = u.powf(paper_exponent(u));
                [r, 1.0 - r, 1.0 - r]
            }
            ColourMap::RedCyan(n) => {
                let r = u.powf(n);
                [r, 1.0 - r, 1.0 - r]
            }
            ColourMap::Grey(n) => {
                let g = u.powf(n);
                [g, g, g]
            }
        }
    }

    /// The colour of the material (u = 1 on its boundary).
    pub(crate) fn material(self) -> [f64; 3] {
        match self {
            ColourMap::Paper | ColourMap::RedCyan(_) => [1.0, 1.0, 0.0],
            ColourMap::Grey(_) => [1.0, 1.0, 1.0],
        }
    }
}

/// Red at this level: [`auto_exponent`] makes R = uⁿ fall to it at the smallest
/// u in the picture, so the colours span the whole rectangle.
pub(crate) const AUTO_FLOOR: f64 = 0.02;

/// The exponent n with u_minⁿ = [`AUTO_FLOOR`], u_min the smallest u in (0, 1) on
/// the rectangle's border and corners (u falls away from the part, so its minimum
/// over the rectangle is on the border), clamped to [1, 500].
pub(crate) fn auto_exponent(field: &Field, lo: Vec2, hi: Vec2) -> f64 {
    let mut u_min: f64 = 1.0;
    let k = 64;
    for i in 0..=k {
        let t = i as f64 / k as f64;
        for p in [
            Vec2::new(lo.x + t * (hi.x - lo.x), lo.y),
            Vec2::new(lo.x + t * (hi.x - lo.x), hi.y),
            Vec2::new(lo.x, lo.y + t * (hi.y - lo.y)),
            Vec2::new(hi.x, lo.y + t * (hi.y - lo.y)),
        ] {
            let u = field.value(p);
            if u.is_finite() && u > 0.0 {
                u_min = u_min.min(u);
            }
        }
    }
    if u_min >= 1.0 {
        return 500.0;
    }
    (AUTO_FLOOR.ln() / u_min.ln()).clamp(1.0, 500.0)
}

/// The paper's exponent n for level u (Section 3.2, found experimentally there).
pub(crate) fn paper_exponent(u: f64) -> f64 {
    if u > 0.995 {
        500.0
    } else if u > 0.99 {
        100.0
    } else if u > 0.989 {
        50.0
    } else {
        5.0
    }
}

/// What to draw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FieldImageSpec {
    /// Lower-left corner of the pictured rectangle, mm.
    pub(crate) lo: Vec2,
    /// Upper-right corner, mm.
    pub(crate) hi: Vec2,
    /// Resolution, pixels per mm.
    pub(crate) px_per_mm: f64,
    /// Grid vertices every this many pixels (u is evaluated there only; ≥ 1).
    pub(crate) step_px: usize,
    /// The colour map.
    pub(crate) map: ColourMap,
}

/// The largest image [`field_image`] makes, in pixels (a 8000 × 8000 picture).
pub(crate) const MAX_PIXELS: u64 = 64_000_000;

/// A field image [`field_image`] refuses to draw.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ImageError {
    /// Pixels per mm not a positive finite number, or vertices every 0 px.
    #[error("resolution must be positive, got {px_per_mm} px/mm, vertices every {step_px} px")]
    Resolution {
        /// The resolution asked for, pixels per mm.
        px_per_mm: f64,
        /// The vertex step asked for, pixels.
        step_px: usize,
    },
    /// The rectangle has no width or no height.
    #[error("the pictured rectangle is empty")]
    EmptyRectangle,
    /// More than [`MAX_PIXELS`] pixels.
    #[error("{width} × {height} pixels is too large (at most {MAX_PIXELS}); lower the resolution")]
    TooLarge {
        /// The picture's width, pixels (a whole number).
        width: f64,
        /// Its height, pixels (a whole number).
        height: f64,
    },
}

/// An image [`encode_png`] could not encode.
#[derive(Debug, thiserror::Error)]
#[error("PNG encoding: {0}")]
pub struct PngError(#[from] png::EncodingError);

/// An RGB image, 8 bits per channel, rows from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Rgb8 {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major RGB bytes, the first row at the top (largest y).
    pub data: Vec<u8>,
}

/// Render the field over `spec` (see the module docs). `polys` are the part's
/// flattened contours (material on the left), used as the mask.
pub(crate) fn field_image(
    field: &Field,
    polys: &[Vec<Vec2>],
    spec: &FieldImageSpec,
) -> Result<Rgb8, ImageError> {
    let FieldImageSpec {
        lo,
        hi,
        px_per_mm,
        step_px,
        map,
    } = *spec;
    if !(px_per_mm > 0.0 && px_per_mm.is_finite()) || step_px == 0 {
        return Err(ImageError::Resolution { px_per_mm, step_px });
    }
    if !(hi.x > lo.x && hi.y > lo.y) {
        return Err(ImageError::EmptyRectangle);
    }
    let w = ((hi.x - lo.x) * px_per_mm).round().max(1.0);
    let h = ((hi.y - lo.y) * px_per_mm).round().max(1.0);
    if w * h > MAX_PIXELS as f64 {
        return Err(ImageError::TooLarge {
            width: w,
            height: h,
        });
    }
    let (w, h) = (w as usize, h as usize);
    // Vertices cover the pixel centres: vertex (a, b) sits at pixel (a·step, b·step)
    // counted from the bottom-left pixel centre.
    let gx = (w - 1).div_ceil(step_px) + 1;
    let gy = (h - 1).div_ceil(step_px) + 1;
    let px = 1.0 / px_per_mm;
    let pixel_centre = |i: f64, j_from_bottom: f64| {
        Vec2::new(lo.x + (i + 0.5) * px, lo.y + (j_from_bottom + 0.5) * px)
    };
    let mask = material_mask(polys);
    let colours: Vec<[f64; 3]> = (0..gy)
        .into_par_iter()
        .flat_map_iter(|b| {
            let mask = &mask;
            (0..gx).map(move |a| {
                let p = pixel_centre((a * step_px) as f64, (b * step_px) as f64);
                if mask(p) {
                    map.material()
                } else {
                    map.colour(field.value(p))
                }
            })
        })
        .collect();
    let vertex = |a: usize, b: usize| colours[b.min(gy - 1) * gx + a.min(gx - 1)];
    let rows: Vec<Vec<u8>> = (0..h)
        .into_par_iter()
        .map(|row| {
            let jb = h - 1 - row; // pixel row counted from the bottom
            let (b, s) = (jb / step_px, (jb % step_px) as f64 / step_px as f64);
            let mut out = Vec::with_capacity(3 * w);
            for i in 0..w {
                let (a, t) = (i / step_px, (i % step_px) as f64 / step_px as f64);
                let (c0, c1, c2, c3) = (
                    vertex(a, b),
                    vertex(a + 1, b),
                    vertex(a + 1, b + 1),
                    vertex(a, b + 1),
                );
                for k in 0..3 {
                    let c = (1.0 - s) * ((1.0 - t) * c0[k] + t * c1[k])
                        + s * ((1.0 - t) * c3[k] + t * c2[k]);
                    out.push((c * 255.0).round().clamp(0.0, 255.0) as u8);
                }
            }
            out
        })
        .collect();
    Ok(Rgb8 {
        width: w as u32,
        height: h as u32,
        data: rows.concat(),
    })
}

/// The text pfcam puts in every PNG it writes, as its `Software` chunk; that is
/// how pfcam recognises its own PNG files (see `output`).
pub(crate) fn png_software() -> String {
    crate::report::generator()
}

/// Encode as PNG with a `Software` text chunk (`pfcam <version>`) and a `Title`.
pub fn encode_png(img: &Rgb8, title: &str) -> Result<Vec<u8>, PngError> {
    let mut buf = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut buf, img.width, img.height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.add_text_chunk("Software".into(), png_software())?;
        // tEXt is Latin-1: keep the title to printable ASCII.
        let title: String = title
            .chars()
            .map(|c| {
                if c.is_ascii_graphic() || c == ' ' {
                    c
                } else {
                    '?'
                }
            })
            .collect();
        enc.add_text_chunk("Title".into(), title)?;
        let mut writer = enc.write_header()?;
        writer.write_image_data(&img.data)?;
        writer.finish()?;
    }
    Ok(buf)
}

/// Standard base64 (RFC 4648, with padding), for a PNG embedded in an SVG.
pub(crate) fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for ch in bytes.chunks(3) {
        let b = [ch[0], *ch.get(1).unwrap_or(&0), *ch.get(2).unwrap_or(&0)];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= ch.len() {
                s.push(A[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The refusals' texts are the strings they were, number formats too.
    #[test]
    fn image_errors_say_what_the_strings_said() {
        let (px_per_mm, step_px, w, h) = (-0.5, 0usize, 9000.0, 8000.0);
        let cases = [
            (ImageError::Resolution { px_per_mm, step_px }, format!("resolution must be positive, got {px_per_mm} px/mm, vertices every {step_px} px")),
            (ImageError::EmptyRectangle, "the pictured rectangle is empty".to_string()),
            (ImageError::TooLarge { width: w, height: h }, format!("{w} × {h} pixels is too large (at most {MAX_PIXELS}); lower the resolution")),
        ];
        for (e, text) in cases {
            assert_eq!(e.to_string(), text);
        }
    }

    #[test]
    fn base64_matches_rfc4648_vectors() {
        for (i, o) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(i.as_bytes()), o);
        }
    }

    #[test]
    fn paper_colours() {
        // Void never takes the material's yellow, however close u is to 1.
        let top = ColourMap::Paper.colour(0.9999);
        assert!(top[0] > 0.95 && top[2] < 0.05, "{top:?}");
        assert_eq!(ColourMap::Paper.colour(1.0), top);
        assert_ne!(ColourMap::Paper.colour(1.0), ColourMap::Paper.material());
        assert_eq!(ColourMap::Paper.material(), [1.0, 1.0, 0.0]);
        assert_eq!(ColourMap::Paper.colour(0.0), [0.0, 1.0, 1.0]);
        let c = ColourMap::Paper.colour(0.5);
        assert!((c[0] - 0.5f64.powi(5)).abs() < 1e-15 && c[1] == 1.0 - c[0]);
        let c = ColourMap::Paper.colour(0.996);
        assert!((c[0] - 0.996f64.powi(500)).abs() < 1e-12);
        assert_eq!(ColourMap::Grey(2.0).colour(0.5), [0.25; 3]);
        assert_eq!(ColourMap::Grey(2.0).colour(f64::NAN), [0.0; 3]);
        assert_eq!(ColourMap::RedCyan(2.0).colour(0.5), [0.25, 0.75, 0.75]);
        assert_eq!(ColourMap::RedCyan(2.0).material(), [1.0, 1.0, 0.0]);
    }

    #[test]
    fn auto_exponent_spans_the_picture() {
        // u = 0.1 ln r; on [2, 4] × [−1, 1] its minimum is at (2, 0), on the border.
        let f = Field::new(vec![Vec2::ZERO], vec![-0.1 * std::f64::consts::TAU]);
        let n = auto_exponent(&f, Vec2::new(2.0, -1.0), Vec2::new(4.0, 1.0));
        let u_min = 0.1 * 2f64.ln();
        assert!((u_min.powf(n) - AUTO_FLOOR).abs() < 1e-12, "n {n}");
        // No u in (0, 1) on the border: nothing to span, the largest n.
        let flat = Field::new(vec![Vec2::ZERO], vec![0.0]);
        assert_eq!(
            auto_exponent(&flat, Vec2::new(2.0, -1.0), Vec2::new(4.0, 1.0)),
            500.0
        );
    }

    /// A far charge gives u ≈ 0.55 growing to the right; with col(u) = u a vertex
    /// pixel shows u there exactly, and the bilinear blend keeps rows monotone.
    #[test]
    fn image_is_the_bilinear_interpolant_of_vertex_colours() {
        let f = Field::new(vec![Vec2::new(-1000.0, 0.0)], vec![-0.5]);
        let spec = FieldImageSpec {
            lo: Vec2::new(0.0, 0.0),
            hi: Vec2::new(10.0, 5.0),
            px_per_mm: 4.0,
            step_px: 4,
            map: ColourMap::Grey(1.0),
        };
        let img = field_image(&f, &[], &spec).unwrap();
        assert_eq!((img.width, img.height), (40, 20));
        assert_eq!(img.data.len(), 40 * 20 * 3);
        let px = |i: usize, row: usize| img.data[3 * (row * 40 + i)];
        // u = (1/2π) ln r grows to the right (r from the charge at x = −1000).
        for row in 0..20 {
            for i in 0..39 {
                assert!(px(i, row) <= px(i + 1, row));
            }
        }
        let u = f.value(Vec2::new(0.125 + 8.0 * 0.25, 0.125));
        let want = (u.clamp(0.0, 1.0) * 255.0).round() as u8;
        assert_eq!(px(8, 19), want);
    }

    #[test]
    fn png_round_trips_with_its_marker() {
        let img = Rgb8 {
            width: 3,
            height: 2,
            data: (0..18).map(|k| k as u8 * 10).collect(),
        };
        let bytes = encode_png(&img, "job x").unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        let needle = format!("tEXtSoftware\0{}", png_software());
        assert!(bytes.windows(needle.len()).any(|w| w == needle.as_bytes()));
        let dec = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut r = dec.read_info().unwrap();
        let mut out = vec![0; r.output_buffer_size().unwrap()];
        let info = r.next_frame(&mut out).unwrap();
        assert_eq!((info.width, info.height), (3, 2));
        assert_eq!(&out[..info.buffer_size()], &img.data[..]);
    }
}
