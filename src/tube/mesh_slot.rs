//! The mesh of a boss with a slot: a trim that is a rectangle
//! u ∈ [u₀, 1], v ∈ [a, b] of the (u, v) plane (`[[shape.trim]]`), cut out
//! of the tube as a sector with its apex on the spine (docs/method.md §16.3).
//!
//! The wall's grid is laid on the slot: the columns start at v = a and take
//! b as one of them (the others 2π/P apart), and a row is put at u₀ (the
//! slot's floor), so every wall cell is wholly in the slot or out of it.
//! The cells in the slot (rows from u₀ up, columns between a and b) are
//! left out, and the opening is closed by
//!
//! - the **floor**: a fan from the spine point A₀(u₀) over the floor row's
//!   columns from a to b (normal up);
//! - the two **sides**: at each row pair from u₀ up, the quad from the spine
//!   points to X(u, a) (and X(u, b)): the rays of the sections' pie pieces;
//! - the **cap**: a fan from the top spine point over the kept columns.
//!
//! Orientation (a boss, rings counter-clockwise from above): the side at a
//! faces increasing v, the one at b decreasing v; every directed edge then
//! has exactly one opposite (`Mesh::check`).

use super::mesh::TubeMeshError;
use crate::geometry::Vec2;
use crate::sources::pde_tube::{PdeTube, TubeKind};
use crate::surface::Mesh;
use std::f64::consts::TAU;

/// A slot as the mesh needs it.
pub(super) struct Slot {
    /// The floor's u.
    u0: f64,
    /// Its angles, a < b < a + π.
    a: f64,
    b: f64,
    /// Set by [`Slot::columns`] and [`Slot::rows`]: b's column, the floor's row.
    jb: std::cell::Cell<usize>,
    floor: std::cell::Cell<usize>,
}

/// u of a trim reaching the top (the kept arcs' own limit).
const REACHES_TOP: f64 = 1.0 - 1e-9;

impl Slot {
    /// The tube's slot, if it has trims: one rectangle in (u, v) reaching
    /// u = 1, on a rising boss; else an error (the job refuses the rest).
    pub(super) fn of(tube: &PdeTube) -> Result<Option<Slot>, TubeMeshError> {
        let trims = tube.trims();
        let Some(t) = trims.first() else {
            return Ok(None);
        };
        if trims.len() > 1 || tube.kind() != TubeKind::Boss || !tube.rising() {
            return Err(TubeMeshError::TrimNotOnBoss);
        }
        let us: Vec<f64> = t.iter().map(|p| p[0]).collect();
        let vs: Vec<f64> = t.iter().map(|p| p[1]).collect();
        let lo = |x: &[f64]| x.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = |x: &[f64]| x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let rect = t.len() == 4
            && t.iter().all(|p| {
                (p[0] == lo(&us) || p[0] == hi(&us)) && (p[1] == lo(&vs) || p[1] == hi(&vs))
            });
        let (u0, a, b) = (lo(&us), lo(&vs), hi(&vs));
        if !rect || hi(&us) < REACHES_TOP || u0 <= 0.0 || !(b > a && b - a < 0.5 * TAU) {
            return Err(TubeMeshError::TrimNotSlot);
        }
        Ok(Some(Slot {
            u0,
            a,
            b,
            jb: 0.into(),
            floor: 0.into(),
        }))
    }

    /// The columns' v: a, then 2π/`p` apart, with b among them (a grid
    /// point closer to b than a tenth of a step gives way to it).
    pub(super) fn columns(&self, p: usize) -> Vec<f64> {
        let step = TAU / p as f64;
        let mut vs: Vec<f64> = (0..p)
            .map(|j| self.a + step * j as f64)
            .filter(|&v| (v - self.b).abs() > 0.1 * step)
            .collect();
        let jb = vs.partition_point(|&v| v < self.b);
        vs.insert(jb, self.b);
        self.jb.set(jb);
        vs
    }

    /// The rows (u, z relative to the top) from the foot up: z every
    /// depth/`n`, and the floor (u₀ at its own z; a row closer than a tenth
    /// of a step gives way to it).
    pub(super) fn rows(&self, tube: &PdeTube, n: usize) -> Vec<(f64, f64)> {
        use crate::levels::sections::Sections;
        let (bottom, _) = tube.z_range();
        let z0 = tube.surface().spine().point(self.u0)[2] - tube.top_z();
        let step = -bottom / n as f64;
        let mut rows: Vec<(f64, f64)> = (0..=n)
            .map(|i| bottom * (1.0 - i as f64 / n as f64))
            .filter(|&z| (z - z0).abs() > 0.1 * step)
            .map(|z| (tube.u_of(z), z))
            .collect();
        let f = rows.partition_point(|r| r.1 < z0);
        rows.insert(f, (self.u0, z0));
        self.floor.set(f);
        rows
    }

    /// Whether the wall cell between rows i, i + 1 and columns j, j + 1 is in
    /// the slot.
    pub(super) fn cuts(&self, i: usize, j: usize) -> bool {
        i >= self.floor.get() && j < self.jb.get()
    }

    /// The floor, the sides and the cap (module doc); `rows` as
    /// [`Slot::rows`] gave them, `p` columns, `top` the stock top.
    pub(super) fn add_faces(
        &self,
        m: &mut Mesh,
        tube: &PdeTube,
        (rows, p, top): (&[(f64, f64)], usize, f64),
    ) {
        let (f, jb, n) = (self.floor.get(), self.jb.get(), rows.len() - 1);
        let at = |i: usize, j: usize| (i * p + j % p) as u32;
        // Spine points S_i, rows f..=n.
        let s0 = m.vertices.len() as u32;
        for &(u, z) in &rows[f..] {
            let c = tube.surface().spine().point(u);
            let c = Vec2::new(c[0], c[1]);
            m.vertices.push([c.x, c.y, top + z]);
        }
        let spine = |i: usize| s0 + (i - f) as u32;
        for j in 0..jb {
            m.triangles.push([spine(f), at(f, j), at(f, j + 1)]);
        }
        for j in jb..p {
            m.triangles.push([spine(n), at(n, j), at(n, j + 1)]);
        }
        for i in f..n {
            let (s, t) = (spine(i), spine(i + 1));
            m.triangles.push([s, t, at(i + 1, 0)]);
            m.triangles.push([s, at(i + 1, 0), at(i, 0)]);
            m.triangles.push([s, at(i + 1, jb), t]);
            m.triangles.push([s, at(i, jb), at(i + 1, jb)]);
        }
    }
}
