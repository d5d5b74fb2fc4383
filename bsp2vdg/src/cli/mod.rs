//! The parts of the command line that are not the compile itself: option spellings,
//! process priority, what is printed, and the CI baseline mode.

pub mod args;
pub mod baseline;
pub mod batch;
pub mod outputs;
pub mod priority;
pub mod report;
