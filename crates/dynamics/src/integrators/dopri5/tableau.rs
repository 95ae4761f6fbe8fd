//! The Dormand-Prince 5(4) tableau (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.5) and
//! the coefficients of the 4th-order continuous extension of their DOPRI5 code (`D`, §II.6).
//!
//! Stage j (1..7) of a step of size h from (t, y₀): Y_j = y₀ + h Σ_{i<j} a_ji k_i,
//! k_j = f(t + c_j h, Y_j). The 5th-order solution is Y₇ (the last row of `A` is b, "first
//! same as last"); the error estimate h Σ e_j k_j is its difference from the 4th-order one.

/// c_j.
pub(super) const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];

/// a_ji (row j: the weights of the stages before it).
pub(super) const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];

/// e_j = b_j − b̂_j: the error estimate's weights.
pub(super) const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// d_j: the weights of the continuous extension's last coefficient.
pub(super) const D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];
