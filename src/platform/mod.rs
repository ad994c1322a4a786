//! What the crate needs from the machine: what a path names, the output files it may write, the
//! memory available.

pub mod memory;
pub mod output_file;
pub mod paths;
