//! Finishing (issue 14): the second program of a job with a `[finish]` tool.
//! The roughing leaves `operation.stock_to_leave` on the walls; the finisher
//! follows the modelled surface S2 along the equipotentials Γ(s_k) of the
//! shape's field ([`passes`]), its axis where the cutter touches S2 at the
//! contact points and its height from a drop-cutter against S2's mesh
//! ([`path`]), so that it never enters the part by construction; `pfcam
//! simulate` checks the two programs against the part independently.

pub(crate) mod corner;
pub(crate) mod geodesic;
pub(crate) mod passes;
pub(crate) mod path;

use crate::field::isolines::Grid;
use crate::field::level;
use crate::field::Field;
use crate::geometry::Vec2;
use crate::job::{Finish, Job};
use crate::levels::DepthProfile;
use crate::toolpath::dropcutter::{Cutter, MeshIndex};
use crate::toolpath::Toolpath;

/// Why a finishing program (`[finish]`) could not be made: the boss's or
/// cavity's passes ([`finish`]), a tube's rings (`tube::rings`) or a patch's
/// raster (`patch::raster`). Each message is the one the user reads after
/// `finishing: `.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FinishError {
    /// A boss or cavity without a `[profile]` (φ(s) gives S2's heights).
    #[error("a boss or cavity needs a [profile]")]
    NoProfile,
    /// The wall's foot Γ(`foot`) has no curve to start the passes from.
    #[error("the foot of the wall Γ({foot:.4}) has no curve")]
    FootWithoutCurve {
        /// The foot's s.
        foot: f64,
    },
    /// ∇u vanishes on a candidate level Γ(`s`), so its spacing is unknown.
    #[error("∇u vanishes on Γ({s:.5})")]
    GradientVanishes {
        /// The level's s.
        s: f64,
    },
    /// The geodesic pattern's wall needs `n` passes, more than `max`.
    #[error("the wall needs {n} finishing passes, more than {max}: raise finish.scallop or use a larger finishing tool")]
    TooManyPasses {
        /// Passes needed.
        n: usize,
        /// The most allowed.
        max: usize,
    },
    /// The equipotential pattern's candidate levels passed `max` passes.
    #[error("the wall needs more than {max} finishing passes: raise finish.scallop or use a larger finishing tool")]
    TooManyLevels {
        /// The most allowed.
        max: usize,
    },
    /// No triangle of S2 lies under the finishing tool's axis at (`x`, `y`).
    #[error("no part of the surface lies under the finishing tool at X{x:.3} Y{y:.3}")]
    NothingUnder {
        /// The axis's x, mm.
        x: f64,
        /// The axis's y, mm.
        y: f64,
    },
    /// A flat finishing cutter on a tube's curved wall.
    #[error("finish.shape = \"flat\" cannot follow a curved wall within the tolerance (its edge leaves a stair): use \"ball\" or \"bull\"")]
    FlatOnWall,
    /// A flat finishing cutter on a patch's curved surface.
    #[error("finish.shape = \"flat\" cannot finish a curved surface by parallel passes within the tolerance (its edge leaves a stair): use \"ball\" or \"bull\"")]
    FlatOnSurface,
    /// A tube whose trims are not one slot less than π wide.
    #[error("the finishing rings follow one trim less than π wide only")]
    RingTrims,
    /// A tube's section at `u` that the slot cuts into more than one piece.
    #[error("the section at u = {u:.4} is not one piece: the finishing rings follow one slot")]
    SectionPieces {
        /// The section's parameter.
        u: f64,
    },
    /// More than `max` rings.
    #[error("the finish would take more than {max} rings: raise finish.scallop, or use a larger finishing tool")]
    TooManyRings {
        /// The most rings allowed.
        max: usize,
    },
    /// More than `max` samples over all the rings.
    #[error("the finish would take {rings} rings of {samples} samples (at most {max} samples): raise finish.scallop or use a larger finishing tool")]
    TooManyRingSamples {
        /// Rings planned.
        rings: usize,
        /// Samples per ring.
        samples: usize,
        /// The most samples allowed.
        max: usize,
    },
    /// The ring heights stopped rising: a broken invariant of the planner.
    #[error("the finishing rings do not advance at z = {z:.4} mm (please report this pfcam bug)")]
    RingsStall {
        /// Where they stopped (relative to the top), mm.
        z: f64,
    },
    /// A raster with more passes or samples than allowed.
    #[error("the raster would take {passes} passes of {samples} samples (at most {max_passes} passes, {max_samples} samples): raise finish.scallop or operation.tolerance, or use a larger finishing tool")]
    TooManyRasterSamples {
        /// Passes planned.
        passes: usize,
        /// Samples per pass.
        samples: usize,
        /// The most passes allowed.
        max_passes: usize,
        /// The most samples allowed.
        max_samples: usize,
    },
}

