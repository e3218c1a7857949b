//! The zero set of a field on a regular grid as a closed, consistently
//! oriented triangle mesh: marching tetrahedra.
//!
//! Every grid cube is cut into the six tetrahedra around its diagonal from
//! corner (0, 0, 0) to (1, 1, 1) (corners c, c + eₐ, c + eₐ + e_b, c + 1 for
//! the six orders (a, b) of the axes). On each face of a cube the cut is the
//! diagonal through the face's lowest-index and highest-index corners, so a
//! face shared by two cubes is cut alike from both sides and the pieces meet.
//! A node is *inside* when f < 0 (the solid {f < 0}), else outside. In a
//! tetrahedron with mixed signs the zero set is a triangle (one corner apart)
//! or a quadrilateral (two and two), its vertices on the tetrahedron's edges
//! between an inside and an outside node, each placed by regula falsi on f
//! along its edge and kept at least [`T_MIN`] of the edge from its ends. A
//! vertex is keyed by its grid edge, so the tetrahedra sharing an edge share
//! it, and every mesh edge (on a tetrahedron's face, shared by two
//! tetrahedra, or a quadrilateral's diagonal) is used by exactly two
//! triangles, once each way: the mesh is closed when no node on the grid's
//! boundary is inside (checked). No face table is needed, so there are no
//! ambiguous cases (marching cubes' holes).
//!
//! Orientation: for a tetrahedron (v₀, v₁, v₂, v₃) of positive volume, the
//! triangle on the edges v₀v₁, v₀v₂, v₀v₃, in that order, faces away from
//! v₀; the quadrilateral with v₀, v₁ inside, v₂, v₃ outside, on the edges
//! v₀v₂, v₀v₃, v₁v₃, v₁v₂ in that order, faces toward v₂, v₃. Each case is
//! brought to one of these by an even permutation of the corners (which
//! keeps the volume positive), so every triangle faces out of the solid.

use nalgebra::Vector3;
use rayon::prelude::*;
use std::collections::HashMap;

/// No vertex lies closer than this fraction of its edge to the edge's ends
/// (no zero-area triangle, also after rounding to an STL's 32-bit floats).
pub const T_MIN: f64 = 0.02;

/// Most grid nodes (64 MB of values).
pub(crate) const MAX_NODES: usize = 8_000_000;

/// Regula falsi steps at most per vertex.
const ROOT_STEPS: usize = 60;

/// A regular grid of nodes lo + (i hx, j hy, k hz), `n[0]` × `n[1]` × `n[2]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid3 {
    /// The first node, mm.
    pub(crate) lo: Vector3<f64>,
    /// The spacing per axis, mm.
    pub(crate) h: Vector3<f64>,
    /// Nodes per axis (at least 2 each).
    pub(crate) n: [usize; 3],
}

impl Grid3 {
    /// The grid over [lo, hi] with spacing at most `spacing`, or None when
    /// it is empty, not finite or has more than [`MAX_NODES`] nodes.
    pub fn covering(lo: Vector3<f64>, hi: Vector3<f64>, spacing: f64) -> Option<Grid3> {
        let mut n = [0; 3];
        let mut h = Vector3::zeros();
        let mut total = 1.0;
        for k in 0..3 {
            let cells = ((hi[k] - lo[k]) / spacing).ceil();
            if !(cells.is_finite() && cells >= 1.0 && cells < MAX_NODES as f64) {
                return None;
            }
            n[k] = cells as usize + 1;
            h[k] = (hi[k] - lo[k]) / cells;
            total *= n[k] as f64;
        }
        (total <= MAX_NODES as f64).then_some(Grid3 { lo, h, n })
    }

    /// Number of nodes.
    pub(crate) fn len(&self) -> usize {
        self.n[0] * self.n[1] * self.n[2]
    }

    fn index(&self, i: usize, j: usize, k: usize) -> usize {
        i + self.n[0] * (j + self.n[1] * k)
    }

    /// Position of node `id`.
    pub(crate) fn node(&self, id: usize) -> Vector3<f64> {
        let (i, rest) = (id % self.n[0], id / self.n[0]);
        let (j, k) = (rest % self.n[1], rest / self.n[1]);
        self.lo + Vector3::new(i as f64, j as f64, k as f64).component_mul(&self.h)
    }

    fn on_boundary(&self, id: usize) -> bool {
        let (i, rest) = (id % self.n[0], id / self.n[0]);
        let (j, k) = (rest % self.n[1], rest / self.n[1]);
        i == 0 || j == 0 || k == 0 || i + 1 == self.n[0] || j + 1 == self.n[1] || k + 1 == self.n[2]
    }
}

/// An indexed triangle mesh, mm: the zero set (as `surface::Mesh`, which
/// checks and writes it; kept apart so that the sources stay below
/// `surface` in the layering).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct IsoMesh {
    /// Vertex positions.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as vertex indices, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

