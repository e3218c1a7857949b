//! A PDE tube's part as a closed triangle mesh (`pfcam surface`, and the
//! up-facing triangles `simulate` reads).
//!
//! The solid is what a boss job leaves (the tube standing on the floor of
//! the stock rectangle) or a mould job (the slab with the tube as its
//! pocket), closed below by a bottom face `surface::BASE_THICKNESS` under
//! the deepest cut, as the other sources' parts are:
//!
//! - **wall**: rings X(uᵢ, vⱼ), vⱼ = 2πj/P, at heights zᵢ = −H + iH/n
//!   (uᵢ = u(zᵢ), the tube's own inverse of A₀z), quads between neighbouring
//!   rings, two triangles each;
//! - **cap**: the narrow end (a boss's top, a mould's pocket floor), a fan
//!   from the spine point A₀(u) (the end curves are star-shaped about it);
//! - **annulus**: the wide end (a boss's foot, a mould's rim) to the stock
//!   rectangle at the same height: ring vertex j (polar angle θⱼ about the
//!   spine point, increasing) to the point where the ray at θⱼ leaves the
//!   rectangle, with the rectangle's corners inserted between the rays they
//!   fall between; each ring vertex fans to its stretch of the border;
//! - **sides and bottom**: the border ring straight down, and a fan from the
//!   rectangle's centre below (not from a corner: border points collinear
//!   with the apex would give zero-area triangles).
//!
//! Orientation (outward normals): a boss's wall triangles run (Lⱼ, Lⱼ₊₁,
//! Uⱼ₊₁), (Lⱼ, Uⱼ₊₁, Uⱼ) for a lower ring L and upper U, both
//! counter-clockwise from above; a mould's the other way round (its
//! material is outside). Every directed edge then has exactly one opposite.

use super::widest_z;
use crate::geometry::Vec2;
use crate::levels::sections::Sections;
use crate::sources::pde_tube::{PdeTube, TubeKind, MAX_POINTS};
use crate::surface::{Mesh, Surface, BASE_THICKNESS};
use std::f64::consts::{PI, TAU};

/// Why [`tube_mesh`] could not mesh a tube's part.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TubeMeshError {
    /// More than one trim, or a trim not on a rising boss.
    #[error("the part's mesh cannot carry this trim: only one trim, on a boss, is implemented")]
    TrimNotOnBoss,
    /// A trim that is not a slot from a u in (0, 1) to the top.
    #[error("the part's mesh cannot carry this trim: it must be a rectangle in (u, v) from a u in (0, 1) to the top, less than π wide")]
    TrimNotSlot,
    /// A polar angle of the wide end's ring does not increase.
    #[error(
        "the tube's wide end does not turn monotonically about its axis (a step of {step:.3e} rad)"
    )]
    NotMonotonic {
        /// The step from the previous angle, radians (in [0, 2π)).
        step: f64,
    },
    /// The wide end's ring turns more than once.
    #[error("the tube's wide end winds more than once about its axis")]
    WindsTwice,
}

/// Points of the vertex rings of a tube at `resolution` mm: about the
/// widest ring's perimeter over the resolution, a multiple of 4, 64 to
/// [`MAX_POINTS`].
fn ring_points(tube: &PdeTube, resolution: f64) -> usize {
    let u = tube.u_of(widest_z(tube));
    let ring = tube.surface().ring(u, 256);
    let length: f64 = (0..ring.len())
        .map(|j| {
            let (a, b) = (ring[j], ring[(j + 1) % ring.len()]);
            (b[0] - a[0]).hypot(b[1] - a[1])
        })
        .sum();
    let p = 4 * (length / (4.0 * resolution)).ceil() as usize;
    p.clamp(64, MAX_POINTS)
}

