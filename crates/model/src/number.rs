//! Numbers in messages: times and values as a reader expects them in a sentence ("at t = 0.5 s",
//! "at t = 1e12 s"). A leaf, so that reading a model (`prepare`) and checking its functions
//! (`functions`) say numbers alike without using each other.

/// A number in plain notation between 1e-4 and 1e9, in scientific notation beyond.
pub(crate) fn num(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-4..1e9).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}