/// What the finisher needs besides the mesh.
pub(crate) struct FinishParams<'a> {
    /// The cutter.
    pub(crate) cutter: Cutter,
    /// φ(s).
    pub(crate) profile: &'a DepthProfile,
    /// A cavity (the mould) rather than a boss.
    pub(crate) cavity: bool,
    /// Climb (material on the right of the cutter's travel).
    pub(crate) climb: bool,
    /// Cutting feed, mm/min.
    pub(crate) feed: f64,
    /// Ramp feed, mm/min.
    pub(crate) plunge_feed: f64,
    /// Ramp angle, degrees.
    pub(crate) ramp_angle: f64,
    /// Safe Z, mm: where the program starts and ends.
    pub(crate) safe_z: f64,
    /// Z of the rapids between passes (`stock.retract_z`), mm.
    pub(crate) retract_z: f64,
    /// The stock top (`stock.top`), mm: where S2's flat top lies.
    pub(crate) top: f64,
    /// Height above the surface at which an entry's ramp starts, mm: the most
    /// the roughing can have left over S2 (a stepdown and the stock to leave).
    pub(crate) entry: f64,
    /// Chord tolerance, mm.
    pub(crate) tol: f64,
    /// The stock the roughing leaves on the walls (`operation.stock_to_leave`), mm.
    pub(crate) leave: f64,
}

impl FinishParams<'_> {
    /// The cutter grown by `d` in every direction (radius and corner both
    /// r + d, rc + d: the points within d of the cutter): where it touches
    /// the mesh with its tip at z, the cutter's own tip at z + d lies d off
    /// the mesh everywhere.
    pub(crate) fn grown(&self, d: f64) -> Cutter {
        Cutter {
            radius: self.cutter.radius + d,
            corner: self.cutter.corner + d,
        }
    }

    /// z (absolute, mm) of S2 where u = `s` ([`crate::surface::surface_z`]).
    pub(crate) fn z_of(&self, s: f64) -> f64 {
        crate::surface::surface_z(self.profile, self.cavity, self.top, s)
    }
}

/// The finishing program and what it was planned from.
#[derive(Clone, Debug, PartialEq)]
pub struct Finished {
    /// The tool path (tip coordinates).
    pub toolpath: Toolpath,
    /// The pass width on the surface, mm.
    pub(crate) width: f64,
    /// The lower bound of its machining time: S2's sloped area (the walls) ÷
    /// the pass width ÷ the feed, s (no pattern of passes at most w apart
    /// covers the walls with less feed length).
    pub(crate) lower_bound_s: f64,
}

/// Area of the triangles of `tris` that are neither flat nor vertical (S2's
/// walls), mm².
pub(crate) fn wall_area(tris: &[[[f64; 3]; 3]]) -> f64 {
    tris.iter()
        .map(|c| {
            let n = crate::surface::triangle_normal(c);
            let a = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            let cos = if a > 0.0 { n[2].abs() / a } else { 1.0 };
            if cos < 1.0 - 1e-9 && cos > 1e-9 {
                0.5 * a
            } else {
                0.0
            }
        })
        .sum()
}

/// The top edge of the wall (where S2's wall meets its flat top at the stock
/// top `top`: Γ(s_top) of a boss, the rim Γ(s_bottom) of a mould) as
/// segments for the drop-cutter, each a zero-area triangle (dropped on as the
/// segment it is). The mesh's own crease runs along marching-squares chords
/// of grid cells, which cut off a letter's sharp corners by up to a tenth of
/// a millimetre; on a near-vertical wall that is a millimetre of z, and a ball
/// lowered against those chords cuts into the corner. These segments follow
/// Γ(s_top) within [`CREASE_TOL`] (chords refined onto the level by Newton),
/// so the ball stays out of the letter's top.
pub(crate) fn crease_edges(
    grid: &Grid,
    field: &Field,
    glyphs: &[Vec<Vec2>],
    profile: &DepthProfile,
    cavity: bool,
    top: f64,
    tol: f64,
) -> Vec<[[f64; 3]; 3]> {
    let (lo, hi) = profile.s_range();
    let s = if cavity { lo } else { hi };
    let h = crate::levels::plan::GRID_SPACING;
    let mut out = Vec::new();
    for poly in level::curves(grid, field, glyphs, s, h, tol) {
        let fine = level::refine(&poly, field, s, CREASE_TOL);
        for (a, b) in fine.edges() {
            let (a, b) = ([a.x, a.y, top], [b.x, b.y, top]);
            out.push([a, b, b]);
        }
    }
    out
}

