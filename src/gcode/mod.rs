//! G-code: parsing (and, in another branch, writing).

pub mod parse;
