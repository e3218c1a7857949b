//! A DXF drawing's entities as paths in the plane: LINE, CIRCLE, ARC,
//! ELLIPSE, LWPOLYLINE and POLYLINE (bulges as circular arcs), SPLINE (control
//! points, knots, weights), and INSERT of a block (base point, scale, rotation,
//! extrusion, MINSERT rows and columns; nested to [`MAX_DEPTH`]). Every other
//! entity (text, dimensions, hatches, points, meshes, ...) is not read.
//!
//! Coordinates: LINE, ELLIPSE and SPLINE are in world coordinates; CIRCLE,
//! ARC, LWPOLYLINE, 2-D POLYLINE and INSERT in their object coordinate system
//! (OCS), found from the extrusion direction by the DXF reference's arbitrary
//! axis algorithm. Everything is then seen from above (z dropped), in drawing
//! units.

use std::collections::{BTreeSet, HashMap};
use std::f64::consts::TAU;

use dxf::entities::{Entity, EntityType};
use dxf::{Block, Drawing};

use super::super::Vec2;
use super::curves::{Affine3, Nurbs, Path, Piece, P3};

/// Deepest nesting of INSERTs (a block that inserts itself stops here).
pub(crate) const MAX_DEPTH: usize = 16;

/// Most entities visited, block copies included: each is at least one vertex
/// (the outlines' bound is 500 000), so more is refused before the work.
pub(crate) const MAX_ENTITIES: usize = 500_000;

/// What the drawing gives on the chosen layer.
pub(crate) struct Read {
    /// The paths, in drawing units.
    pub(crate) paths: Vec<Path>,
    /// Every layer that has an entity pfcam reads (as written in the file).
    pub(crate) layers: BTreeSet<String>,
}

/// The paths of every entity pfcam reads on `layer` (every layer when `None`;
/// names compare without case, as CAD programs do). Entities inside a block on
/// layer `0` take the layer of their INSERT. Paper space and invisible
/// entities are left out.
pub(crate) fn read(drawing: &Drawing, layer: Option<&str>) -> Result<Read, String> {
    let mut w = Walker {
        blocks: drawing
            .blocks()
            .map(|b| (b.name.to_lowercase(), b))
            .collect(),
        layer: layer.map(str::to_lowercase),
        out: Read {
            paths: Vec::new(),
            layers: BTreeSet::new(),
        },
        count: 0,
    };
    let top: Vec<&Entity> = drawing
        .entities()
        .filter(|e| !e.common.is_in_paper_space)
        .collect();
    w.walk(&top, &Affine3::IDENTITY, "0", 0)?;
    Ok(w.out)
}

struct Walker<'a> {
    blocks: HashMap<String, &'a Block>,
    layer: Option<String>,
    out: Read,
    count: usize,
}

/// "SPLINE (handle 2A, layer L)", for messages.
fn name(e: &Entity, what: &str) -> String {
    format!(
        "{what} (handle {}, layer {})",
        e.common.handle.as_string(),
        e.common.layer
    )
}

fn p3(p: &dxf::Point) -> P3 {
    [p.x, p.y, p.z]
}

