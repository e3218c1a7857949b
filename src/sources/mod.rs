//! Shape sources other than the MFS field of glyphs: surfaces from the seed
//! papers (issue 18). Each is standalone maths here; the sections interface
//! that makes one a job's shape lives elsewhere.

pub mod harmonic_bezier;
pub mod pde;
pub mod pde6;
pub mod pde_trim;
pub mod pde_tube;
pub mod polyharmonic;
