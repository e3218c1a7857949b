//! The final stock against the part: what the job says (tool, stepdown, stock)
//! and the part's own model, the surface S2 that `pfcam surface` writes
//! (`surface::job_surface`: walls between the level curves Γ(s_k) of the
//! shape's field, flat top and floor), never the paths that were cut.
//!
//! The part's height over each cell centre is read from S2's up-facing
//! triangles (linear interpolation in each, the highest where several cover
//! a centre). A cell lower than the part by more than the tolerance is a
//! gouge, reported at the line that last cut that cell; a cell higher than the
//! part is material left.

use super::report::{Finding, Kind, PartComparison, Worst};
use super::stock::HeightMap;
use super::{SimError, StockBox};
use crate::job::{Job, OperationKind};
use crate::surface::{job_surface, up_area, SurfaceOptions};
use std::collections::BTreeMap;

/// The part as a height field: triangles whose normal points up (+z), and
/// closed outlines whose inside (even-odd: outlines less their counters)
/// stands at `outline_z`. Where neither covers a cell it is not compared.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PartModel {
    /// What it is, for the report (`surface S2`, `glyph outlines`).
    pub name: String,
    /// Triangles (x, y, z corners, mm), each seen from above.
    pub triangles: Vec<[[f64; 3]; 3]>,
    /// Closed polygons (x, y, mm; the last point joins the first).
    pub outlines: Vec<Vec<[f64; 2]>>,
    /// Height of the outlines' inside, mm.
    pub outline_z: f64,
    /// Points on the walls with their unit normals, on the exact surface
    /// where the part has one (S2: `walls::project_walls`); empty: the wall
    /// triangles' centroids stand for them (`simulate::walls`).
    pub wall_points: Vec<([f64; 3], [f64; 3])>,
}

/// What `--job` tells the simulation.
#[derive(Clone, Debug, PartialEq)]
pub struct JobFacts {
    /// `tool.diameter`, mm.
    pub tool_diameter: f64,
    /// `tool.stepdown`, mm.
    pub stepdown: f64,
    /// The stock block (a boss's or cavity's stock rectangle, top
    /// `stock.top`); `None` for a profile (cut from a sheet of unknown size).
    pub stock: Option<StockBox>,
    /// The part's model; `None` for a profile.
    pub part: Option<PartModel>,
    /// `operation.tolerance`, mm.
    pub tolerance: f64,
    /// `operation.max_scallop`, mm.
    pub scallop: f64,
    /// `tool.stepover`, mm.
    pub stepover: f64,
}

/// The job's part could not be modelled.
fn part(e: crate::pipeline::PipelineError) -> SimError {
    SimError::Part(Box::new(e))
}

