//! `[[surface]] type = ...`: a point of body j held on a surface fixed in body i (a ball on a
//! dish, a stylus on a sculptured surface), the surface kinds and the keys each takes
//! (`cardan_mechanism::SurfaceSpec`, `cardan_constraints::Surface`). The surface parameters u
//! and v are two extra coordinates of the mechanism.

use super::{Default, Entry, Key, Value, Vocabulary};
use cardan_mechanism::Quantity;

const POINT_I: Key = Key::new(
    "point_i",
    Value::Name,
    Default::Required,
    "a point of body i: the plane's origin (u = v = 0), the sphere's, cylinder's or torus' centre",
);
const AXIS_I: Key = Key::new(
    "axis_i",
    Value::Name,
    Default::Required,
    "a vector of body i: the plane's normal, the sphere's polar axis, the cylinder's or the \
     torus' axis",
);
const X_AXIS_I: Key = Key::new(
    "x_axis_i",
    Value::Name,
    Default::Is("a direction perpendicular to axis_i chosen by cardan"),
    "a vector of body i: where u = 0 lies (its part perpendicular to axis_i); the plane's u \
     axis",
);
const RADIUS: Key = Key::new(
    "radius",
    Value::Number(Quantity::Length),
    Default::Required,
    "R > 0 (m): the sphere's or the cylinder's radius, the torus' centre circle",
);

/// The surface kinds.
pub const SURFACES: Vocabulary = Vocabulary {
    what: "surface type",
    table: "[[surface]]",
    selector: "type",
    common: &[
        Key::new(
            "name",
            Value::Name,
            Default::Required,
            "unique among joints, curves, surfaces, cams, couplers, drivers and forces; the \
             columns of its parameters in the joint tables carry it (NAME.u, NAME.v)",
        ),
        Key::new("type", Value::Name, Default::Required, "the surface kind"),
        Key::new(
            "body_i",
            Value::Name,
            Default::Required,
            "the body carrying the surface (ground allowed)",
        ),
        Key::new(
            "body_j",
            Value::Name,
            Default::Required,
            "the body whose point stays on the surface",
        ),
        Key::new(
            "point_j",
            Value::Name,
            Default::Required,
            "the point of body j held on the surface",
        ),
        Key::new(
            "initial_u",
            Value::Number(Quantity::Length),
            Default::Is("the parameters of the surface point nearest to point_j as drawn"),
            "u at the drawn pose (with initial_v)",
        ),
        Key::new(
            "initial_v",
            Value::Number(Quantity::Length),
            Default::Is("as initial_u"),
            "v at the drawn pose (with initial_u)",
        ),
    ],
    entries: &[
        Entry {
            name: "plane",
            aliases: &[],
            summary: "the plane through point_i normal to axis_i, u along x_axis_i and v across \
                      it (a point in a plane with its two coordinates as outputs)",
            keys: &[POINT_I, AXIS_I, X_AXIS_I],
        },
        Entry {
            name: "sphere",
            aliases: &[],
            summary: "a sphere of radius R about point_i, u the arc length along its equator \
                      (normal to axis_i) from x_axis_i, v along a meridian; singular at the poles",
            keys: &[POINT_I, AXIS_I, X_AXIS_I, RADIUS],
        },
        Entry {
            name: "cylinder",
            aliases: &[],
            summary:
                "a circular cylinder of radius R about axis_i through point_i, u = R θ around \
                      it from x_axis_i, v along axis_i",
            keys: &[POINT_I, AXIS_I, X_AXIS_I, RADIUS],
        },
        Entry {
            name: "torus",
            aliases: &[],
            summary: "a torus about axis_i through point_i: the points at tube_radius r from the \
                      centre circle of radius R; u the arc length along the centre circle, v \
                      around the tube from its outer equator",
            keys: &[
                POINT_I,
                AXIS_I,
                X_AXIS_I,
                RADIUS,
                Key::new(
                    "tube_radius",
                    Value::Number(Quantity::Length),
                    Default::Required,
                    "0 < r < R (m)",
                ),
            ],
        },
        Entry {
            name: "patch",
            aliases: &["bicubic"],
            summary: "a bicubic Bézier patch over 16 control points of body i, u and v in [0, 1] \
                      (a run stops where the point leaves it)",
            keys: &[Key::new(
                "points",
                Value::Points(Quantity::Length),
                Default::Required,
                "the 4 × 4 control points in body i's coordinates, row by row: points[4 i + j] \
                 is P_ij, i along u, j along v; the patch passes through the four corners",
            )],
        },
    ],
};
