//! Evaluation counts per pipeline stage (issue 13), compiled in only with the
//! cargo feature `count-evals`; in a normal build every function here is an
//! empty inline function and the counters do not exist.
//!
//! The stage is one process-wide value, not per thread: counts are meant to be
//! taken on one thread (`RAYON_NUM_THREADS=1`, as `examples/count_evals.rs`
//! does), where the stages follow each other. With more threads the totals are
//! right but their split between stages is not.

/// A stage of the pipeline that evaluates fields.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Everything not below (previews, surfaces, composition).
    Other = 0,
    /// The shape's MFS solves: matrices, boundary checks.
    ShapeSolve,
    /// The level planner's grid, its contours Γ(s), their refinement and the z schedule.
    LevelGrid,
    /// The levels' own MFS solves (a cavity level's, and its inverse problem's).
    LevelSolve,
    /// The inverse problem's grid and the clearing rings extracted from it.
    InverseGrid,
    /// The rolling-disk tracing of rings, walls and bays.
    Rings,
    /// The cavities' coverage measure.
    Coverage,
    /// The finishing program: the passes and their contact points (S2's
    /// mesh and the drops below are counted on their own).
    Finishing,
    /// The finishing's mesh of S2 and its drop-cutter index.
    FinishMesh,
    /// The finishing's tip drops: one per contact point of every pass.
    FinishTips,
    /// The finishing's chord checks: the drops that keep a straight move
    /// between two tips above the drop-cutter's height.
    FinishChords,
    /// The finishing's links, entries and thinning (Douglas–Peucker with a
    /// drop at every point a longer chord passes).
    FinishMoves,
}

/// Every stage, in the order of [`Stage`]'s discriminants.
#[cfg(feature = "count-evals")]
pub(crate) const STAGES: [Stage; 12] = [
    Stage::Other,
    Stage::ShapeSolve,
    Stage::LevelGrid,
    Stage::LevelSolve,
    Stage::InverseGrid,
    Stage::Rings,
    Stage::Coverage,
    Stage::Finishing,
    Stage::FinishMesh,
    Stage::FinishTips,
    Stage::FinishChords,
    Stage::FinishMoves,
];

impl Stage {
    /// A short name for tables.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Other => "other",
            Stage::ShapeSolve => "shape solve",
            Stage::LevelGrid => "level grid and schedule",
            Stage::LevelSolve => "level solves",
            Stage::InverseGrid => "inverse grid and rings",
            Stage::Rings => "rings (tracing)",
            Stage::Coverage => "coverage",
            Stage::Finishing => "finishing",
            Stage::FinishMesh => "finishing: mesh, index",
            Stage::FinishTips => "finishing: tip drops",
            Stage::FinishChords => "finishing: chord checks",
            Stage::FinishMoves => "finishing: links, thinning",
        }
    }
}

/// What was counted in one stage.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Counts {
    /// Wall-clock seconds spent in the stage (meaningful on one thread).
    pub seconds: f64,
    /// Field evaluations (u, ∇u, both, or the Hessian at one point).
    pub evals: u64,
    /// Kernel pairs summed directly (a charge and a point; a matrix entry).
    pub pairs: u64,
    /// Terms of local expansions evaluated (Horner steps).
    pub terms: u64,
    /// Nearest-edge distance queries (`DistanceIndex`).
    pub queries: u64,
    /// Drop-cutter drops (`toolpath::dropcutter`).
    pub drops: u64,
}