/// The job's facts; for a boss or cavity this builds S2 (an MFS solve and the
/// isobands at `surface_resolution` mm), which takes seconds.
pub fn job_facts(job: &Job, surface_resolution: f64) -> Result<JobFacts, SimError> {
    let mut facts = JobFacts {
        tool_diameter: job.tool.diameter,
        stepdown: job.tool.stepdown,
        stock: None,
        part: None,
        tolerance: job.operation.tolerance,
        // With a finishing tool, its scallop bound is what the part is held to.
        scallop: job
            .finish
            .as_ref()
            .map_or(job.operation.max_scallop, |f| f.scallop),
        stepover: job.tool.stepover,
    };
    if job.operation.kind == OperationKind::Profile {
        // The part of a profile is the shape itself, standing at the stock top
        // inside its outlines (the walls are vertical).
        let (shape, _) = crate::pipeline::job_shape(job, &mut |_| {}).map_err(part)?;
        let tol = job.operation.tolerance * crate::pipeline::FLATTEN_FRACTION;
        facts.part = Some(PartModel {
            name: "glyph outlines".into(),
            triangles: Vec::new(),
            outlines: shape
                .contours()
                .map(|c| c.flatten(tol).iter().map(|p| [p.x, p.y]).collect())
                .collect(),
            outline_z: job.stock.top,
            wall_points: Vec::new(),
        });
        return Ok(facts);
    }
    if let Some(spec) = job.shape.height_source() {
        let (lo, hi) = crate::patch::patch_stock(job, spec);
        facts.stock = Some(StockBox {
            lo: [lo.x, lo.y],
            hi: [hi.x, hi.y],
            top: job.stock.top,
        });
        facts.part = Some(PartModel {
            name: match spec {
                crate::patch::HeightSource::Bezier(_) => "harmonic patch".into(),
                crate::patch::HeightSource::Poly(_) => "polyharmonic relief".into(),
            },
            triangles: crate::patch::patch_part_triangles(job, spec, surface_resolution)
                .map_err(part)?,
            outlines: Vec::new(),
            outline_z: job.stock.top,
            wall_points: Vec::new(),
        });
        return Ok(facts);
    }
    if let crate::geometry::ShapeSource::PdeTube(spec) = &job.shape {
        let tube = crate::tube::tube_sections(spec).map_err(part)?;
        let (lo, hi) = crate::tube::tube_stock(job, &tube);
        facts.stock = Some(StockBox {
            lo: [lo.x, lo.y],
            hi: [hi.x, hi.y],
            top: job.stock.top,
        });
        facts.part = Some(PartModel {
            name: "PDE tube".into(),
            triangles: crate::tube::tube_part_triangles(job, spec, surface_resolution)
                .map_err(part)?,
            outlines: Vec::new(),
            outline_z: job.stock.top,
            wall_points: Vec::new(),
        });
        return Ok(facts);
    }
    let opts = SurfaceOptions {
        resolution: surface_resolution,
    };
    let built = job_surface(job, &opts, &mut |_| {}).map_err(|e| part(e.into()))?;
    let s = &built.surface;
    facts.stock = Some(StockBox {
        lo: [s.stock_lo.x, s.stock_lo.y],
        hi: [s.stock_hi.x, s.stock_hi.y],
        top: job.stock.top,
    });
    let mesh = &s.mesh;
    let triangles: Vec<[[f64; 3]; 3]> = (0..mesh.triangles.len())
        .map(|t| mesh.corners(t))
        .filter(|c| up_area(c) > 1e-12)
        .collect();
    let wall_points = super::walls::project_walls(&triangles, &s2_height(job, &built.field));
    facts.part = Some(PartModel {
        name: "surface S2".into(),
        triangles,
        outlines: Vec::new(),
        outline_z: job.stock.top,
        wall_points,
    });
    Ok(facts)
}

/// S2's exact height z = z(u(x, y)) and its gradient (dz/ds · ∇u, 0 where
/// u is outside φ's range: the flat top and floor).
fn s2_height<'a>(
    job: &'a Job,
    field: &'a crate::field::Field,
) -> impl Fn(f64, f64) -> (f64, [f64; 2]) + Sync + 'a {
    let cavity = job.operation.kind == OperationKind::Cavity;
    let top = job.stock.top;
    move |x, y| {
        let Some(profile) = job.profile.as_ref() else {
            return (top, [0.0, 0.0]);
        };
        let (lo, hi) = profile.s_range();
        let p = crate::geometry::Vec2::new(x, y);
        let u = field.value(p);
        let z = crate::surface::surface_z(profile, cavity, top, u.clamp(lo, hi));
        if u <= lo || u >= hi {
            return (z, [0.0, 0.0]);
        }
        let e = 1e-7 * (hi - lo);
        let (a, b) = ((u - e).max(lo), (u + e).min(hi));
        let dz = (crate::surface::surface_z(profile, cavity, top, b)
            - crate::surface::surface_z(profile, cavity, top, a))
            / (b - a);
        let g = field.grad(p);
        (z, [dz * g.x, dz * g.y])
    }
}

/// |n_z| of the triangle's unit normal: the cosine of its slope.
fn slope_cos(c: &[[f64; 3]; 3]) -> f64 {
    super::walls::unit_normal(c).map_or(1.0, |n| n[2].abs())
}

