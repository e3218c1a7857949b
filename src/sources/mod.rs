pub mod pde;