#[cfg(feature = "count-evals")]
mod imp {
    use super::{Counts, Stage, STAGES};
    use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering::Relaxed};
    use std::sync::Mutex;
    use std::time::Instant;

    static STAGE: AtomicUsize = AtomicUsize::new(0);
    static SINCE: Mutex<Option<Instant>> = Mutex::new(None);
    static NANOS: [AtomicU64; STAGES.len()] = [ZERO; STAGES.len()];
    #[allow(clippy::declare_interior_mutable_const)]
    const ZERO: AtomicU64 = AtomicU64::new(0);
    #[allow(clippy::declare_interior_mutable_const)]
    const ROW: [AtomicU64; 5] = [ZERO; 5];
    static COUNTS: [[AtomicU64; 5]; STAGES.len()] = [ROW; STAGES.len()];

    /// Charge the time since the last switch to the current stage.
    fn clock() {
        let now = Instant::now();
        let mut since = SINCE.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(t) = *since {
            NANOS[STAGE.load(Relaxed)].fetch_add((now - t).as_nanos() as u64, Relaxed);
        }
        *since = Some(now);
    }
    pub(crate) fn set_stage(s: Stage) -> Stage {
        clock();
        STAGES[STAGE.swap(s as usize, Relaxed)]
    }
    pub(crate) fn add(k: usize, n: u64) {
        COUNTS[STAGE.load(Relaxed)][k].fetch_add(n, Relaxed);
    }
    pub(crate) fn take() -> Vec<(Stage, Counts)> {
        clock();
        STAGES
            .iter()
            .map(|&s| {
                let c = &COUNTS[s as usize];
                (
                    s,
                    Counts {
                        seconds: NANOS[s as usize].swap(0, Relaxed) as f64 * 1e-9,
                        evals: c[0].swap(0, Relaxed),
                        pairs: c[1].swap(0, Relaxed),
                        terms: c[2].swap(0, Relaxed),
                        queries: c[3].swap(0, Relaxed),
                        drops: c[4].swap(0, Relaxed),
                    },
                )
            })
            .collect()
    }
}

/// Whether this build counts (the `count-evals` feature).
pub(crate) const ENABLED: bool = cfg!(feature = "count-evals");

/// Makes `s` the current stage until the guard is dropped, when the stage
/// it replaced is current again (for a stage inside another).
#[inline(always)]
pub(crate) fn enter(s: Stage) -> StageGuard {
    StageGuard(set_stage(s))
}

/// Restores a stage when dropped ([`enter`]).
#[must_use = "the stage ends when the guard is dropped"]
pub(crate) struct StageGuard(Stage);

impl Drop for StageGuard {
    #[inline(always)]
    fn drop(&mut self) {
        if ENABLED {
            set_stage(self.0);
        }
    }
}

/// Make `s` the current stage; returns the one it replaces.
#[inline(always)]
pub fn set_stage(s: Stage) -> Stage {
    #[cfg(feature = "count-evals")]
    {
        imp::set_stage(s)
    }
    #[cfg(not(feature = "count-evals"))]
    {
        let _ = s;
        Stage::Other
    }
}

#[inline(always)]
fn add(_k: usize, _n: u64) {
    #[cfg(feature = "count-evals")]
    imp::add(_k, _n);
}

/// One field evaluation that summed `pairs` kernel pairs directly and
/// `terms` expansion terms.
#[inline(always)]
pub(crate) fn eval(pairs: usize, terms: usize) {
    add(0, 1);
    add(1, pairs as u64);
    add(2, terms as u64);
}

/// `pairs` kernel pairs outside any field evaluation (a solve's matrix).
#[inline(always)]
pub(crate) fn pairs(pairs: usize) {
    add(1, pairs as u64);
}

/// One nearest-edge distance query.
#[inline(always)]
pub(crate) fn query() {
    add(3, 1);
}

/// One drop of the drop-cutter.
#[inline(always)]
pub(crate) fn drop() {
    add(4, 1);
}

/// The counts per stage since the last call, and zero them (empty without the
/// feature).
pub fn take() -> Vec<(Stage, Counts)> {
    #[cfg(feature = "count-evals")]
    {
        imp::take()
    }
    #[cfg(not(feature = "count-evals"))]
    {
        Vec::new()
    }
}

#[cfg(all(test, feature = "count-evals"))]
mod tests {
    use super::*;
    use crate::field::Field;
    use crate::geometry::Vec2;

    /// A direct field of three charges evaluated five times counts five
    /// evaluations and fifteen kernel pairs in the current stage (at least:
    /// other tests may count in the same stage at the same time).
    #[test]
    fn direct_evaluations_are_counted_with_their_pairs() {
        let f = Field::new(
            vec![
                Vec2::new(0.0, 0.0),
                Vec2::new(5.0, 0.0),
                Vec2::new(0.0, 5.0),
            ],
            vec![1.0, -0.5, 0.25],
        );
        set_stage(Stage::Finishing);
        for k in 0..5 {
            f.value(Vec2::new(1.0 + k as f64, 2.0));
        }
        let c = take()
            .into_iter()
            .find(|(s, _)| *s == Stage::Finishing)
            .map(|(_, c)| c)
            .unwrap_or_default();
        assert!(c.evals >= 5 && c.pairs >= 15, "{c:?}");
    }
}
