//! The parts of the command line that are not the compile itself: option spellings,
//! process priority, and what is printed.

pub mod args;
pub mod priority;
pub mod report;
