//! The tutorial's chapter of the report.

pub mod studies;