/// How closely the crease segments follow Γ(s_top), mm.
pub(crate) const CREASE_TOL: f64 = 1e-4;

/// The job's finishing cutter.
pub(crate) fn cutter_of(f: &Finish) -> Cutter {
    Cutter {
        radius: f.radius(),
        corner: f.corner,
    }
}

/// The finishing passes of a boss or cavity with `[finish]`, planned before
/// the mesh is needed: the levels (equipotential or geodesic) and their
/// curves, and the pass width.
pub(crate) struct PassPlan {
    /// The passes from the floor up, and which is the foot's.
    planned: passes::Planned,
    /// The pass width on the surface, mm.
    width: f64,
}

/// The passes of a boss or cavity with `[finish]` ([`PassPlan`]): `field`
/// and `glyphs` as the roughing solved them, `grid` u over the part (as the
/// level planner samples it, spacing `h`). Needs no mesh, so a caller may
/// build the drop-cutter's index beside it.
pub(crate) fn plan_passes(
    job: &Job,
    f: &Finish,
    field: &Field,
    glyphs: &[Vec<Vec2>],
    grid: Grid,
    h: f64,
) -> Result<PassPlan, FinishError> {
    let profile = job.profile.as_ref().ok_or(FinishError::NoProfile)?;
    let cavity = job.operation.kind == crate::job::OperationKind::Cavity;
    let curves = passes::Curves {
        field,
        grid,
        glyphs,
        h,
        tol: job.operation.tolerance,
    };
    let width = passes::pass_width(f.corner, f.scallop);
    let z_of = |s: f64| crate::surface::surface_z(profile, cavity, job.stock.top, s);
    let dist = (f.pattern == crate::job::Pattern::Geodesic)
        .then(|| curves.distance(profile, (cavity, f.corner), &z_of));
    let planned = passes::pass_levels(
        &curves,
        dist.as_ref(),
        profile,
        cavity,
        width,
        job.operation.stock_to_leave,
    )?;
    Ok(PassPlan { planned, width })
}

/// The finishing program of a boss or cavity with `[finish]` from its
/// passes (`plan`, [`plan_passes`]): `mesh` S2's triangles, `wall_area`
/// their sloped area (the lower bound's).
pub(crate) fn finish(
    job: &Job,
    f: &Finish,
    field: &Field,
    plan: PassPlan,
    mesh: &MeshIndex,
    wall_area: f64,
) -> Result<Finished, FinishError> {
    let profile = job.profile.as_ref().ok_or(FinishError::NoProfile)?;
    let cavity = job.operation.kind == crate::job::OperationKind::Cavity;
    let p = FinishParams {
        cutter: cutter_of(f),
        profile,
        cavity,
        climb: job.operation.direction == crate::job::Direction::Climb,
        feed: f.feed,
        plunge_feed: f.plunge_feed,
        ramp_angle: job.tool.ramp_angle,
        safe_z: job.stock.safe_z,
        retract_z: job.stock.retract_z,
        top: job.stock.top,
        entry: job.tool.stepdown + job.operation.stock_to_leave + 0.5,
        tol: job.operation.tolerance,
        leave: job.operation.stock_to_leave,
    };
    let PassPlan { planned, width } = plan;
    let cands = with_corner(planned, width, field, &p, mesh);
    let loops = tip_loops(&cands.passes, field, &p, mesh)?;
    let floor_z = match cands.passes.get(cands.floor) {
        Some((passes::At::S(s), _)) => p.z_of(*s),
        _ => p.top,
    };
    let loops = without_floor_bound(loops, cands.passes.len(), cands.floor + 1, floor_z);
    let max_link = path::LINK_WIDTHS * width + 2.0 * f.radius();
    let order = match f.pattern {
        crate::job::Pattern::Equipotential => path::order(&loops, 2.0 * width, max_link),
        crate::job::Pattern::Geodesic => path::order_nearest(&loops, 2.0 * width, max_link),
    };
    let toolpath = path::moves(&loops, &order, &p, mesh);
    Ok(Finished {
        toolpath,
        width,
        lower_bound_s: wall_area / width / f.feed * 60.0,
    })
}

/// The tip loop of every loop of every pass (in parallel; in pass order, the
/// first failure in that order reported).
fn tip_loops(
    passes: &[passes::Pass],
    field: &Field,
    p: &FinishParams,
    mesh: &MeshIndex,
) -> Result<Vec<path::Loop>, FinishError> {
    use rayon::prelude::*;
    let jobs: Vec<(usize, passes::At, &geodesic::Curve)> = passes
        .iter()
        .enumerate()
        .flat_map(|(k, (at, curves))| curves.iter().map(move |c| (k, *at, c)))
        .collect();
    let each: Vec<Result<path::Loop, FinishError>> = jobs
        .par_iter()
        .map(|&(k, at, c)| path::tip_loop(c, k, at, field, p, mesh))
        .collect();
    each.into_iter().collect()
}