/// The closed mesh of the tube's part (module doc), `top` the stock top
/// (mm, where the tube's top goes), vertices at most about `resolution` mm
/// apart, `stock` the stock rectangle. A trimmed boss is meshed by
/// `super::mesh_slot`. An error is a pfcam bug (a ring whose polar angle
/// does not increase), or a trim the mesh cannot carry.
pub(crate) fn tube_mesh(
    tube: &PdeTube,
    top: f64,
    resolution: f64,
    stock: (Vec2, Vec2),
) -> Result<Surface, TubeMeshError> {
    let p = ring_points(tube, resolution);
    let (bottom, _) = tube.z_range();
    let n = ((-bottom / resolution).ceil() as usize).max(2);
    let slot = super::mesh_slot::Slot::of(tube)?;
    let mut m = Mesh::default();
    // Rings from the bottom up: ring i's vertex j is i·p + j.
    let rows = match &slot {
        Some(s) => s.rows(tube, n),
        None => (0..=n)
            .map(|i| {
                let z = bottom * (1.0 - i as f64 / n as f64);
                (tube.u_of(z), z)
            })
            .collect(),
    };
    let p = match &slot {
        Some(s) => {
            let vs = s.columns(p);
            for &(u, z) in &rows {
                m.vertices.extend(vs.iter().map(|&v| {
                    let q = tube.surface().point(u, v);
                    [q[0], q[1], top + z]
                }));
            }
            vs.len()
        }
        None => {
            for &(u, z) in &rows {
                let ring = tube.surface().ring(u, p);
                m.vertices
                    .extend(ring.iter().map(|q| [q[0], q[1], top + z]));
            }
            p
        }
    };
    let n = rows.len() - 1;
    let at = |i: usize, j: usize| (i * p + j % p) as u32;
    let boss = tube.kind() == TubeKind::Boss;
    let in_slot = |i: usize, j: usize| slot.as_ref().is_some_and(|s| s.cuts(i, j));
    for i in 0..n {
        for j in (0..p).filter(|&j| !in_slot(i, j)) {
            let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
            if boss {
                m.triangles.push([a, b, c]);
                m.triangles.push([a, c, d]);
            } else {
                m.triangles.push([a, c, b]);
                m.triangles.push([a, d, c]);
            }
        }
    }
    let (cap, wide) = if boss { (n, 0) } else { (0, n) };
    let ring = |i: usize| -> Vec<u32> { (0..p).map(|j| at(i, j)).collect() };
    let centre = |i: usize| {
        let c = tube.surface().spine().point(rows[i].0);
        Vec2::new(c[0], c[1])
    };
    match &slot {
        Some(s) => s.add_faces(&mut m, tube, (&rows, p, top)),
        None => add_cap(&mut m, &ring(cap), centre(cap)),
    }
    let z_wide = m.vertices[at(wide, 0) as usize][2];
    let z_bottom = top + bottom - BASE_THICKNESS;
    let border = add_annulus(&mut m, &ring(wide), centre(wide), stock)?;
    add_sides_and_bottom(&mut m, &border, (z_wide, z_bottom), stock);
    Ok(Surface {
        mesh: m,
        stock_lo: stock.0,
        stock_hi: stock.1,
        z_bottom,
        levels: Vec::new(),
        crossings: Vec::new(),
        grid: (p, n + 1),
    })
}

/// The fan from `c` (at the ring's height) over the ring, normal up.
fn add_cap(m: &mut Mesh, ring: &[u32], c: Vec2) {
    let z = m.vertices[ring[0] as usize][2];
    let apex = m.vertices.len() as u32;
    m.vertices.push([c.x, c.y, z]);
    for j in 0..ring.len() {
        m.triangles
            .push([apex, ring[j], ring[(j + 1) % ring.len()]]);
    }
}

/// Where the ray from `c` at angle `t` leaves the rectangle `r` (c inside).
fn ray_exit(c: Vec2, t: f64, r: (Vec2, Vec2)) -> Vec2 {
    let d = Vec2::new(t.cos(), t.sin());
    let along = |c: f64, d: f64, lo: f64, hi: f64| {
        if d > 0.0 {
            (hi - c) / d
        } else if d < 0.0 {
            (lo - c) / d
        } else {
            f64::INFINITY
        }
    };
    let (sx, sy) = (along(c.x, d.x, r.0.x, r.1.x), along(c.y, d.y, r.0.y, r.1.y));
    let q = c + d * sx.min(sy);
    // On the edge it crosses exactly (the sides are built from these points).
    let edge = |d: f64, lo: f64, hi: f64| if d > 0.0 { hi } else { lo };
    if sx <= sy {
        Vec2::new(edge(d.x, r.0.x, r.1.x), q.y.clamp(r.0.y, r.1.y))
    } else {
        Vec2::new(q.x.clamp(r.0.x, r.1.x), edge(d.y, r.0.y, r.1.y))
    }
}

/// The ring's polar angles about `c`, unwrapped from the first: strictly
/// increasing, the whole turn under 2π; else an error.
fn unwrapped_angles(m: &Mesh, ring: &[u32], c: Vec2) -> Result<Vec<f64>, TubeMeshError> {
    let angle = |k: u32| {
        let v = m.vertices[k as usize];
        (v[1] - c.y).atan2(v[0] - c.x)
    };
    let first = angle(ring[0]);
    let mut out = vec![first];
    for &k in &ring[1..] {
        let prev = *out.last().unwrap_or(&first);
        let step = (angle(k) - prev).rem_euclid(TAU);
        if step <= 0.0 || step >= PI {
            return Err(TubeMeshError::NotMonotonic { step });
        }
        out.push(prev + step);
    }
    let last = *out.last().unwrap_or(&first);
    if last - first >= TAU {
        return Err(TubeMeshError::WindsTwice);
    }
    Ok(out)
}

