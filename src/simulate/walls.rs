//! What a ball end mill left on the part's walls, measured along the normal
//! in 3-D rather than on the height map.
//!
//! The height map measures material vertically at cell centres. On a wall
//! near vertical that fails twice: a sliver a few µm thick along the wall
//! stands tall in one cell's column (0.0044 mm along the normal read as
//! 0.029 mm on mfs-sign's power wall at 0.05 mm cells), and a ball grazing
//! a wall's top edge between two cell centres drops up to √(2·r·δ) lower on
//! the samples than on the part (0.4 mm for δ = 0.05 mm), so the envelope of
//! what the tool can reach (`reach`) sinks under the part's foot there.
//!
//! Here, for a ball of radius r, exactly (up to the mesh and the sampling of
//! the part): at the centroid P of every wall triangle of the part's model,
//! with its normal n,
//! - the material the program left is the distance from P to the volume the
//!   ball swept, min over the program's moves of |P − segment of centres| − r
//!   (the centres are the tips raised by r);
//! - the ball reaches P if it can touch P: the ball centred at P + r·n
//!   enters no triangle of the part by more than [`ENTER`].
//!
//! The largest material left at a point the ball reaches is reported. Only
//! the last program counts (the finisher; walls are its to finish), and
//! only walls (triangles tilted more than [`WALL_TILT`]); flats are
//! measured well by the height map.

use super::moves::Move;
use super::part::PartModel;
use super::report::Worst;
use nalgebra::Vector3;
use rayon::prelude::*;
use serde::Serialize;

/// A triangle is a wall where its normal leans more than this from
/// vertical (cos of 0.5°).
pub(crate) const WALL_TILT: f64 = 0.999_961_923_064_171_4;
/// How far (mm) a ball touching P may enter the part's triangles and still
/// count as reaching P: on a concave wall the flat facets stand off the
/// curved surface by their sag, under a µm at 0.1 mm triangles.
pub(crate) const ENTER: f64 = 0.002;
/// Bins of the moves and triangles, mm.
const BIN: f64 = 0.5;
/// Most material (mm) measured past the ball's radius: a point farther
/// than this from every ball position reads as this.
pub(crate) const FAR: f64 = 1.0;

/// The largest material left along the normal on the walls where the ball
/// reaches (value and line of the nearest move), and how many wall points
/// were measured and how many the ball cannot reach.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct WallLeft {
    /// Material left, mm, and the program line of the nearest ball position.
    pub left: Worst,
    /// When several programs were simulated: the one `left.line` is in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) program: Option<String>,
    /// Where (x, y, z of the wall point).
    pub(crate) at: [f64; 3],
    /// Wall points measured.
    pub(crate) points: usize,
}

type V3 = [f64; 3];

fn v(a: V3) -> Vector3<f64> {
    Vector3::from(a)
}

/// Distance from `p` to the segment a–b.
fn segment_distance(p: V3, a: V3, b: V3) -> f64 {
    let (p, a, ab) = (v(p), v(a), v(b) - v(a));
    let l2 = ab.norm_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(&ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).norm()
}

/// Distance from `p` to the triangle (the closest point by its region:
/// inside, on an edge or at a corner).
pub(crate) fn triangle_distance(q: V3, t: &[V3; 3]) -> f64 {
    let (p, c) = (v(q), t.map(v));
    let n = (c[1] - c[0]).cross(&(c[2] - c[0]));
    let nn = n.norm_squared();
    if nn > 0.0 {
        // The foot of p on the plane, inside if on the inner side of all
        // three edges.
        let h = (p - c[0]).dot(&n) / nn;
        let foot = p - n * h;
        let inside = (0..3).all(|i| {
            let (a, b) = (c[i], c[(i + 1) % 3]);
            (b - a).cross(&(foot - a)).dot(&n) >= 0.0
        });
        if inside {
            return h.abs() * nn.sqrt();
        }
    }
    (0..3)
        .map(|i| segment_distance(q, t[i], t[(i + 1) % 3]))
        .fold(f64::INFINITY, f64::min)
}

/// The unit normal of triangle `t` (its corners' order: counter-clockwise
/// seen from where it points), `None` for a degenerate one.
pub(crate) fn unit_normal(t: &[V3; 3]) -> Option<V3> {
    let c = t.map(v);
    (c[1] - c[0])
        .cross(&(c[2] - c[0]))
        .try_normalize(0.0)
        .map(Into::into)
}