/// Why no mesh.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IsoError {
    /// f is inside (< 0) at a node on the grid's boundary: the zero set is
    /// not closed within the grid.
    #[error("the solid reaches the boundary of the region meshed (f = {value:.3e} < 0 at ({:.3}, {:.3}, {:.3}))", at[0], at[1], at[2])]
    Open {
        /// The node.
        at: [f64; 3],
        /// f there.
        value: f64,
    },
    /// f is not finite at a node.
    #[error("the field is not finite at ({:.3}, {:.3}, {:.3})", at[0], at[1], at[2])]
    NotFinite {
        /// The node.
        at: [f64; 3],
    },
}

/// The six tetrahedra of a cube as corner offsets (bit 0 x, bit 1 y, bit 2
/// z), each of positive volume.
const TETS: [[u8; 4]; 6] = [
    [0, 1, 3, 7], // x then y: det(e_x, e_y, e_z) = +1
    [0, 3, 2, 7], // y then x, v1 and v2 swapped
    [0, 2, 6, 7], // y then z
    [0, 6, 4, 7], // z then y, swapped
    [0, 4, 5, 7], // z then x
    [0, 5, 1, 7], // x then z, swapped
];

/// The even permutations of (0, 1, 2, 3).
const EVEN: [[usize; 4]; 12] = [
    [0, 1, 2, 3],
    [0, 2, 3, 1],
    [0, 3, 1, 2],
    [1, 0, 3, 2],
    [1, 2, 0, 3],
    [1, 3, 2, 0],
    [2, 0, 1, 3],
    [2, 1, 3, 0],
    [2, 3, 0, 1],
    [3, 0, 2, 1],
    [3, 1, 0, 2],
    [3, 2, 1, 0],
];

/// A piece of the zero set in one tetrahedron: its vertices' grid edges,
/// in order (three for a triangle, four for a quadrilateral).
type Piece = ([u64; 4], usize);

/// The key of the grid edge between nodes a and b.
fn edge_key(a: usize, b: usize) -> u64 {
    let (a, b) = if a < b { (a, b) } else { (b, a) };
    ((a as u64) << 32) | b as u64
}

/// The oriented piece of one tetrahedron (module doc), if its corners
/// `v` (node ids) have mixed signs.
fn piece(v: [usize; 4], inside: [bool; 4]) -> Option<Piece> {
    let count = inside.iter().filter(|&&b| b).count();
    let first = |m: usize| {
        EVEN.iter()
            .find(|p| (0..4).all(|i| (i < m) == inside[p[i]]))
    };
    let e = |a: usize, b: usize| edge_key(v[a], v[b]);
    match count {
        1 => first(1).map(|p| ([e(p[0], p[1]), e(p[0], p[2]), e(p[0], p[3]), 0], 3)),
        3 => {
            // The outside corner first; reversed to face it.
            let p = EVEN.iter().find(|p| !inside[p[0]])?;
            Some(([e(p[0], p[1]), e(p[0], p[3]), e(p[0], p[2]), 0], 3))
        }
        2 => first(2).map(|p| {
            (
                [e(p[0], p[2]), e(p[0], p[3]), e(p[1], p[3]), e(p[1], p[2])],
                4,
            )
        }),
        _ => None,
    }
}

/// The pieces of every tetrahedron of the cubes in the layer k.
fn layer_pieces(g: &Grid3, inside: &[bool], k: usize) -> Vec<Piece> {
    let mut out = Vec::new();
    for j in 0..g.n[1] - 1 {
        for i in 0..g.n[0] - 1 {
            let c = |b: u8| {
                g.index(
                    i + (b & 1) as usize,
                    j + (b >> 1 & 1) as usize,
                    k + (b >> 2) as usize,
                )
            };
            for t in TETS {
                let v = t.map(c);
                if let Some(p) = piece(v, v.map(|n| inside[n])) {
                    out.push(p);
                }
            }
        }
    }
    out
}

/// The zero of f on the segment a (inside, f(a) = fa < 0) → b (outside,
/// fb ≥ 0) as a fraction of it, by the Illinois variant of regula falsi,
/// clamped to [T_MIN, 1 − T_MIN].
fn root<F: Fn(Vector3<f64>) -> f64>(
    f: &F,
    a: Vector3<f64>,
    b: Vector3<f64>,
    fa: f64,
    fb: f64,
) -> f64 {
    let (mut t0, mut t1, mut f0, mut f1) = (0.0, 1.0, fa, fb);
    let mut side = 0;
    for _ in 0..ROOT_STEPS {
        if t1 - t0 < 1e-12 {
            break;
        }
        let t = (t0 - f0 * (t1 - t0) / (f1 - f0)).clamp(t0, t1);
        let ft = f(a + (b - a) * t);
        if ft == 0.0 || !ft.is_finite() {
            t0 = t;
            t1 = t;
            break;
        }
        if ft < 0.0 {
            (t0, f0) = (t, ft);
            if side == -1 {
                f1 *= 0.5;
            }
            side = -1;
        } else {
            (t1, f1) = (t, ft);
            if side == 1 {
                f0 *= 0.5;
            }
            side = 1;
        }
    }
    (0.5 * (t0 + t1)).clamp(T_MIN, 1.0 - T_MIN)
}