/// The part's height over every cell centre (−∞ where no triangle covers it)
/// and the cosine of its slope there (1 on flat ground and outlines).
pub fn part_surface(map: &HeightMap, part: &PartModel) -> (Vec<f64>, Vec<f64>) {
    let g = map.grid;
    let mut h = vec![f64::NEG_INFINITY; g.nx * g.ny];
    let mut cos = vec![1.0; g.nx * g.ny];
    for c in &part.triangles {
        let area = up_area(c);
        let tri_cos = slope_cos(c);
        let xs = [c[0][0], c[1][0], c[2][0]];
        let ys = [c[0][1], c[1][1], c[2][1]];
        let (Some((i0, i1)), Some((j0, j1))) = (
            g.cols(
                xs.iter().copied().fold(f64::INFINITY, f64::min),
                xs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            ),
            g.rows(
                ys.iter().copied().fold(f64::INFINITY, f64::min),
                ys.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            ),
        ) else {
            continue;
        };
        for j in j0..=j1 {
            let y = g.cy(j);
            for i in i0..=i1 {
                let x = g.cx(i);
                // Barycentric weights: each the sub-triangle's share of the area.
                let w = |a: usize, b: usize| {
                    ((c[b][0] - c[a][0]) * (y - c[a][1]) - (x - c[a][0]) * (c[b][1] - c[a][1]))
                        / area
                };
                let (l0, l1, l2) = (w(1, 2), w(2, 0), w(0, 1));
                let eps = -1e-9;
                if l0 >= eps && l1 >= eps && l2 >= eps {
                    let z = l0 * c[0][2] + l1 * c[1][2] + l2 * c[2][2];
                    let k = j * g.nx + i;
                    if z > h[k] {
                        h[k] = z;
                        cos[k] = tri_cos;
                    }
                }
            }
        }
    }
    fill_outlines(map, &part.outlines, part.outline_z, &mut h);
    (h, cos)
}

/// Raises `h` to `z` over the inside of `outlines` (even-odd), row by row: the
/// crossings of each row's centre line with the edges, sorted, pair up into
/// the inside spans.
fn fill_outlines(map: &HeightMap, outlines: &[Vec<[f64; 2]>], z: f64, h: &mut [f64]) {
    let g = map.grid;
    let mut xs = Vec::new();
    for j in 0..g.ny {
        let y = g.cy(j);
        xs.clear();
        for poly in outlines {
            for (k, a) in poly.iter().enumerate() {
                let b = poly[(k + 1) % poly.len()];
                // Half-open in y, so a vertex on the line counts once.
                if (a[1] <= y) != (b[1] <= y) {
                    xs.push(a[0] + (y - a[1]) / (b[1] - a[1]) * (b[0] - a[0]));
                }
            }
        }
        xs.sort_by(f64::total_cmp);
        for pair in xs.chunks_exact(2) {
            if let Some((i0, i1)) = g.cols(pair[0], pair[1]) {
                for v in &mut h[j * g.nx + i0..=j * g.nx + i1] {
                    *v = v.max(z);
                }
            }
        }
    }
}