/// The centroid and unit normal of every wall triangle (tilted more than
/// [`WALL_TILT`], facing up).
pub(crate) fn wall_centroids(triangles: &[[V3; 3]]) -> Vec<(V3, V3)> {
    triangles
        .iter()
        .filter_map(|t| {
            let n = unit_normal(t)?;
            (n[2] > 0.0 && n[2] < WALL_TILT).then(|| {
                let c = [0, 1, 2].map(|a| (t[0][a] + t[1][a] + t[2][a]) / 3.0);
                (c, n)
            })
        })
        .collect()
}

/// Most Newton steps of [`project_walls`].
const NEWTON_STEPS: usize = 8;
/// Farthest (mm) a wall point moves onto the exact surface; one that would
/// move farther is dropped.
const MOVE_LIMIT: f64 = 0.2;

/// The wall triangles' centroids moved along their mesh normal onto the
/// exact surface z = `height(x, y)` (which returns z and ∇z) by Newton's
/// method, each with the exact surface's unit normal (−∇z, 1)/|…| there.
/// On a near-vertical wall a 0.1 mm mesh's facets stand up to a few
/// hundredths of a millimetre off the surface in plan (0.026 mm at
/// mfs-sign's M): measuring from them would count that as material left.
pub(crate) fn project_walls(
    triangles: &[[V3; 3]],
    height: &(dyn Fn(f64, f64) -> (f64, [f64; 2]) + Sync),
) -> Vec<(V3, V3)> {
    wall_centroids(triangles)
        .into_par_iter()
        .filter_map(|(p, n)| {
            let mut t = 0.0;
            for _ in 0..NEWTON_STEPS {
                let q: V3 = (v(p) + v(n) * t).into();
                let (z, g) = height(q[0], q[1]);
                let f = z - q[2];
                let df = g[0] * n[0] + g[1] * n[1] - n[2];
                if f.abs() < 1e-9 {
                    let m = (g[0] * g[0] + g[1] * g[1] + 1.0).sqrt();
                    return Some((q, [-g[0] / m, -g[1] / m, 1.0 / m]));
                }
                if df.abs() < 1e-12 || t.abs() > MOVE_LIMIT {
                    return None;
                }
                t -= f / df;
            }
            None
        })
        .collect()
}

/// Items binned by their XY box on a grid of [`BIN`] mm from `lo`.
pub(super) struct Bins {
    lo: [f64; 2],
    nx: usize,
    ny: usize,
    cells: Vec<Vec<u32>>,
}

impl Bins {
    pub(super) fn new(lo: [f64; 2], hi: [f64; 2], boxes: &[([f64; 2], [f64; 2])]) -> Bins {
        let nx = (((hi[0] - lo[0]) / BIN).ceil() as usize).max(1);
        let ny = (((hi[1] - lo[1]) / BIN).ceil() as usize).max(1);
        let mut cells = vec![Vec::new(); nx * ny];
        for (k, (a, b)) in boxes.iter().enumerate() {
            let (i0, j0) = Self::cell(lo, nx, ny, *a);
            let (i1, j1) = Self::cell(lo, nx, ny, *b);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    cells[j * nx + i].push(k as u32);
                }
            }
        }
        Bins { lo, nx, ny, cells }
    }

    fn cell(lo: [f64; 2], nx: usize, ny: usize, p: [f64; 2]) -> (usize, usize) {
        let i = ((p[0] - lo[0]) / BIN).floor().clamp(0.0, (nx - 1) as f64) as usize;
        let j = ((p[1] - lo[1]) / BIN).floor().clamp(0.0, (ny - 1) as f64) as usize;
        (i, j)
    }

    /// The items in the cells that a disc of radius `r` about `p` touches
    /// (an item may come more than once).
    pub(super) fn near(&self, p: [f64; 2], r: f64) -> impl Iterator<Item = usize> + '_ {
        let (i0, j0) = Self::cell(self.lo, self.nx, self.ny, [p[0] - r, p[1] - r]);
        let (i1, j1) = Self::cell(self.lo, self.nx, self.ny, [p[0] + r, p[1] + r]);
        (j0..=j1).flat_map(move |j| {
            (i0..=i1).flat_map(move |i| self.cells[j * self.nx + i].iter().map(|&k| k as usize))
        })
    }
}