/// f at every node, in parallel; an error where f is not finite or is
/// inside on the boundary.
fn sample<F: Fn(Vector3<f64>) -> f64 + Sync>(g: &Grid3, f: &F) -> Result<Vec<f64>, IsoError> {
    let values: Vec<f64> = (0..g.len())
        .into_par_iter()
        .map(|id| f(g.node(id)))
        .collect();
    for (id, &v) in values.iter().enumerate() {
        let at: [f64; 3] = g.node(id).into();
        if !v.is_finite() {
            return Err(IsoError::NotFinite { at });
        }
        if v < 0.0 && g.on_boundary(id) {
            return Err(IsoError::Open { at, value: v });
        }
    }
    Ok(values)
}

/// The mesh of {f = 0} on `g` (module doc): closed, every triangle facing
/// out of {f < 0}. Empty when no node is inside.
pub fn zero_set<F: Fn(Vector3<f64>) -> f64 + Sync>(g: &Grid3, f: &F) -> Result<IsoMesh, IsoError> {
    let values = sample(g, f)?;
    let inside: Vec<bool> = values.iter().map(|&v| v < 0.0).collect();
    let pieces: Vec<Piece> = (0..g.n[2] - 1)
        .into_par_iter()
        .flat_map_iter(|k| layer_pieces(g, &inside, k))
        .collect();
    // Number the vertices in the order the pieces meet them.
    let mut ids: HashMap<u64, u32> = HashMap::new();
    let mut keys = Vec::new();
    for (e, n) in &pieces {
        for &key in &e[..*n] {
            ids.entry(key).or_insert_with(|| {
                keys.push(key);
                (keys.len() - 1) as u32
            });
        }
    }
    let vertices: Vec<[f64; 3]> = keys
        .par_iter()
        .map(|&key| {
            let (a, b) = ((key >> 32) as usize, (key & 0xffff_ffff) as usize);
            let (i, o) = if inside[a] { (a, b) } else { (b, a) };
            let (pi, po) = (g.node(i), g.node(o));
            (pi + (po - pi) * root(f, pi, po, values[i], values[o])).into()
        })
        .collect();
    let triangles = pieces
        .iter()
        .flat_map(|(e, n)| split(&vertices, e[..*n].iter().map(|k| ids[k]).collect()))
        .collect();
    Ok(IsoMesh {
        vertices,
        triangles,
    })
}

/// A triangle as is; a quadrilateral cut along its shorter diagonal.
fn split(p: &[[f64; 3]], q: Vec<u32>) -> Vec<[u32; 3]> {
    if q.len() == 3 {
        return vec![[q[0], q[1], q[2]]];
    }
    let d = |a: u32, b: u32| {
        let (a, b) = (Vector3::from(p[a as usize]), Vector3::from(p[b as usize]));
        (a - b).norm_squared()
    };
    if d(q[0], q[2]) <= d(q[1], q[3]) {
        vec![[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
    } else {
        vec![[q[0], q[1], q[3]], [q[1], q[2], q[3]]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every tetrahedron of [`TETS`] has positive volume, and the six fill
    /// the unit cube.
    #[test]
    fn the_tetrahedra_are_positive_and_fill_the_cube() {
        let c = |b: u8| Vector3::new((b & 1) as f64, (b >> 1 & 1) as f64, (b >> 2) as f64);
        let mut total = 0.0;
        for t in TETS {
            let [a, b, cc, d] = t.map(c);
            let v = (b - a).dot(&(cc - a).cross(&(d - a))) / 6.0;
            assert!(v > 0.0, "{t:?}");
            total += v;
        }
        assert!((total - 1.0).abs() < 1e-15);
    }

    /// A node inside on the boundary is an error; nothing inside is an
    /// empty mesh.
    #[test]
    fn open_and_empty() {
        let g = Grid3::covering(Vector3::repeat(-1.0), Vector3::repeat(1.0), 0.25).unwrap();
        let big = |x: Vector3<f64>| x.norm() - 1.5;
        assert!(matches!(zero_set(&g, &big), Err(IsoError::Open { .. })));
        let none = |x: Vector3<f64>| x.norm() + 1.0;
        assert!(zero_set(&g, &none).unwrap().triangles.is_empty());
        let nan = |_: Vector3<f64>| f64::NAN;
        assert!(matches!(
            zero_set(&g, &nan),
            Err(IsoError::NotFinite { .. })
        ));
    }
}