/// Whether (x, y) lies within `tol` of an edge of the outlines.
fn near_outline(outlines: &[Vec<[f64; 2]>], x: f64, y: f64, tol: f64) -> bool {
    outlines.iter().any(|poly| {
        (0..poly.len()).any(|k| {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let l2 = dx * dx + dy * dy;
            let t = if l2 > 0.0 {
                (((x - a[0]) * dx + (y - a[1]) * dy) / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (a[0] + t * dx - x).hypot(a[1] + t * dy - y) <= tol
        })
    })
}

/// The reach `r` (the envelope of the tips `drops` on the cells) at the
/// cells `over` (where the envelope on the cells'
/// heights reads more than half the bound, scallop + tolerance, left) raised by a ball's exact drops
/// onto the part's triangles ([`super::reach::refine`]); other tools and
/// parts without triangles keep the cells' envelope.
fn exact_reach(
    g: &super::stock::Grid,
    drops: &[f64],
    tool: &super::tool::Tool,
    part: &PartModel,
    r: &mut [f64],
    over: &[usize],
) {
    if over.is_empty() || part.triangles.is_empty() || tool.shape() != super::ToolShape::Ball {
        return;
    }
    let all: Vec<[f64; 3]> = part.triangles.iter().flatten().copied().collect();
    let (lo, hi) = super::walls::xy_box(&all);
    let boxes: Vec<_> = part
        .triangles
        .iter()
        .map(|t| super::walls::xy_box(t))
        .collect();
    let bins = super::walls::Bins::new(lo, hi, &boxes);
    let rad = tool.radius();
    let top: Vec<f64> = part
        .triangles
        .iter()
        .map(|t| t[0][2].max(t[1][2]).max(t[2][2]))
        .collect();
    // A triangle whose top is under `floor` cannot lift the tip over it.
    let drop_at = |x: f64, y: f64, floor: f64| -> Option<f64> {
        let z = bins
            .near([x, y], rad)
            .filter(|&i| top[i] > floor)
            .map(|i| super::balldrop::ball_on_triangle(&part.triangles[i], x, y, rad))
            .fold(f64::NEG_INFINITY, f64::max);
        z.is_finite().then_some(z - rad)
    };
    super::reach::refine(g, drops, tool, r, over, &drop_at);
}

/// Compares the stock with the part; adds one [`Kind::Gouge`] finding per line
/// whose cuts lie below the part by more than the tolerance.
pub(crate) fn compare(
    map: &HeightMap,
    part: &PartModel,
    job: &JobFacts,
    tool: Option<&super::tool::Tool>,
    findings: &mut Vec<Finding>,
) -> PartComparison {
    let g = map.grid;
    let (ph, cos) = part_surface(map, part);
    // What the last tool can reach of the part (`reach`): the material
    // above it is the programs' to remove.
    let drops = tool.map(|t| super::reach::drops(&g, &ph, t));
    let mut reach = tool
        .zip(drops.as_ref())
        .map(|(t, d)| super::reach::envelope_of_drops(&g, d, t));
    if let (Some(r), Some(t), Some(d)) = (reach.as_mut(), tool, drops.as_ref()) {
        // Half the bound (scallop + tolerance): the largest figure left
        // unrefined is under it, so any near the bound is exact.
        let bound = 0.5 * (job.scallop + job.tolerance);
        let over: Vec<usize> = (0..ph.len())
            .filter(|&k| {
                ph[k] != f64::NEG_INFINITY
                    && r[k].is_finite()
                    && (map.h[k] - r[k].max(ph[k])) * cos[k] > bound
            })
            .collect();
        exact_reach(&g, d, t, part, r, &over);
    }
    let mut max_left_reachable = Worst::default();
    let mut cells = 0;
    let mut max_gouge = Worst::default();
    let mut max_left = Worst::default();
    let mut gouged = 0;
    let mut over_scallop = 0;
    let mut by_line: BTreeMap<u32, (f64, usize)> = BTreeMap::new();
    for (k, (&p, &h)) in ph.iter().zip(&map.h).enumerate() {
        if p == f64::NEG_INFINITY {
            continue;
        }
        cells += 1;
        let line = map.last_cut[k];
        // Below the part, the depth is measured along the surface's normal
        // (the vertical depth times the cosine of the slope): on a wall at 80°
        // a cut 0.006 mm into it is 0.035 mm below it vertically. Material
        // left is measured vertically.
        let mut gouge = if p > h { (p - h) * cos[k] } else { p - h };
        // An outline's walls are vertical: a cut into it is measured across,
        // and one within the tolerance of the wall is no gouge.
        if gouge > 0.0
            && near_outline(
                &part.outlines,
                g.cx(k % g.nx),
                g.cy(k / g.nx),
                job.tolerance,
            )
        {
            gouge = 0.0;
        }
        max_gouge.take(gouge, line as usize);
        max_left.take(-gouge, line as usize);
        if let Some(r) = &reach {
            // Along the surface's normal, as a scallop is: on a wall at 80°
            // a ridge 0.01 mm proud stands 0.06 mm over it vertically.
            let floor = if r[k].is_finite() { r[k].max(p) } else { p };
            max_left_reachable.take((h - floor) * cos[k], line as usize);
        }
        if gouge > job.tolerance {
            gouged += 1;
            let e = by_line.entry(line).or_insert((0.0, k));
            if gouge > e.0 {
                *e = (gouge, k);
            }
        }
        if -gouge > job.scallop + job.tolerance {
            over_scallop += 1;
        }
    }
    for (line, (depth, k)) in by_line {
        let (x, y) = (g.cx(k % g.nx), g.cy(k / g.nx));
        findings.push(Finding {
            line: line as usize,
            kind: Kind::Gouge,
            depth,
            x,
            y,
            message: format!(
                "gouge: cuts {depth:.4} mm below the part ({}) at X{x:.3} Y{y:.3}, more than the tolerance {} mm",
                part.name, job.tolerance
            ),
        });
    }
    PartComparison {
        model: part.name.clone(),
        cells,
        max_gouge,
        max_gouge_program: None,
        gouged_cells: gouged,
        max_left,
        max_left_program: None,
        max_left_reachable,
        max_left_reachable_program: None,
        walls: None,
        left_share_over_scallop: if cells > 0 {
            over_scallop as f64 / cells as f64
        } else {
            0.0
        },
        tolerance: job.tolerance,
        scallop: job.scallop,
        stepover: job.stepover,
    }
}
