//! A harmonic patch's part as a closed triangle mesh (`pfcam surface`) and
//! as the up-facing triangles `simulate` and the finisher read.
//!
//! The solid is the block under the patch: the top surface z = stock.top +
//! h(x, y) − max h over the rectangle, triangulated on a grid (two triangles
//! a cell, both corners of each diagonal on the surface, so every vertex is
//! exact), four vertical side walls down to the bottom at stock.top − depth
//! − `surface::BASE_THICKNESS`, and the bottom face on the same grid. Walking
//! the rectangle's border counter-clockwise seen from above, each border step
//! P → Q gets the wall quad (B_P, B_Q, T_Q, T_P) (T on the top, B on the
//! bottom), so every directed edge has exactly one opposite: the top's
//! T_P → T_Q against the wall's T_Q → T_P, the wall's B_P → B_Q against the
//! bottom's (clockwise seen from above), the wall's vertical edges against
//! the neighbouring quad's.

use crate::geometry::Vec2;
use crate::levels::height_field::HeightFieldSections;
use crate::surface::{Mesh, Surface, BASE_THICKNESS};

/// The part's heights, machine z (mm): the top of the surface at `top` (the
/// stock top), its lowest point `depth` below it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Placement {
    /// stock.top, mm: where max h goes.
    pub(crate) top: f64,
    /// max h − min h, mm.
    pub(crate) depth: f64,
}

impl Placement {
    /// z of the bottom face, mm.
    pub(crate) fn z_bottom(&self) -> f64 {
        self.top - self.depth - BASE_THICKNESS
    }

    /// z of the floor around the part (its lowest point), mm.
    pub(crate) fn z_floor(&self) -> f64 {
        self.top - self.depth
    }
}

/// Grid points along a side of `length` mm at spacing at most `resolution`.
fn points_along(length: f64, resolution: f64) -> usize {
    ((length / resolution).ceil() as usize).max(1) + 1
}

/// The closed mesh of the patch block (module doc), its grid at most
/// `resolution` mm apart (at least 2 points a side). `stock` is the stock
/// rectangle (lower-left, upper-right).
pub(crate) fn patch_mesh(
    sections: &HeightFieldSections,
    place: Placement,
    resolution: f64,
    stock: (Vec2, Vec2),
) -> Surface {
    let (lo, size) = sections.rectangle_box();
    let (nx, ny) = (
        points_along(size.x, resolution),
        points_along(size.y, resolution),
    );
    let (hx, hy) = (size.x / (nx - 1) as f64, size.y / (ny - 1) as f64);
    let hmax = sections.top_height();
    let zb = place.z_bottom();
    let mut vertices = Vec::with_capacity(2 * nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let p = lo + Vec2::new(i as f64 * hx, j as f64 * hy);
            vertices.push([p.x, p.y, place.top + sections.height(p) - hmax]);
        }
    }
    for j in 0..ny {
        for i in 0..nx {
            let p = lo + Vec2::new(i as f64 * hx, j as f64 * hy);
            vertices.push([p.x, p.y, zb]);
        }
    }
    let t = |i: usize, j: usize| (j * nx + i) as u32;
    let b = |i: usize, j: usize| (nx * ny + j * nx + i) as u32;
    let mut triangles = Vec::with_capacity(4 * nx * ny + 4 * (nx + ny));
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let (a, bb, c, d) = ((i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1));
            triangles.push([t(a.0, a.1), t(bb.0, bb.1), t(c.0, c.1)]);
            triangles.push([t(a.0, a.1), t(c.0, c.1), t(d.0, d.1)]);
            triangles.push([b(a.0, a.1), b(c.0, c.1), b(bb.0, bb.1)]);
            triangles.push([b(a.0, a.1), b(d.0, d.1), b(c.0, c.1)]);
        }
    }
    let border = border_ccw(nx, ny);
    for k in 0..border.len() {
        let (p, q) = (border[k], border[(k + 1) % border.len()]);
        triangles.push([b(p.0, p.1), b(q.0, q.1), t(q.0, q.1)]);
        triangles.push([b(p.0, p.1), t(q.0, q.1), t(p.0, p.1)]);
    }
    Surface {
        mesh: Mesh {
            vertices,
            triangles,
        },
        stock_lo: stock.0,
        stock_hi: stock.1,
        z_bottom: zb,
        levels: Vec::new(),
        crossings: Vec::new(),
        grid: (nx, ny),
    }
}

/// The border grid points, counter-clockwise seen from above from (0, 0).
fn border_ccw(nx: usize, ny: usize) -> Vec<(usize, usize)> {
    let mut out = Vec::with_capacity(2 * (nx + ny));
    out.extend((0..nx - 1).map(|i| (i, 0)));
    out.extend((0..ny - 1).map(|j| (nx - 1, j)));
    out.extend((1..nx).rev().map(|i| (i, ny - 1)));
    out.extend((1..ny).rev().map(|j| (0, j)));
    out
}

/// The floor around the patch, inside the stock rectangle, at `z` (mm): four
/// trapezoids, two up-facing triangles each (none where the margin is 0).
pub(crate) fn floor_triangles(
    rect: (Vec2, Vec2),
    stock: (Vec2, Vec2),
    z: f64,
) -> Vec<[[f64; 3]; 3]> {
    let (r0, r1) = rect;
    let (s0, s1) = stock;
    let r = [
        [r0.x, r0.y, z],
        [r1.x, r0.y, z],
        [r1.x, r1.y, z],
        [r0.x, r1.y, z],
    ];
    let s = [
        [s0.x, s0.y, z],
        [s1.x, s0.y, z],
        [s1.x, s1.y, z],
        [s0.x, s1.y, z],
    ];
    let mut out = Vec::with_capacity(8);
    for k in 0..4 {
        let n = (k + 1) % 4;
        out.push([s[k], s[n], r[n]]);
        out.push([s[k], r[n], r[k]]);
    }
    out.retain(|c| crate::surface::up_area(c) > 1e-12);
    out
}
