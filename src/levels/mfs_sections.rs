//! The MFS field of a shape as a [`Sections`] source: the paper's
//! S2 = {(x, y) ∈ Γ(s), z = φ(s)} (Section 7). The section at z is the
//! equipotential Γ(s(z)), s(z) the inverse of the depth profile φ (mirrored
//! for a cavity, whose rim is the widest curve), extracted from one grid of u
//! over the whole job (`field::level::curves`) and cached per s.

use super::plan::{level_error_bound, PlanError, EMPTY_BOX, GRID_SPACING};
use super::sections::{LevelField, Sections};
use super::DepthProfile;
use crate::field::isolines::Grid;
use crate::field::level;
use crate::field::{Field, FieldFigures};
use crate::geometry::{polygons_bbox, Ring, Vec2};
use std::collections::HashMap;
use std::sync::Mutex;

/// A shape's field, its glyphs and φ(s), with the grid of u its curves come from.
pub(crate) struct MfsSections {
    field: Field,
    glyphs: Vec<Vec<Vec2>>,
    profile: DepthProfile,
    cavity: bool,
    tol: f64,
    figures: FieldFigures,
    grid: Grid,
    h: f64,
    cache: Mutex<HashMap<u64, Vec<Ring>>>,
}

/// What [`MfsSections::new`] needs.
pub(crate) struct MfsInput {
    /// The shape's field (generating boundary: the glyphs).
    pub(crate) field: Field,
    /// The glyphs, flattened, material on the left, mm.
    pub(crate) glyphs: Vec<Vec<Vec2>>,
    /// φ(s).
    pub(crate) profile: DepthProfile,
    /// True for a cavity (the mould: material outside Γ(s)).
    pub(crate) cavity: bool,
    /// The job's tolerance, mm: the curves' chords are refined to
    /// `field::level::CHORD_FRACTION` of it.
    pub(crate) tol: f64,
    /// The shape field's figures, reported for the boss levels that use it.
    pub(crate) figures: FieldFigures,
}

impl MfsSections {
    /// Sample u on one grid (spacing [`GRID_SPACING`], or finer for a shape
    /// over 800 mm across), grown until Γ(s_bottom) closes inside it; an
    /// error if it does not within five growths.
    pub(crate) fn new(input: MfsInput) -> Result<MfsSections, PlanError> {
        let (grid, h) = job_grid(&input.field, &input.glyphs, &input.profile)?;
        Ok(MfsSections {
            field: input.field,
            glyphs: input.glyphs,
            profile: input.profile,
            cavity: input.cavity,
            tol: input.tol,
            figures: input.figures,
            grid,
            h,
            cache: Mutex::new(HashMap::new()),
        })
    }

    /// The shape's field.
    pub(crate) fn field(&self) -> &Field {
        &self.field
    }

    /// φ'(s), mm per unit s (the depth profile's slope).
    pub(crate) fn slope(&self, s: f64) -> f64 {
        self.profile.slope(s)
    }

    /// The glyphs, flattened.
    pub(crate) fn glyphs(&self) -> &[Vec<Vec2>] {
        &self.glyphs
    }

    /// s at the level of `zrel` (relative to the stock top): from the profile,
    /// mirrored for a cavity.
    pub(crate) fn s_of(&self, zrel: f64) -> f64 {
        let p = &self.profile;
        if self.cavity {
            p.s_at(-p.depth() - zrel)
        } else {
            p.s_at(zrel)
        }
    }

    /// Γ(s) (`field::level::curves`), each s extracted once (the schedule, the
    /// stock, the bound and the levels ask for the same curves); loops
    /// around the material counter-clockwise.
    pub(crate) fn curves(&self, s: f64) -> Vec<Ring> {
        if let Some(c) = self
            .cache
            .lock()
            .ok()
            .and_then(|m| m.get(&s.to_bits()).cloned())
        {
            return c;
        }
        let polys = level::curves(&self.grid, &self.field, &self.glyphs, s, self.h, self.tol);
        if let Ok(mut m) = self.cache.lock() {
            m.insert(s.to_bits(), polys.clone());
        }
        polys
    }
}

impl Sections for MfsSections {
    fn z_range(&self) -> (f64, f64) {
        (-self.profile.depth(), 0.0)
    }

    /// Γ(s(z)); for a cavity reversed, the material being outside it.
    fn section(&self, z: f64) -> Vec<Vec<Vec2>> {
        let rings = self.curves(self.s_of(z)).into_iter();
        if self.cavity {
            rings.map(|r| r.reversed().into_points()).collect()
        } else {
            rings.map(Ring::into_points).collect()
        }
    }

    fn level_value(&self, z: f64) -> f64 {
        self.s_of(z)
    }

    /// A boss level: u/s, with u the shape's field. Outside Γ(s) it is
    /// harmonic, 1 on Γ(s) and 0 on the outer circle and the sinks, so by
    /// uniqueness it is the solution of the level's own problem (the paper
    /// solves that problem again by MFS; its answer is known exactly), with the
    /// boundary error of the shape's field divided by s
    /// (../shared/design/FIELD-NOTES.md). A fresh MFS solve on Γ(s) near s = 1,
    /// where Γ(s) has near-corners of tiny radius, erred by far more. Its
    /// warning: an error above [`level_error_bound`]. A cavity: `None`, the
    /// mould is outside Γ(s) and its problem is not the shape's.
    fn level_field(&self, z: f64) -> Option<LevelField> {
        if self.cavity {
            return None;
        }
        let s = self.s_of(z);
        let figures = FieldFigures {
            max_error: self.figures.max_error / s,
            ..self.figures
        };
        let (e, bound) = (figures.max_error, level_error_bound(s));
        let warning = (e > bound || e.is_nan()).then(|| format!(
            "s = {s:.6}: its field (the shape's u/s) errs by {e:.2e}, above {bound:.1e} (a hundredth of 1 − s): lower profile.s1 (the top edge)"
        ));
        Some(LevelField {
            field: self.field.scaled(1.0 / s),
            figures,
            warning,
        })
    }
}

/// One grid of u for the whole job (spacing [`GRID_SPACING`], or finer for a
/// shape over 800 mm across), grown until Γ(s_bottom) closes inside it.
pub(crate) fn job_grid(
    field: &Field,
    glyphs: &[Vec<Vec2>],
    profile: &DepthProfile,
) -> Result<(Grid, f64), PlanError> {
    let (s_lo, _) = profile.s_range();
    let (lo, hi) = polygons_bbox(glyphs).unwrap_or(EMPTY_BOX);
    let diag = (hi - lo).norm();
    // The padding, 0.1 of the diagonal, grows by 1.8 for each try.
    let pad = |k: usize| (0..k).fold(0.1 * diag, |p, _| p * 1.8);
    let h = GRID_SPACING.max(diag / 2000.0);
    let sample = |k: usize| {
        let d = Vec2::new(pad(k), pad(k));
        Grid::sample(field, lo - d, hi + d, h, glyphs)
    };
    let grid = level::closing_grid(s_lo, 6, sample).ok_or(PlanError::LevelOpen {
        s: s_lo,
        pad: pad(5),
    })?;
    Ok((grid, h))
}
