//! Solids from scattered points by polyharmonic boundary integrals (Ochiai,
//! seed paper 001, issue 19): a field T₁, fixed to +1 on a large fictitious
//! box, with ∇²T₁ = −T₂ and ∇²T₂ = −(loads at the given points, each spread
//! over a ball of radius A); the solid is {T₁ < 0}. docs/method.md §17 has the
//! equations as implemented, the corrections to the printed ones and the
//! measured figures.

pub mod closed;
pub mod elements;
pub mod envelope;
mod error;
pub mod fast;
mod fault;
mod field;
mod gauss;
pub mod iso;
pub mod kernels;
pub mod lagrange;
pub mod quadrature;
pub mod relief;
pub mod spec;
pub mod sphere;
pub mod system;

pub use elements::{BoxMesh, Element};
pub use envelope::Envelope;
pub use error::PolyError;
pub use fast::FastField;
pub use fault::PolyFault;
pub use gauss::GaussRule;
pub use kernels::{Kernel, Radial};
pub use quadrature::{QuadRule, Quadrature};
pub use relief::{Relief, ReliefSpec};
pub use spec::{PolyInputs, PolySpec, Solid};
pub use system::{solve, solve_dirichlet, GivenPoint, Model, PointKind, Solution};
