//! `[[curve]] type = ...`: a point of body j held on a curve fixed in body i (a pin in a
//! curved slot, a roller on a track, a tool point on a path), the curve kinds and the keys each
//! takes (`cardan_mechanism::CurveSpec`, `cardan_constraints::Curve`). The curve parameter u is
//! an extra coordinate of the mechanism: arc length for a line, a circle and a helix, the
//! chord-length parameter of a spline.

use super::{Default, Entry, Key, Value, Vocabulary};
use cardan_mechanism::Quantity;

const POINT_I: Key = Key::new(
    "point_i",
    Value::Name,
    Default::Required,
    "a point of body i: the line's origin (u = 0), the circle's or the helix's centre",
);
const AXIS_I: Key = Key::new(
    "axis_i",
    Value::Name,
    Default::Required,
    "a vector of body i: the line's direction, the circle's or the helix's axis",
);
const X_AXIS_I: Key = Key::new(
    "x_axis_i",
    Value::Name,
    Default::Is("a direction perpendicular to axis_i chosen by cardan"),
    "a vector of body i: the direction from the centre to the point u = 0 (its part \
     perpendicular to axis_i); u grows counter-clockwise about axis_i",
);
const RADIUS: Key = Key::new(
    "radius",
    Value::Number(Quantity::Length),
    Default::Required,
    "R > 0 (m)",
);

/// How a spline interpolates its points (`[[curve]]` and `[[cam]]`).
pub(super) const INTERPOLATION: Key = Key::new(
    "interpolation",
    Value::Choice(&["cubic", "quintic"]),
    Default::Is("cubic"),
    "the spline through the points: cubic (C², natural or periodic ends) or quintic (C⁴: \
     continuous jerk and its rate along a path, a smoother cam lift; natural or periodic ends)",
);

/// The curve kinds.
pub const CURVES: Vocabulary = Vocabulary {
    what: "curve type",
    table: "[[curve]]",
    selector: "type",
    common: &[
        Key::new(
            "name",
            Value::Name,
            Default::Required,
            "unique among joints, curves, couplers, drivers and forces; the curve parameter's \
             columns in the joint tables carry it",
        ),
        Key::new("type", Value::Name, Default::Required, "the curve kind"),
        Key::new(
            "body_i",
            Value::Name,
            Default::Required,
            "the body carrying the curve (ground allowed)",
        ),
        Key::new(
            "body_j",
            Value::Name,
            Default::Required,
            "the body whose point follows the curve",
        ),
        Key::new(
            "point_j",
            Value::Name,
            Default::Required,
            "the point of body j held on the curve",
        ),
        Key::new(
            "initial_u",
            Value::Number(Quantity::Length),
            Default::Is("the parameter of the curve point nearest to point_j as drawn"),
            "the curve parameter u at the drawn pose (m)",
        ),
    ],
    entries: &[
        Entry {
            name: "line",
            aliases: &["straight"],
            summary: "a straight line through point_i along axis_i, u the signed distance from \
                      point_i (a straight slot: a prismatic joint without its rotation rows)",
            keys: &[POINT_I, AXIS_I],
        },
        Entry {
            name: "circle",
            aliases: &["arc"],
            summary: "a circle of radius R about axis_i through point_i, u = R θ the arc length \
                      from x_axis_i (any number of turns)",
            keys: &[POINT_I, AXIS_I, X_AXIS_I, RADIUS],
        },
        Entry {
            name: "helix",
            aliases: &[],
            summary: "a circular helix about axis_i: radius R, advance `pitch` per turn along \
                      axis_i, u the arc length",
            keys: &[
                POINT_I,
                AXIS_I,
                X_AXIS_I,
                RADIUS,
                Key::new(
                    "pitch",
                    Value::Number(Quantity::Length),
                    Default::Required,
                    "advance per turn along axis_i (m; negative: left-handed)",
                ),
            ],
        },
        Entry {
            name: "spline",
            aliases: &["cubic"],
            summary: "a cubic spline through points of body i (C², chord-length parameter): \
                      open with natural ends, or closed and periodic",
            keys: &[
                Key::new(
                    "points",
                    Value::Points(Quantity::Length),
                    Default::Required,
                    "the points the curve passes through, in body i's coordinates (at least 2; \
                     closed: at least 4 with the first repeated at the end)",
                ),
                Key::new(
                    "closed",
                    Value::Flag,
                    Default::Is("false"),
                    "a closed curve (a cam profile, a loop track): periodic, u wraps",
                ),
                INTERPOLATION,
            ],
        },
    ],
};