pub(super) fn xy_box(pts: &[V3]) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in pts {
        for a in 0..2 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    (lo, hi)
}

/// The ball's centre segments of the feed moves (arcs as chords within
/// `tol`), each with its line.
fn centre_segments(moves: &[Move], r: f64, tol: f64) -> Vec<(V3, V3, usize)> {
    let up = |p: V3| [p[0], p[1], p[2] + r];
    moves
        .iter()
        .filter(|m| !m.rapid)
        .flat_map(|m| {
            m.pieces(tol)
                .into_iter()
                .map(move |s| (up(s.a), up(s.b), m.line))
        })
        .collect()
}

/// See the module docs: the walls of `part` against the feed moves of
/// `moves` cut with a ball of radius `r` (chords of arcs within `tol`).
/// `None` when the part has no wall triangle.
pub(crate) fn ball_left_on_walls(
    part: &PartModel,
    moves: &[Move],
    r: f64,
    tol: f64,
) -> Option<WallLeft> {
    let walls: Vec<(V3, V3)> = if part.wall_points.is_empty() {
        wall_centroids(&part.triangles)
    } else {
        part.wall_points.clone()
    };
    if walls.is_empty() {
        return None;
    }
    let segs = centre_segments(moves, r, tol);
    let all: Vec<V3> = part.triangles.iter().flatten().copied().collect();
    let (lo, hi) = xy_box(&all);
    let seg_bins = Bins::new(
        lo,
        hi,
        &segs.iter().map(|s| xy_box(&[s.0, s.1])).collect::<Vec<_>>(),
    );
    let tri_bins = Bins::new(
        lo,
        hi,
        &part.triangles.iter().map(|t| xy_box(t)).collect::<Vec<_>>(),
    );
    // Material left at every wall point, then the reach test from the
    // largest down: the first point the ball reaches holds the maximum.
    let mut left: Vec<(f64, usize, usize)> = walls
        .par_iter()
        .enumerate()
        .map(|(k, &(p, _))| {
            let (d, line) = seg_bins
                .near([p[0], p[1]], r + FAR)
                .map(|i| (segment_distance(p, segs[i].0, segs[i].1), segs[i].2))
                .fold((r + FAR, 0), |a, b| if b.0 < a.0 { b } else { a });
            ((d - r).max(0.0), line, k)
        })
        .collect();
    left.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.2.cmp(&b.2)));
    let reaches = |k: usize| {
        let (p, n) = walls[k];
        let c: V3 = (v(p) + v(n) * r).into();
        tri_bins
            .near([c[0], c[1]], r)
            .all(|i| triangle_distance(c, &part.triangles[i]) >= r - ENTER)
    };
    let found = left.iter().find(|&&(_, _, k)| reaches(k));
    let (value, line, k) = found.copied().unwrap_or((0.0, 0, 0));
    Some(WallLeft {
        left: Worst { value, line },
        program: None,
        at: walls[k].0,
        points: walls.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_distance_to_a_triangle_is_the_plane_s_inside_and_the_edge_s_outside() {
        let t = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]];
        assert!((triangle_distance([0.5, 0.5, 3.0], &t) - 3.0).abs() < 1e-12);
        assert!((triangle_distance([1.0, -1.0, 0.0], &t) - 1.0).abs() < 1e-12);
        let far = triangle_distance([3.0, 3.0, 0.0], &t);
        assert!((far - (2.0f64.sqrt() * 2.0)).abs() < 1e-12, "{far}");
        assert!((triangle_distance([-3.0, -4.0, 0.0], &t) - 5.0).abs() < 1e-12);
    }

    /// A wall z = x·tan θ over x ∈ [0, 2] (y ∈ [−3, 3]) between a floor at 0
    /// and a top at 2·tan θ, as 0.1 mm strips.
    fn ramp(theta: f64) -> PartModel {
        let t = theta.tan();
        let z = |x: f64| t * x.clamp(0.0, 2.0);
        let mut tris = Vec::new();
        for i in -30..50 {
            let (x0, x1) = (i as f64 * 0.1, (i + 1) as f64 * 0.1);
            tris.push([[x0, -3.0, z(x0)], [x1, -3.0, z(x1)], [x1, 3.0, z(x1)]]);
            tris.push([[x0, -3.0, z(x0)], [x1, 3.0, z(x1)], [x0, 3.0, z(x0)]]);
        }
        PartModel {
            name: "ramp".into(),
            triangles: tris,
            ..PartModel::default()
        }
    }

    fn feed(line: usize, a: V3, b: V3) -> Move {
        Move {
            line,
            rapid: false,
            from: a,
            to: b,
            arc: None,
        }
    }

    /// The ball (radius r) touching the ramp of [`ramp`] at x along y:
    /// its centre r along the normal, its tip r under that.
    fn pass(line: usize, x: f64, theta: f64, r: f64) -> Move {
        let (s, c) = theta.sin_cos();
        let centre = [x - r * s, 0.0, x * theta.tan() + r * c];
        feed(
            line,
            [centre[0], -3.0, centre[2] - r],
            [centre[0], 3.0, centre[2] - r],
        )
    }

    fn strips(part: &PartModel, keep: impl Fn(f64) -> bool) -> PartModel {
        let triangles = part
            .triangles
            .iter()
            .filter(|t| keep((t[0][0] + t[1][0] + t[2][0]) / 3.0))
            .copied()
            .collect();
        PartModel {
            triangles,
            ..part.clone()
        }
    }

    #[test]
    fn between_two_passes_on_a_slope_the_cusp_is_left() {
        let (theta, r) = (30f64.to_radians(), 1.0);
        // The strips between the passes' contacts at x = 0.8 and 1.2, and
        // the floor and top: w = 0.4/cos θ apart along the slope.
        let part = strips(&ramp(theta), |x| {
            (0.8..1.2).contains(&x) || !(0.0..2.0).contains(&x)
        });
        let moves = [pass(1, 0.8, theta, r), pass(2, 1.2, theta, r)];
        let got = ball_left_on_walls(&part, &moves, r, 1e-3).unwrap();
        let w = 0.4 / theta.cos();
        let cusp = r - (r * r - w * w / 4.0).sqrt();
        // The triangles' centroids (x0 + 0.1/3 and x0 + 0.2/3 in each
        // strip) nearest the cusp's ridge at x = 1 lie 0.1/3 off it, L =
        // 0.2 − 0.1/3 in plan from a contact: √(r² + (L/cos θ)²) − r.
        let l = (0.2 - 0.1 / 3.0) / theta.cos();
        let expect = (r * r + l * l).sqrt() - r;
        assert!(
            got.left.value <= cusp && (got.left.value - expect).abs() < 1e-9,
            "{} vs {expect}, cusp {cusp}",
            got.left.value
        );
        assert_eq!(got.points, 8);
    }

    #[test]
    fn a_ball_does_not_reach_into_the_concave_crease_at_the_wall_s_foot() {
        let (theta, r) = (30f64.to_radians(), 1.0);
        let c = theta.cos();
        let part = ramp(theta);
        // One pass touching at x = 1.2: the farthest wall point it leaves
        // uncut that a ball can touch is the lowest strip whose ball stays
        // out of the floor: x·tan θ + r·cos θ ≥ r, x ≥ r(1 − cos θ)/tan θ
        // = 0.232; the triangles' centroids are at 0.1·k + 0.1/3 and
        // 0.1·k + 0.2/3, the first past it 0.2 + 0.1/3.
        let got = ball_left_on_walls(&part, &[pass(7, 1.2, theta, r)], r, 1e-3).unwrap();
        assert_eq!(got.points, 40);
        assert!((r * (1.0 - c) / theta.tan() - 0.232).abs() < 1e-3);
        let x = 0.2 + 0.1 / 3.0;
        assert!((got.at[0] - x).abs() < 1e-9, "{:?}", got.at);
        // Its material: from there to the ball along the slope, L = (1.2 −
        // x)/cos θ from the contact: √(r² + L²) − r.
        let l = (1.2 - x) / c;
        let expect = (r * r + l * l).sqrt() - r;
        assert!(
            (got.left.value - expect).abs() < 1e-6,
            "{} vs {expect}",
            got.left.value
        );
        assert_eq!(got.left.line, 7);
    }
}