impl<'a> Walker<'a> {
    fn walk(
        &mut self,
        es: &[&'a Entity],
        xf: &Affine3,
        parent: &str,
        depth: usize,
    ) -> Result<(), String> {
        for e in es {
            self.count += 1;
            if self.count > MAX_ENTITIES {
                return Err(format!(
                    "has more than {MAX_ENTITIES} entities (block copies counted): simplify it"
                ));
            }
            if !e.common.is_visible {
                continue;
            }
            let layer = if e.common.layer == "0" {
                parent
            } else {
                &e.common.layer
            };
            if let EntityType::Insert(ins) = &e.specific {
                self.insert(e, ins, xf, layer, depth)?;
                continue;
            }
            let Some(paths) = paths_of(e, xf)? else {
                continue;
            };
            self.out.layers.insert(layer.to_string());
            if self
                .layer
                .as_ref()
                .is_none_or(|l| *l == layer.to_lowercase())
            {
                self.out.paths.extend(paths);
            }
        }
        Ok(())
    }

    /// The block's entities through the INSERT's transform, once per row and
    /// column: OCS · T(location) · R(rotation) · T(column, row spacing) ·
    /// S(scales) · T(−base point).
    fn insert(
        &mut self,
        e: &Entity,
        ins: &'a dxf::entities::Insert,
        xf: &Affine3,
        layer: &str,
        depth: usize,
    ) -> Result<(), String> {
        let what = || name(e, &format!("INSERT of block \"{}\"", ins.name));
        if depth >= MAX_DEPTH {
            return Err(format!(
                "nests INSERTs deeper than {MAX_DEPTH} at {} (does a block insert itself?)",
                what()
            ));
        }
        let Some(block) = self.blocks.get(&ins.name.to_lowercase()).copied() else {
            return Err(format!("has an {} but no such block", what()));
        };
        let ocs = ocs(p3_of_vec(&ins.extrusion_direction))
            .ok_or_else(|| format!("has an {} with no extrusion direction", what()))?;
        let base = p3(&block.base_point);
        let head = xf
            .after(&ocs)
            .after(&Affine3::translate(p3(&ins.location)))
            .after(&Affine3::rotate_z(ins.rotation.to_radians()));
        let tail = Affine3::scale([ins.x_scale_factor, ins.y_scale_factor, ins.z_scale_factor])
            .after(&Affine3::translate([-base[0], -base[1], -base[2]]));
        let entities: Vec<&Entity> = block.entities.iter().collect();
        for r in 0..ins.row_count.max(1) {
            for c in 0..ins.column_count.max(1) {
                let cell = [
                    f64::from(c) * ins.column_spacing,
                    f64::from(r) * ins.row_spacing,
                    0.0,
                ];
                let m = head.after(&Affine3::translate(cell)).after(&tail);
                if !m.is_finite() {
                    return Err(format!("has an {} whose transform is not finite", what()));
                }
                self.walk(&entities, &m, layer, depth + 1)?;
                self.count += 1;
                if self.count > MAX_ENTITIES {
                    return Err(format!(
                        "has more than {MAX_ENTITIES} entities (block copies counted): simplify it"
                    ));
                }
            }
        }
        Ok(())
    }
}

fn p3_of_vec(v: &dxf::Vector) -> P3 {
    [v.x, v.y, v.z]
}

fn cross(a: P3, b: P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn unit(a: P3) -> Option<P3> {
    let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    (n > 0.0 && n.is_finite()).then(|| [a[0] / n, a[1] / n, a[2] / n])
}

/// The object coordinate system of extrusion direction `n` (the DXF
/// reference's arbitrary axis algorithm): Ax = Wy × N when N is within 1/64 of
/// the z axis in x and y, else Wz × N; Ay = N × Ax. `None` for a zero `n`.
pub(crate) fn ocs(n: P3) -> Option<Affine3> {
    let n = unit(n)?;
    let ax = if n[0].abs() < 1.0 / 64.0 && n[1].abs() < 1.0 / 64.0 {
        cross([0.0, 1.0, 0.0], n)
    } else {
        cross([0.0, 0.0, 1.0], n)
    };
    let ax = unit(ax)?;
    let ay = unit(cross(n, ax))?;
    Some(Affine3::axes(ax, ay, n))
}

/// The paths of one entity (not an INSERT), or `None` for an entity pfcam
/// does not read.
fn paths_of(e: &Entity, xf: &Affine3) -> Result<Option<Vec<Path>>, String> {
    let open = |pieces: Vec<Piece>| Path {
        pieces,
        closed: false,
    };
    let in_ocs = |n: &dxf::Vector, what: &str| -> Result<Affine3, String> {
        ocs(p3_of_vec(n))
            .map(|o| xf.after(&o))
            .ok_or_else(|| format!("has a {} with no extrusion direction", name(e, what)))
    };
    let path = match &e.specific {
        EntityType::Line(l) => {
            let (a, b) = (xf.point(p3(&l.p1)), xf.point(p3(&l.p2)));
            if a == b {
                return Ok(Some(Vec::new()));
            }
            open(vec![Piece::Line(a, b)])
        }
        EntityType::Circle(c) => {
            let m = in_ocs(&c.normal, "CIRCLE")?;
            Path {
                pieces: vec![circle(&m, p3(&c.center), c.radius, 0.0, TAU)],
                closed: true,
            }
        }
        EntityType::Arc(a) => {
            let m = in_ocs(&a.normal, "ARC")?;
            let t0 = a.start_angle.to_radians();
            let mut sweep = (a.end_angle - a.start_angle).rem_euclid(360.0).to_radians();
            if sweep == 0.0 {
                sweep = TAU;
            }
            open(vec![circle(&m, p3(&a.center), a.radius, t0, t0 + sweep)])
        }
        EntityType::Ellipse(el) => return ellipse(e, el, xf).map(|p| Some(vec![p])),
        EntityType::LwPolyline(p) => {
            let m = in_ocs(&p.extrusion_direction, "LWPOLYLINE")?;
            let z = e.common.elevation;
            let pts: Vec<(P3, f64)> = p
                .vertices
                .iter()
                .map(|v| ([v.x, v.y, z], v.bulge))
                .collect();
            bulged(&m, &pts, p.is_closed())
        }
        EntityType::Polyline(p) => return polyline(e, p, xf),
        EntityType::Spline(s) => open(vec![Piece::Spline(spline(e, s, xf)?)]),
        _ => return Ok(None),
    };
    Ok(Some(vec![path]))
}

/// The circle of radius r about `c` (in the frame `m` maps) from t0 to t1.
fn circle(m: &Affine3, c: P3, r: f64, t0: f64, t1: f64) -> Piece {
    Piece::Conic {
        c: m.point(c),
        u: m.vector([r, 0.0, 0.0]),
        v: m.vector([0.0, r, 0.0]),
        t0,
        t1,
    }
}

/// ELLIPSE: centre and major axis in world coordinates, the minor axis
/// ratio × (N × major), parameters from start to end counter-clockwise about N.
fn ellipse(e: &Entity, el: &dxf::entities::Ellipse, xf: &Affine3) -> Result<Path, String> {
    let n = unit(p3_of_vec(&el.normal))
        .ok_or_else(|| format!("has an {} with no normal", name(e, "ELLIPSE")))?;
    let major = p3_of_vec(&el.major_axis);
    let minor = cross(n, major).map(|v| v * el.minor_axis_ratio);
    let (t0, mut t1) = (el.start_parameter, el.end_parameter);
    if t1 <= t0 {
        t1 += TAU;
    }
    let full = (t1 - t0 - TAU).abs() < 1e-9;
    Ok(Path {
        pieces: vec![Piece::Conic {
            c: xf.point(p3(&el.center)),
            u: xf.vector(major),
            v: xf.vector(minor),
            t0,
            t1: if full { t0 + TAU } else { t1 },
        }],
        closed: full,
    })
}

/// POLYLINE: a 2-D one (OCS, bulges) or a 3-D one (world, straight); meshes
/// and spline frame control points are not read.
fn polyline(
    e: &Entity,
    p: &dxf::entities::Polyline,
    xf: &Affine3,
) -> Result<Option<Vec<Path>>, String> {
    const IS_3D: i32 = 8;
    const MESH: i32 = 16 | 64;
    const FRAME_POINT: i32 = 16;
    if p.flags & MESH != 0 {
        return Ok(None);
    }
    let vs = p.vertices().filter(|v| v.flags & FRAME_POINT == 0);
    let (m, pts): (Affine3, Vec<(P3, f64)>) = if p.flags & IS_3D != 0 {
        (*xf, vs.map(|v| (p3(&v.location), 0.0)).collect())
    } else {
        let o = ocs(p3_of_vec(&p.normal))
            .ok_or_else(|| format!("has a {} with no extrusion direction", name(e, "POLYLINE")))?;
        let z = p.location.z;
        (
            xf.after(&o),
            vs.map(|v| ([v.location.x, v.location.y, z], v.bulge))
                .collect(),
        )
    };
    Ok(Some(vec![bulged(&m, &pts, p.flags & 1 != 0)]))
}

/// A polyline's vertices (OCS points with the bulge of the segment that
/// starts there) as lines and arcs. Bulge b = tan(θ/4) for the arc's included
/// angle θ (counter-clockwise when b > 0); the centre is the chord's midpoint
/// plus (1 − b²)/(4b) times the chord turned a quarter left.
fn bulged(m: &Affine3, pts: &[(P3, f64)], closed: bool) -> Path {
    let n = pts.len();
    let segs = if closed { n } else { n.saturating_sub(1) };
    let mut pieces = Vec::with_capacity(segs);
    for i in 0..segs {
        let ((a, b), (q, _)) = (pts[i], pts[(i + 1) % n]);
        let (pa, pq) = (Vec2::new(a[0], a[1]), Vec2::new(q[0], q[1]));
        if pa == pq {
            continue;
        }
        if b == 0.0 || !b.is_finite() {
            pieces.push(Piece::Line(m.point(a), m.point(q)));
            continue;
        }
        let d = pq - pa;
        let c = (pa + pq) * 0.5 + d.perp() * ((1.0 - b * b) / (4.0 * b));
        let r = pa.dist(c);
        let t0 = (pa - c).y.atan2((pa - c).x);
        pieces.push(circle(m, [c.x, c.y, a[2]], r, t0, t0 + 4.0 * b.atan()));
    }
    Path {
        pieces,
        closed: closed && n > 1,
    }
}

/// SPLINE from its control points, knots and weights (fit points alone are
/// not read).
fn spline(e: &Entity, s: &dxf::entities::Spline, xf: &Affine3) -> Result<Nurbs, String> {
    let what = || name(e, "SPLINE");
    let n = s.control_points.len();
    if n == 0 {
        return Err(format!(
            "has a {} given by fit points only, which pfcam does not read: save it with control points (in most CAD programs, convert the spline's fit points to control vertices)",
            what()
        ));
    }
    let p = usize::try_from(s.degree_of_curve).unwrap_or(0);
    if !(1..=25).contains(&p) || n <= p {
        return Err(format!("has a {} of degree {} with {n} control points: the degree must be 1 to 25 and below the number of points", what(), s.degree_of_curve));
    }
    let knots = s.knot_values.clone();
    if knots.len() != n + p + 1 {
        return Err(format!(
            "has a {} with {} knots for {n} control points of degree {p}: it needs {}",
            what(),
            knots.len(),
            n + p + 1
        ));
    }
    if knots.iter().any(|k| !k.is_finite())
        || knots.windows(2).any(|w| w[1] < w[0])
        || knots[n] <= knots[p]
    {
        return Err(format!(
            "has a {} whose knots are not finite and nondecreasing over a non-empty range",
            what()
        ));
    }
    let weights = if s.weight_values.is_empty() {
        vec![1.0; n]
    } else {
        s.weight_values.clone()
    };
    if weights.len() != n || weights.iter().any(|w| !(w.is_finite() && *w > 0.0)) {
        return Err(format!(
            "has a {} with {} weights for {n} control points (each must be a positive number)",
            what(),
            weights.len()
        ));
    }
    Ok(Nurbs {
        degree: p,
        knots,
        points: s.control_points.iter().map(|q| xf.point(p3(q))).collect(),
        weights,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn the_arbitrary_axis_algorithm_mirrors_x_for_a_downward_extrusion() {
        let up = ocs([0.0, 0.0, 1.0]).unwrap();
        assert_eq!(up, Affine3::IDENTITY);
        let down = ocs([0.0, 0.0, -2.0]).unwrap();
        assert!(down.point([3.0, 4.0, 0.0]).dist(Vec2::new(-3.0, 4.0)) < 1e-15);
        // A tilted normal: the OCS axes are orthonormal and x lies in the
        // world's xy plane (Wz × N).
        let t = ocs([1.0, 0.0, 1.0]).unwrap();
        let ax = t.vector([1.0, 0.0, 0.0]);
        assert!((ax.norm() - 1.0).abs() < 1e-15);
        assert!(ocs([0.0, 0.0, 0.0]).is_none());
    }

    #[test]
    fn a_bulge_makes_the_arc_through_its_ends() {
        // Bulge tan(θ/4) for θ = 90°, from (1, 0) to (0, 1): the quarter of
        // the unit circle about the origin, counter-clockwise.
        let b = (PI / 8.0).tan();
        let path = bulged(
            &Affine3::IDENTITY,
            &[([1.0, 0.0, 0.0], b), ([0.0, 1.0, 0.0], 0.0)],
            false,
        );
        let Piece::Conic { c, u, v, t0, t1 } = path.pieces[0] else {
            panic!("{path:?}")
        };
        assert!(
            c.norm() < 1e-15 && (u.norm() - 1.0).abs() < 1e-15 && (v.norm() - 1.0).abs() < 1e-15
        );
        assert!(t0.abs() < 1e-15 && (t1 - PI / 2.0).abs() < 1e-15);
        // A negative bulge goes clockwise, the centre on the other side.
        let path = bulged(
            &Affine3::IDENTITY,
            &[([1.0, 0.0, 0.0], -b), ([0.0, 1.0, 0.0], 0.0)],
            false,
        );
        let end = path.pieces[0].start();
        assert!(end.dist(Vec2::new(1.0, 0.0)) < 1e-15);
        let Piece::Conic { c, t0, t1, .. } = path.pieces[0] else {
            panic!()
        };
        assert!(c.dist(Vec2::new(1.0, 1.0)) < 1e-15 && (t1 - t0 + PI / 2.0).abs() < 1e-15);
    }
}
