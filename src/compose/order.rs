//! The parts of a composition in waves: a part's wave is one more than the
//! latest wave of the parts it names (0 for a primitive), so the parts of a
//! wave depend only on earlier waves and are built in parallel. The paper's Q
//! (m1 … m6, Q) runs as {m1, m4}, {m2, m3, m5}, {m6}, {Q}.
//!
//! What each part sees is what it would see built in order: for every name
//! it refers to, the latest part of that name before it. A part whose
//! operand failed is not built. The error returned is the first failing
//! part's in order: every part before it was built (a part is skipped only
//! when an earlier one failed), so it saw the same models as in order.

use super::{build_part, model_of, Frame, Models, PartReport};
use crate::compose::{ComposeError, Model};
use crate::geometry::{Composition, Contour, PartSource};
use rayon::prelude::*;
use std::collections::HashMap;

/// What became of a part.
enum Slot {
    Pending,
    Built(Box<Model>, Vec<PartReport>),
    Failed(ComposeError),
    /// An operand failed.
    Skipped,
}

/// Every part of a composition, built.
pub(super) struct BuiltParts<'c> {
    comp: &'c Composition,
    slots: Vec<Slot>,
}

impl BuiltParts<'_> {
    /// The model named `name` (the last part of that name) and every part's
    /// reports, in order.
    pub(super) fn result(self, name: &str) -> Result<(Model, Vec<PartReport>), ComposeError> {
        let mut models: Models = HashMap::new();
        let mut reports = Vec::new();
        for (part, slot) in self.comp.parts.iter().zip(&self.slots) {
            if let Slot::Built(m, r) = slot {
                models.insert(part.name.as_str(), m);
                reports.extend(r.iter().cloned());
            }
        }
        Ok((model_of(&models, name, name)?, reports))
    }
}

/// For each part, the earlier parts it names (the latest of each name).
fn operands(comp: &Composition) -> Vec<Vec<usize>> {
    let parts = &comp.parts;
    (0..parts.len())
        .map(|k| {
            let names: &[String] = match &parts[k].source {
                PartSource::Ref(of) => std::slice::from_ref(of),
                PartSource::Op { of, .. } => of,
                _ => &[],
            };
            let mut deps: Vec<usize> = names
                .iter()
                .filter_map(|n| (0..k).rev().find(|&j| parts[j].name == *n))
                .collect();
            deps.sort_unstable();
            deps.dedup();
            deps
        })
        .collect()
}

/// Each part's wave.
fn waves(deps: &[Vec<usize>]) -> Vec<usize> {
    let mut wave = vec![0; deps.len()];
    for k in 0..deps.len() {
        wave[k] = deps[k].iter().map(|&j| wave[j] + 1).max().unwrap_or(0);
    }
    wave
}

/// Build every part, wave by wave; `on_part(done, total)` after each part.
pub(super) fn build_parts<'c>(
    comp: &'c Composition,
    mut prims: HashMap<&str, Vec<Contour>>,
    frame: &Frame,
    on_part: &mut dyn FnMut(usize, usize),
) -> Result<BuiltParts<'c>, ComposeError> {
    let parts = &comp.parts;
    let n = parts.len();
    let mut prim_of: Vec<Option<Vec<Contour>>> = parts
        .iter()
        .map(|p| prims.remove(p.name.as_str()))
        .collect();
    let deps = operands(comp);
    let wave = waves(&deps);
    let mut slots: Vec<Slot> = (0..n).map(|_| Slot::Pending).collect();
    let mut done = 0;
    for w in 0..=wave.iter().copied().max().unwrap_or(0) {
        let jobs: Vec<(usize, Option<Vec<Contour>>)> = (0..n)
            .filter(|&k| wave[k] == w)
            .map(|k| (k, prim_of[k].take()))
            .collect();
        let results: Vec<(usize, Slot)> = jobs
            .into_par_iter()
            .map(|(k, prim)| (k, build_one(comp, k, prim, &deps[k], &slots, frame)))
            .collect();
        for (k, slot) in results {
            slots[k] = slot;
            done += 1;
            on_part(done, n);
        }
        if let Some(e) = first_error(&mut slots) {
            return Err(e);
        }
    }
    Ok(BuiltParts { comp, slots })
}

