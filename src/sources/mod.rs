pub mod pde;
pub mod pde6;
