//! The levels of a boss or cavity, planned by `levels::plan` (the schedule,
//! each level's section and field) and cut by `toolpath::zlevel` (each
//! level's paths in its field), level by level in parallel, with a count of
//! the levels done for the CLI's progress bar.

use super::{Internal, PipelineError, Progress};
use crate::estimate::LowerBound;
use crate::levels::plan::{cavity_error_warning, plan_level, plan_schedule};
use crate::levels::plan::{Level, LevelInfo, LevelJob};
use crate::toolpath::zlevel::{level_paths, LevelCut, LevelParams};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Every level planned and cut.
pub(crate) struct Planned {
    /// The levels with their paths, top down.
    pub cuts: Vec<LevelCut>,
    /// What each level's solve reported, top down.
    pub info: Vec<LevelInfo>,
    /// The order in which the levels are cut, as indices into `cuts`
    /// ([`crate::levels::cutting_order`]).
    pub order: Vec<usize>,
    /// Warnings.
    pub warnings: Vec<String>,
    /// Path settings with the stock rectangle.
    pub params: LevelParams,
    /// Seconds spent extracting contours and choosing the z schedule (wall
    /// clock).
    pub t_schedule: f64,
    /// The lower bound of the machining time, from the levels' contours.
    pub bound: LowerBound,
}

/// How far the levels have got, for a progress display on another thread:
/// the number of levels once the schedule is known, and how many are done.
#[derive(Debug, Default)]
struct LevelProgress {
    /// Levels to cut (0 until the z schedule is chosen).
    total: AtomicUsize,
    /// Levels planned and cut so far.
    done: AtomicUsize,
}

/// Plan and cut the levels ([`plan_and_cut`], in parallel, on the current
/// rayon pool) while this thread reports each finished level: a stage of as
/// many steps as there are levels, announced once the z schedule is known.
pub(crate) fn plan_with_progress(
    lj: &LevelJob,
    params: LevelParams,
    progress: &mut dyn FnMut(Progress),
) -> Result<Planned, PipelineError> {
    let counter = LevelProgress::default();
    let result = std::sync::Mutex::new(None);
    let (mut announced, mut reported) = (false, 0);
    rayon::in_place_scope(|scope| {
        scope.spawn(|_| {
            // A panic must still end the wait below (and is then an error).
            let r = match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                plan_and_cut(lj, params, &counter)
            })) {
                Ok(planned) => planned,
                Err(_) => Err(Internal::PlannerPanicked.into()),
            };
            *result.lock().unwrap_or_else(|e| e.into_inner()) = Some(r);
        });
        loop {
            let finished = result.lock().unwrap_or_else(|e| e.into_inner()).is_some();
            let total = counter.total.load(Ordering::Relaxed);
            if total > 0 && !announced {
                progress(Progress::Stage {
                    name: "solving and tracing the levels".into(),
                    total: total as u64,
                });
                announced = true;
            }
            let done = counter.done.load(Ordering::Relaxed);
            while announced && reported < done {
                progress(Progress::Step);
                reported += 1;
            }
            if finished {
                break;
            }
            // On a pool's own thread (a one-thread pool in tests) do the work
            // here; otherwise wait for the pool.
            if !matches!(rayon::yield_now(), Some(rayon::Yield::Executed)) {
                std::thread::sleep(std::time::Duration::from_millis(50));
            }
        }
    });
    result
        .into_inner()
        .unwrap_or_else(|e| e.into_inner())
        .ok_or(Internal::PlannerUnfinished)?
}

/// The schedule of `lj` ([`plan_schedule`]), then every level below the top
/// planned and cut ([`cut_level`]) in parallel, collected top down (so the
/// result does not depend on the number of threads), counting the levels in
/// `progress` as they finish; `params` gets the schedule's stock rectangle.
fn plan_and_cut(
    lj: &LevelJob,
    params: LevelParams,
    progress: &LevelProgress,
) -> Result<Planned, PipelineError> {
    let schedule = plan_schedule(lj)?;
    let (stock_lo, stock_hi) = schedule.stock;
    let params = LevelParams {
        stock_lo,
        stock_hi,
        ..params
    };
    progress
        .total
        .store(schedule.levels.len(), Ordering::Relaxed);
    let results: Vec<Result<CutLevel, PipelineError>> = schedule
        .levels
        .par_iter()
        .map(|level| {
            let r = cut_level(lj, &params, level);
            progress
                .done
                .fetch_add(usize::from(r.is_ok()), Ordering::Relaxed);
            r
        })
        .collect();
    let (mut cuts, mut info, mut warnings) = (Vec::new(), Vec::new(), Vec::new());
    for r in results {
        let (c, i, w) = r?;
        cuts.push(c);
        info.push(i);
        warnings.extend(w);
    }
    if lj.cavity {
        warnings.extend(cavity_error_warning(&info));
    }
    Ok(Planned {
        cuts,
        info,
        order: schedule.order,
        warnings,
        params,
        t_schedule: schedule.t_schedule,
        bound: schedule.bound,
    })
}

/// One level's cut, report and warnings.
type CutLevel = (LevelCut, LevelInfo, Vec<String>);

/// Level `level`: planned ([`plan_level`]: its section and field), then its
/// paths traced in that field ([`level_paths`]).
fn cut_level(
    lj: &LevelJob,
    params: &LevelParams,
    level: &Level,
) -> Result<CutLevel, PipelineError> {
    let mut planned = plan_level(lj, level)?;
    crate::count::set_stage(crate::count::Stage::Rings);
    let t0 = std::time::Instant::now();
    let mut warnings = std::mem::take(&mut planned.warnings);
    let (paths, uncut) = level_paths(
        lj.cavity,
        &planned.section,
        &planned.field.field,
        params,
        &planned.label,
        &mut warnings,
        planned.reach,
    )
    .map_err(PipelineError::LevelPaths)?;
    let info = planned.info(uncut, t0.elapsed().as_secs_f64());
    let cut = LevelCut {
        z: planned.z,
        s: planned.s,
        part: planned.part,
        paths,
    };
    Ok((cut, info, warnings))
}
