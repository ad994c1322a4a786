//! What the crate needs from the machine: what a path names, the output files it may write, the
//! memory available, and what its loops can do at best (`make timing`'s floors).

pub mod floors;
pub mod memory;
pub mod output_file;
pub mod paths;