/// The floor (a boss) or slab top (a mould) between the ring and the stock
/// rectangle, normal up; returns the border ring (counter-clockwise).
fn add_annulus(
    m: &mut Mesh,
    ring: &[u32],
    c: Vec2,
    stock: (Vec2, Vec2),
) -> Result<Vec<u32>, TubeMeshError> {
    let theta = unwrapped_angles(m, ring, c)?;
    let z = m.vertices[ring[0] as usize][2];
    let (lo, hi) = stock;
    let corners = [lo, Vec2::new(hi.x, lo.y), hi, Vec2::new(lo.x, hi.y)];
    let p = ring.len();
    let mut border: Vec<u32> = Vec::with_capacity(p + 4);
    let push = |m: &mut Mesh, border: &mut Vec<u32>, q: Vec2| {
        border.push(m.vertices.len() as u32);
        m.vertices.push([q.x, q.y, z]);
    };
    // Each ring vertex's stretch of the border: its ray's exit, then the
    // corners before the next ray.
    let mut stretch_start = Vec::with_capacity(p + 1);
    for j in 0..p {
        let (t0, t1) = (
            theta[j],
            if j + 1 < p {
                theta[j + 1]
            } else {
                theta[0] + TAU
            },
        );
        stretch_start.push(border.len());
        push(m, &mut border, ray_exit(c, t0, stock));
        let mut inside: Vec<(f64, Vec2)> = corners
            .iter()
            .map(|&k| {
                let a = (k.y - c.y).atan2(k.x - c.x);
                (t0 + (a - t0).rem_euclid(TAU), k)
            })
            .filter(|(a, _)| *a > t0 + 1e-9 && *a < t1 - 1e-9)
            .collect();
        inside.sort_by(|x, y| x.0.total_cmp(&y.0));
        for (_, k) in inside {
            push(m, &mut border, k);
        }
    }
    stretch_start.push(border.len());
    for j in 0..p {
        let (a, b) = (stretch_start[j], stretch_start[j + 1]);
        for k in a..b {
            m.triangles
                .push([ring[j], border[k], border[(k + 1) % border.len()]]);
        }
        m.triangles
            .push([ring[j], border[b % border.len()], ring[(j + 1) % p]]);
    }
    Ok(border)
}

/// The stock's vertical sides from the border ring (at `z.0`) down to the
/// bottom (`z.1`), and the bottom face, a fan from the rectangle's centre.
fn add_sides_and_bottom(m: &mut Mesh, border: &[u32], z: (f64, f64), stock: (Vec2, Vec2)) {
    let below: Vec<u32> = border
        .iter()
        .map(|&k| {
            let v = m.vertices[k as usize];
            m.vertices.push([v[0], v[1], z.1]);
            (m.vertices.len() - 1) as u32
        })
        .collect();
    let q = border.len();
    for k in 0..q {
        let l = (k + 1) % q;
        m.triangles.push([below[k], below[l], border[l]]);
        m.triangles.push([below[k], border[l], border[k]]);
    }
    let c = (stock.0 + stock.1) * 0.5;
    let apex = m.vertices.len() as u32;
    m.vertices.push([c.x, c.y, z.1]);
    for k in 0..q {
        m.triangles.push([apex, below[(k + 1) % q], below[k]]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sources::pde_tube::spec::test_vase;

    /// The mesh's refusals read as the strings they were.
    #[test]
    fn mesh_errors_say_what_the_strings_said() {
        let step = 3.25e-7;
        let trim = "the part's mesh cannot carry this trim: ";
        let cases = [
            (TubeMeshError::TrimNotOnBoss, format!("{trim}only one trim, on a boss, is implemented")),
            (TubeMeshError::TrimNotSlot, format!("{trim}it must be a rectangle in (u, v) from a u in (0, 1) to the top, less than π wide")),
            (TubeMeshError::NotMonotonic { step }, format!("the tube's wide end does not turn monotonically about its axis (a step of {step:.3e} rad)")),
        ];
        for (e, text) in cases {
            assert_eq!(e.to_string(), text);
        }
    }

    fn vase(kind: TubeKind) -> PdeTube {
        test_vase(kind, Vec2::new(1.0, 2.0))
            .tube()
            .expect("the vase")
    }

    #[test]
    fn boss_and_mould_are_closed_and_their_volumes_add_up_to_the_block() {
        let stock = (Vec2::new(-14.0, -13.0), Vec2::new(16.0, 17.0));
        let block = 30.0 * 30.0 * (15.0 + BASE_THICKNESS);
        for kind in [TubeKind::Boss, TubeKind::Mould] {
            let t = vase(kind);
            let s = tube_mesh(&t, 0.0, 0.4, stock).expect("mesh");
            s.mesh.check().expect("watertight");
            let (lo, hi) = s.mesh.bbox().expect("vertices");
            assert_eq!((lo[2], hi[2]), (-17.0, 0.0));
            assert_eq!((lo[0], hi[1]), (-14.0, 17.0));
            let v = s.mesh.volume();
            // The tube's volume by the sections' areas (Simpson, 60 slices).
            let area = |z: f64| crate::levels::sections::net_area(&t.section(z)).abs();
            let tube: f64 = (0..60)
                .map(|k| {
                    let (a, b) = (-15.0 + 0.25 * k as f64, -15.0 + 0.25 * (k + 1) as f64);
                    0.25 / 6.0 * (area(a) + 4.0 * area(0.5 * (a + b)) + area(b))
                })
                .sum();
            let want = match kind {
                TubeKind::Boss => 30.0 * 30.0 * BASE_THICKNESS + tube,
                TubeKind::Mould => block - tube,
            };
            assert!((v - want).abs() < 1e-3 * tube, "{kind:?}: {v} vs {want}");
        }
    }
}
