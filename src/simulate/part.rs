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
use crate::surface::{job_surface, SurfaceOptions};
use std::collections::BTreeMap;

/// The part as a height field: triangles whose normal points up (+z).
#[derive(Clone, Debug, PartialEq)]
pub struct PartModel {
    /// What it is, for the report (`surface S2`).
    pub name: String,
    /// Triangles (x, y, z corners, mm), each seen from above.
    pub triangles: Vec<[[f64; 3]; 3]>,
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

/// The job's facts; for a boss or cavity this builds S2 (an MFS solve and the
/// isobands at `surface_resolution` mm), which takes seconds.
pub fn job_facts(job: &Job, surface_resolution: f64) -> Result<JobFacts, SimError> {
    let mut facts = JobFacts {
        tool_diameter: job.tool.diameter,
        stepdown: job.tool.stepdown,
        stock: None,
        part: None,
        tolerance: job.operation.tolerance,
        scallop: job.operation.max_scallop,
        stepover: job.tool.stepover,
    };
    if job.operation.kind == OperationKind::Profile {
        return Ok(facts);
    }
    let opts = SurfaceOptions {
        resolution: surface_resolution,
    };
    let built = job_surface(job, &opts, &mut |_| {}).map_err(|e| SimError::Part(e.to_string()))?;
    let s = &built.surface;
    facts.stock = Some(StockBox {
        lo: [s.stock_lo.x, s.stock_lo.y],
        hi: [s.stock_hi.x, s.stock_hi.y],
        top: job.stock.top,
    });
    let mesh = &s.mesh;
    let triangles = (0..mesh.triangles.len())
        .map(|t| mesh.corners(t))
        .filter(|c| up_area(c) > 1e-12)
        .collect();
    facts.part = Some(PartModel {
        name: "surface S2".into(),
        triangles,
    });
    Ok(facts)
}

/// Twice the signed XY area of a triangle: positive when its corners run
/// counter-clockwise seen from above, i.e. its normal points up.
fn up_area(c: &[[f64; 3]; 3]) -> f64 {
    (c[1][0] - c[0][0]) * (c[2][1] - c[0][1]) - (c[2][0] - c[0][0]) * (c[1][1] - c[0][1])
}

/// The part's height over every cell centre (−∞ where no triangle covers it).
pub fn part_heights(map: &HeightMap, part: &PartModel) -> Vec<f64> {
    let g = map.grid;
    let mut h = vec![f64::NEG_INFINITY; g.nx * g.ny];
    for c in &part.triangles {
        let area = up_area(c);
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
                    h[k] = h[k].max(z);
                }
            }
        }
    }
    h
}

/// Compares the stock with the part; adds one [`Kind::Gouge`] finding per line
/// whose cuts lie below the part by more than the tolerance.
pub fn compare(
    map: &HeightMap,
    part: &PartModel,
    job: &JobFacts,
    findings: &mut Vec<Finding>,
) -> PartComparison {
    let g = map.grid;
    let ph = part_heights(map, part);
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
        let gouge = p - h;
        max_gouge.take(gouge, line as usize);
        max_left.take(-gouge, line as usize);
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
        gouged_cells: gouged,
        max_left,
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
