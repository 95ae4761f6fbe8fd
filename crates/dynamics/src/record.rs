//! Storing results at output times.
