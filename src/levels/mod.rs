//! The z-levels of a boss or cavity: the z schedule, the order the levels are
//! cut in, and (in the submodules) the planner, the sections interface and its
//! sources. The depth profile φ(s) they follow is [`DepthProfile`] (from the
//! crate's `profile` module, re-exported here).

pub mod accuracy;
pub(crate) mod height_field;
pub(crate) mod mfs_sections;
pub(crate) mod plan;
pub(crate) mod prism;
pub(crate) mod section_view;
pub mod sections;

pub(crate) use crate::profile::DepthProfile;

/// The z-levels (relative to the stock top) from the top down: 0 first, then
/// equal steps of at most `stepdown`, the last exactly at −depth; then, wherever
/// `gap(z_a, z_b)` (the horizontal distance between the contours of neighbouring
/// levels, mm) exceeds `max_scallop`, a level is added half way in z, until every
/// gap is within bound or the levels are `min_dz` apart. `None` when that
/// takes more than `max_levels` levels: each costs a gap measurement here and a
/// solve and a trace later, and `min_dz` alone allows depth / min_dz of them
/// (10 000 for 200 mm at 0.02 mm).
pub(crate) fn schedule(
    depth: f64,
    stepdown: f64,
    max_scallop: f64,
    min_dz: f64,
    max_levels: usize,
    gap: &dyn Fn(f64, f64) -> f64,
) -> Option<Vec<f64>> {
    let n = ((depth / stepdown) - 1e-9).ceil().max(1.0) as usize;
    if n >= max_levels {
        return None;
    }
    let mut zs: Vec<f64> = (0..=n).map(|k| -depth * k as f64 / n as f64).collect();
    let mut i = 0;
    while i + 1 < zs.len() {
        let (a, b) = (zs[i], zs[i + 1]);
        if a - b > 2.0 * min_dz && gap(a, b) > max_scallop {
            if zs.len() >= max_levels {
                return None;
            }
            zs.insert(i + 1, 0.5 * (a + b));
        } else {
            i += 1;
        }
    }
    Some(zs)
}

/// The order in which the levels are cut, as indices into `rough` (one flag per
/// level, top down: true for a level of the plain stepdown schedule). Slab by
/// slab from the top, a slab being the levels down to and including a stepdown
/// level: first that stepdown level, which clears everything outside the part
/// at its depth (inside it for a cavity) one stepdown below the last, every ring
/// engaging at most a stepover; then the slab's levels added for the scallop
/// bound, from the bottom up. The level below has by then cut out to its own
/// contour, so each only cuts the band between its contour and that one (at
/// most `max_scallop` wide), however far the stepdown level's contour lies. Cut
/// top down instead, every added level had to clear out to the stepdown level
/// below it: mfs-sign's 55 levels cut 232 m where this order cuts 55 m
/// (`pfcam run jobs/mfs-sign.toml`, the header's cut length). The slab above is
/// finished before the next stepdown level: where a stepdown level's disk
/// could not reach (a narrow gap's mouth), the levels above it have cut what
/// they could first, which keeps the next one's cut near a stepdown deep.
pub(crate) fn cutting_order(rough: &[bool]) -> Vec<usize> {
    let mut order = Vec::with_capacity(rough.len());
    let mut slab = Vec::new();
    for (i, &r) in rough.iter().enumerate() {
        if r {
            order.push(i);
            order.extend(slab.drain(..).rev());
        } else {
            slab.push(i);
        }
    }
    order.extend(slab.drain(..).rev());
    order
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_slab_its_stepdown_level_first_then_bottom_up() {
        // Levels top down: 0.5 1 (rough) 1.25 1.5 1.75 2 (rough) 3 (rough).
        let rough = [false, true, false, false, false, true, true];
        assert_eq!(cutting_order(&rough), vec![1, 0, 5, 4, 3, 2, 6]);
        assert_eq!(cutting_order(&[true, true]), vec![0, 1]);
        assert_eq!(cutting_order(&[false, false]), vec![1, 0]);
        assert!(cutting_order(&[]).is_empty());
        // Every level once.
        let mut o = cutting_order(&rough);
        o.sort_unstable();
        assert_eq!(o, (0..rough.len()).collect::<Vec<_>>());
    }

    #[test]
    fn schedule_steps_and_refines() {
        // No gap problem: 6 mm at 1 mm a step gives 7 levels, the last at −6.
        let zs = schedule(6.0, 1.0, 0.5, 0.01, 100, &|_, _| 0.0).expect("levels");
        assert_eq!(zs.len(), 7);
        assert_eq!(zs[6], -6.0);
        // 2.5 mm at most 1 mm: three equal steps.
        let zs = schedule(2.5, 1.0, 0.5, 0.01, 100, &|_, _| 0.0).expect("levels");
        assert_eq!(zs, vec![0.0, -2.5 / 3.0, -5.0 / 3.0, -2.5]);
        // A gap proportional to the step (a 45° wall): 1 mm steps have 1 mm gaps,
        // so every step is halved until the gap is at most 0.3 mm: 0.25 mm steps.
        let zs = schedule(2.0, 1.0, 0.3, 0.01, 100, &|a, b| a - b).expect("levels");
        assert_eq!(zs.len(), 9);
        // The same needs 9 levels: refused with 8 at most, given with 9.
        assert_eq!(schedule(2.0, 1.0, 0.3, 0.01, 8, &|a, b| a - b), None);
        assert_eq!(
            schedule(2.0, 1.0, 0.3, 0.01, 9, &|a, b| a - b),
            Some(zs.clone())
        );
        // A wall no level count satisfies stops at the cap, not at depth / min_dz.
        let calls = std::cell::Cell::new(0);
        let steep = |a: f64, b: f64| {
            calls.set(calls.get() + 1);
            1e3 * (a - b)
        };
        assert_eq!(schedule(200.0, 50.0, 0.01, 0.02, 400, &steep), None);
        assert!(calls.get() < 400, "{} gap measurements", calls.get());
        // Too many passes of the stepdown alone.
        assert_eq!(schedule(10.0, 0.01, 0.5, 0.001, 400, &|_, _| 0.0), None);
        for w in zs.windows(2) {
            assert!((w[0] - w[1] - 0.25).abs() < 1e-12);
        }
    }
}