/// The passes with the corner pass ([`corner`]) between the floor's passes
/// and the foot's, for the foot loops where the cutter stops more than a
/// pass width `width` short of the foot.
fn with_corner(
    mut cands: passes::Planned,
    width: f64,
    field: &Field,
    p: &FinishParams,
    mesh: &MeshIndex,
) -> passes::Planned {
    let Some((passes::At::S(s_foot), foot)) = cands.passes.get(cands.floor) else {
        return cands;
    };
    let floor_z = p.z_of(*s_foot);
    let s_floor = cands.passes.first().map_or(passes::At::S(*s_foot), |f| f.0);
    let reach = (width, 2.0 * p.cutter.radius);
    let loops: Vec<geodesic::Curve> = {
        use rayon::prelude::*;
        foot.par_iter()
            .filter_map(|l| corner::corner_axes(&l.pts, field, p, mesh, floor_z, reach))
            .map(|c| geodesic::Curve::closed(c.axes))
            .collect()
    };
    if !loops.is_empty() {
        cands.passes.insert(cands.floor, (s_floor, loops));
        cands.floor += 1;
    }
    cands
}

/// The loops without the wall's that only sit on the floor (every tip
/// within [`corner::SETTLE`] of it: where the foot bends tighter than the
/// cutter, passes whose contact lies in the bend leave the cutter on the
/// floor, where the corner pass and the floor's passes cut), their passes
/// (`passes` of them) renumbered from the floor up. `wall` is the first
/// pass above the foot's.
fn without_floor_bound(
    loops: Vec<path::Loop>,
    passes: usize,
    wall: usize,
    floor_z: f64,
) -> Vec<path::Loop> {
    let mut kept: Vec<path::Loop> = loops
        .into_iter()
        .filter(|l| l.pass < wall || l.tip.iter().any(|t| t.z > floor_z + corner::SETTLE))
        .collect();
    let mut number = vec![usize::MAX; passes];
    let mut next = 0;
    for l in &mut kept {
        if number[l.pass] == usize::MAX {
            number[l.pass] = next;
            next += 1;
        }
        l.pass = number[l.pass];
    }
    kept
}

/// Fixtures of the finisher's unit tests.
#[cfg(test)]
pub(crate) mod testing {
    use super::FinishParams;
    use crate::levels::DepthProfile;
    use crate::toolpath::dropcutter::{Cutter, MeshIndex};

    /// A 3.175 mm ball over a boss of `profile` (feeds 1000 / 200 mm/min,
    /// ramps at 3°, safe z 5, retract 1, top 0, entry 1.7, tolerance 0.01,
    /// 0.2 mm left by the roughing).
    pub(crate) fn params(profile: &DepthProfile) -> FinishParams<'_> {
        FinishParams {
            cutter: Cutter::ball(1.5875),
            profile,
            cavity: false,
            climb: true,
            feed: 1000.0,
            plunge_feed: 200.0,
            ramp_angle: 3.0,
            safe_z: 5.0,
            retract_z: 1.0,
            top: 0.0,
            entry: 1.7,
            tol: 0.01,
            leave: 0.2,
        }
    }

    /// A step: the floor at z = −3 for x ≤ 1, the top at z = 0 for x ≥ 1
    /// (y from −5 to 5), the wall's top edge as a segment.
    pub(crate) fn step_mesh() -> MeshIndex {
        let tri = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| [a, b, c];
        let tris = vec![
            tri([-10.0, -5.0, -3.0], [1.0, -5.0, -3.0], [1.0, 5.0, -3.0]),
            tri([-10.0, -5.0, -3.0], [1.0, 5.0, -3.0], [-10.0, 5.0, -3.0]),
            tri([1.0, -5.0, 0.0], [5.0, -5.0, 0.0], [5.0, 5.0, 0.0]),
            tri([1.0, -5.0, 0.0], [5.0, 5.0, 0.0], [1.0, 5.0, 0.0]),
            tri([1.0, -5.0, 0.0], [1.0, 5.0, 0.0], [1.0, 5.0, 0.0]),
        ];
        MeshIndex::new(tris, 0.8)
    }

    /// φ(s) of the step's tests: linear from −3 mm at s = 0.9.
    pub(crate) fn step_profile() -> DepthProfile {
        DepthProfile::Linear {
            s_bottom: 0.9,
            depth: 3.0,
        }
    }
}
