//! Locating an event inside a step: the Illinois variant of regula falsi on a function of time
//! over the stepper's dense output (Dowell & Jarratt 1971), shared by the stops' events and the
//! contacts' onsets.

/// The relative time tolerance of an event's location.
pub const EVENT_TIME_TOLERANCE: f64 = 1e-13;

/// At most this many evaluations locate an event.
pub(crate) const MAX_LOCATE: usize = 200;

/// The sign change of f in [a, b] (f > 0 at a, ≤ 0 at b) by the Illinois method, to
/// [`EVENT_TIME_TOLERANCE`]: the final bracket (a with f > 0, b with f ≤ 0), or (t, t) at a time
/// where |f| ≤ `zero`.
pub(crate) fn illinois(
    mut f: impl FnMut(f64) -> f64,
    (mut a, mut fa): (f64, f64),
    (mut b, mut fb): (f64, f64),
    zero: f64,
) -> (f64, f64) {
    let mut side = 0i8;
    for _ in 0..MAX_LOCATE {
        if b - a <= EVENT_TIME_TOLERANCE * (1.0 + b.abs()) {
            break;
        }
        let mut tm = (a * fb - b * fa) / (fb - fa);
        if !(tm > a && tm < b) {
            tm = 0.5 * (a + b);
        }
        let v = f(tm);
        if v.abs() <= zero {
            return (tm, tm);
        }
        if v > 0.0 {
            (a, fa) = (tm, v);
            if side == 1 {
                fb *= 0.5;
            }
            side = 1;
        } else {
            (b, fb) = (tm, v);
            if side == -1 {
                fa *= 0.5;
            }
            side = -1;
        }
    }
    (a, b)
}