/// Part k built from its operands' slots, or skipped when one of them failed.
fn build_one(
    comp: &Composition,
    k: usize,
    prim: Option<Vec<Contour>>,
    deps: &[usize],
    slots: &[Slot],
    frame: &Frame,
) -> Slot {
    let mut models: Models = HashMap::new();
    for &j in deps {
        match &slots[j] {
            Slot::Built(m, _) => {
                models.insert(comp.parts[j].name.as_str(), m);
            }
            _ => return Slot::Skipped,
        }
    }
    match build_part(&comp.parts[k], prim, &models, frame) {
        Ok((m, r)) => Slot::Built(Box::new(m), r),
        Err(e) => Slot::Failed(e),
    }
}

/// The error of the first failed part when every part before it is built
/// (then no later wave can change which error is first).
fn first_error(slots: &mut [Slot]) -> Option<ComposeError> {
    for slot in slots.iter_mut() {
        match slot {
            Slot::Built(..) => continue,
            Slot::Failed(_) => {
                let Slot::Failed(e) = std::mem::replace(slot, Slot::Skipped) else {
                    unreachable!("matched Failed above")
                };
                return Some(e);
            }
            _ => return None,
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{BoolOp, Part, Vec2};

    fn part(name: &str, source: PartSource) -> Part {
        Part {
            name: name.into(),
            source,
            level: None,
            singularities: None,
        }
    }

    /// The paper's Q: m1 and m4 first, then the three equipotentials, then
    /// the union, then the subtraction.
    #[test]
    fn the_paper_q_runs_in_four_waves() {
        let poly = || PartSource::Polygon(vec![Vec2::new(0.0, 0.0); 3]);
        let r = |s: &str| PartSource::Ref(s.into());
        let op = |op, of: &[&str]| PartSource::Op {
            op,
            of: of.iter().map(|s| s.to_string()).collect(),
        };
        let comp = Composition {
            parts: vec![
                part("m1", poly()),
                part("m2", r("m1")),
                part("m3", r("m1")),
                part("m4", poly()),
                part("m5", r("m4")),
                part("m6", op(BoolOp::Union, &["m2", "m5"])),
                part("Q", op(BoolOp::Subtract, &["m6", "m3"])),
            ],
            result: "x".into(),
            height: None,
            origin: Vec2::new(0.0, 0.0),
        };
        let deps = operands(&comp);
        assert_eq!(deps[5], vec![1, 4]);
        assert_eq!(deps[6], vec![2, 5]);
        assert_eq!(waves(&deps), vec![0, 1, 1, 0, 1, 2, 3]);
    }

    /// A name defined twice refers to the latest definition before the part.
    #[test]
    fn a_reference_is_to_the_latest_earlier_part_of_that_name() {
        let poly = || PartSource::Polygon(vec![Vec2::new(0.0, 0.0); 3]);
        let comp = Composition {
            parts: vec![
                part("a", poly()),
                part("b", PartSource::Ref("a".into())),
                part("a", PartSource::Ref("b".into())),
                part("c", PartSource::Ref("a".into())),
                part("d", PartSource::Ref("later".into())),
                part("later", poly()),
            ],
            result: "x".into(),
            height: None,
            origin: Vec2::new(0.0, 0.0),
        };
        let deps = operands(&comp);
        assert_eq!(
            deps,
            vec![vec![], vec![0], vec![1], vec![2], vec![], vec![]]
        );
        assert_eq!(waves(&deps), vec![0, 1, 2, 3, 0, 0]);
    }
}
