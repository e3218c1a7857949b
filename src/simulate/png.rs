//! The final stock as a picture: height as colour (the uncut top pale, the
//! deepest cut dark blue), seen from above with +y up, and a red cross on
//! every collision (rapid into material, straight plunge, gouge).

use super::report::{Finding, Kind};
use super::stock::HeightMap;
#[cfg(test)]
use super::Simulation;
use super::{Sequence, SimError};
use crate::preview::colormap::{encode_png, Rgb8};

/// The longest side of the picture, pixels: a larger stock is drawn with one
/// pixel per block of cells (the block's lowest height).
pub(crate) const MAX_SIDE: usize = 2000;
/// A small stock is drawn with blocks of pixels per cell, to at least this.
pub(crate) const MIN_SIDE: usize = 600;

/// Colour of a height: `t` = 0 at the deepest cut, 1 at the top.
fn colour(t: f64) -> [u8; 3] {
    const STOPS: [(f64, [f64; 3]); 4] = [
        (0.0, [20.0, 30.0, 110.0]),
        (0.4, [30.0, 120.0, 170.0]),
        (0.8, [120.0, 200.0, 170.0]),
        (1.0, [235.0, 225.0, 190.0]),
    ];
    let t = t.clamp(0.0, 1.0);
    let k = STOPS.iter().position(|s| s.0 >= t).unwrap_or(3).max(1);
    let (a, b) = (STOPS[k - 1], STOPS[k]);
    let f = (t - a.0) / (b.0 - a.0);
    let mut c = [0u8; 3];
    for (i, v) in c.iter_mut().enumerate() {
        *v = (a.1[i] + f * (b.1[i] - a.1[i])).round() as u8;
    }
    c
}

/// The picture of `sim`'s final stock as PNG bytes (pfcam's `Software` chunk).
#[cfg(test)]
pub(crate) fn stock_png(sim: &Simulation, title: &str) -> Result<Vec<u8>, SimError> {
    draw(&sim.map, sim.report.findings.iter(), title)
}

/// The picture of the stock after the last program of `seq`, every
/// program's collisions marked.
pub fn sequence_png(seq: &Sequence, title: &str) -> Result<Vec<u8>, SimError> {
    draw(&seq.map, seq.findings().map(|(_, f)| f), title)
}

fn draw<'a>(
    map: &HeightMap,
    findings: impl Iterator<Item = &'a Finding>,
    title: &str,
) -> Result<Vec<u8>, SimError> {
    let g = map.grid;
    let side = g.nx.max(g.ny);
    // cells per pixel (down) or pixels per cell (up)
    let down = side.div_ceil(MAX_SIDE).max(1);
    let up = if down == 1 {
        (MIN_SIDE / side).max(1)
    } else {
        1
    };
    let (w, h) = (g.nx.div_ceil(down) * up, g.ny.div_ceil(down) * up);
    let lowest = map.min();
    let span = (map.top - lowest).max(1e-9);
    let mut data = vec![0u8; 3 * w * h];
    for py in 0..h {
        let j0 = (h - 1 - py) / up * down;
        for px in 0..w {
            let i0 = px / up * down;
            let mut z = f64::INFINITY;
            for j in j0..(j0 + down).min(g.ny) {
                for i in i0..(i0 + down).min(g.nx) {
                    z = z.min(map.at(i, j));
                }
            }
            let c = colour((z - lowest) / span);
            data[3 * (py * w + px)..3 * (py * w + px) + 3].copy_from_slice(&c);
        }
    }
    let scale = up as f64 / down as f64 / g.res; // pixels per mm
    for f in findings.filter(|f| {
        matches!(
            f.kind,
            Kind::RapidIntoMaterial | Kind::StraightPlunge | Kind::Gouge
        )
    }) {
        let cx = (f.x - g.x0) * scale;
        let cy = h as f64 - (f.y - g.y0) * scale;
        for d in -6i64..=6 {
            for (dx, dy) in [(d, d), (d, -d)] {
                for t in 0..2 {
                    let (x, y) = (cx as i64 + dx + t, cy as i64 + dy);
                    if x >= 0 && y >= 0 && (x as usize) < w && (y as usize) < h {
                        let p = 3 * (y as usize * w + x as usize);
                        data[p..p + 3].copy_from_slice(&[230, 20, 20]);
                    }
                }
            }
        }
    }
    let img = Rgb8 {
        width: w as u32,
        height: h as u32,
        data,
    };
    Ok(encode_png(&img, title)?)
}
