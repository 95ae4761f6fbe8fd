//! `[[cam]] follower = ...`: a cam pair, a follower's curve kept in tangent contact with a cam
//! profile (`cardan_mechanism::CamSpec`, `cardan_constraints::CurveOnCurve`), the follower kinds
//! and the keys each takes. The profile (a disc or a closed spline) is given by the common keys;
//! its parameter u and the follower curve's w are extra coordinates of the mechanism.

use super::{Default, Entry, Key, Value, Vocabulary};
use cardan_mechanism::Quantity;

const POINT_J: Key = Key::new(
    "point_j",
    Value::Name,
    Default::Required,
    "a point of body j: on the flat face, or the roller's centre",
);

/// The follower kinds.
pub const CAMS: Vocabulary = Vocabulary {
    what: "cam follower",
    table: "[[cam]]",
    selector: "follower",
    common: &[
        Key::new(
            "name",
            Value::Name,
            Default::Required,
            "unique among joints, curves, cams, couplers, drivers and forces; the columns of its \
             parameters in the joint tables carry it (NAME.u on the profile, NAME.w on the \
             follower's curve)",
        ),
        Key::new(
            "follower",
            Value::Name,
            Default::Required,
            "the follower's kind",
        ),
        Key::new(
            "body_i",
            Value::Name,
            Default::Required,
            "the cam (ground allowed)",
        ),
        Key::new(
            "axis_i",
            Value::Name,
            Default::Required,
            "a vector of body i normal to the cam's plane (the camshaft's axis); the disc's axis",
        ),
        Key::new(
            "profile",
            Value::Choice(&["disc", "spline"]),
            Default::Required,
            "the cam's profile: a circular disc (point_i, radius) or a closed spline through \
             points",
        ),
        Key::new(
            "point_i",
            Value::Name,
            Default::Is("none: needed by profile = \"disc\""),
            "a point of body i: the disc's centre (eccentric from the camshaft axis for a \
             harmonic cam)",
        ),
        Key::new(
            "radius",
            Value::Number(Quantity::Length),
            Default::Is("none: needed by profile = \"disc\""),
            "the disc's radius R > 0 (m)",
        ),
        Key::new(
            "x_axis_i",
            Value::Name,
            Default::Is("a direction perpendicular to axis_i chosen by cardan"),
            "a vector of body i: where the disc's u = 0 lies, seen from its centre",
        ),
        Key::new(
            "points",
            Value::Points(Quantity::Length),
            Default::Is("none: needed by profile = \"spline\""),
            "the profile's points in body i's coordinates, in the plane normal to axis_i, the \
             first repeated at the end (a closed, periodic C² spline)",
        ),
        super::curves::INTERPOLATION,
        Key::new("body_j", Value::Name, Default::Required, "the follower"),
        Key::new(
            "initial_u",
            Value::Number(Quantity::Length),
            Default::Is("the nearest points of the two curves as drawn"),
            "the profile's parameter u at the drawn pose (m)",
        ),
        Key::new(
            "initial_w",
            Value::Number(Quantity::Length),
            Default::Is("the nearest points of the two curves as drawn"),
            "the follower curve's parameter w at the drawn pose (m)",
        ),
    ],
    entries: &[
        Entry {
            name: "flat",
            aliases: &["flat_faced"],
            summary: "a flat-faced follower: the line through point_j along axis_j touches the \
                      profile (w is the distance of the contact point from point_j along the face)",
            keys: &[
                POINT_J,
                Key::new(
                    "axis_j",
                    Value::Name,
                    Default::Required,
                    "a vector of body j along the face, in the cam's plane",
                ),
            ],
        },
        Entry {
            name: "roller",
            aliases: &[],
            summary: "a roller follower: the circle of radius r about point_j (axis axis_j) \
                      touches the profile (the roller is fixed to body j: its spin is not \
                      modelled)",
            keys: &[
                POINT_J,
                Key::new(
                    "axis_j",
                    Value::Name,
                    Default::Required,
                    "a vector of body j along the roller's axis (parallel to the camshaft)",
                ),
                Key::new(
                    "roller_radius",
                    Value::Number(Quantity::Length),
                    Default::Required,
                    "the roller's radius r > 0 (m)",
                ),
            ],
        },
    ],
};
