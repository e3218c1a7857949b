//! Solids from scattered points by polyharmonic boundary integrals (Ochiai,
//! seed paper 001, issue 19): a field T₁, fixed to +1 on a large fictitious
//! box, with ∇²T₁ = −T₂ and ∇²T₂ = −(loads at the given points, each spread
//! over a ball of radius A); the solid is {T₁ < 0}. docs/method.md §17 has the
//! equations as implemented, the corrections to the printed ones and the
//! measured figures.

pub mod closed;
pub(crate) mod elements;
pub(crate) mod envelope;
mod error;
pub(crate) mod fast;
mod fault;
mod field;
mod gauss;
pub mod iso;
pub(crate) mod kernels;
pub(crate) mod lagrange;
pub mod quadrature;
pub(crate) mod relief;
pub(crate) mod spec;
pub mod sphere;
pub(crate) mod system;

pub use elements::BoxMesh;
pub use envelope::Envelope;
pub(crate) use error::PolyError;
pub use fast::FastField;
pub use kernels::Kernel;
pub use quadrature::QuadRule;
pub use quadrature::Quadrature;
pub use relief::Relief;
pub use relief::ReliefSpec;
pub(crate) use spec::PolyInputs;
pub(crate) use spec::PolySpec;
pub(crate) use spec::Solid;
pub use system::solve;
pub use system::solve_dirichlet;
pub use system::GivenPoint;
pub use system::Model;
pub use system::PointKind;
pub use system::Solution;
