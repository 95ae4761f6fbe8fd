//! The TOML model file, as written (docs/model-format.md describes it for users).
//!
//! Every value a later check may complain about is kept as [`Spanned`], so an error such as
//! "unknown point" points at the line and column of the offending value. Every table rejects
//! unknown keys ([`parse`] turns serde's message into one with the nearest valid key).

use crate::diag::{did_you_mean, Error, Source};
use serde::Deserialize;
use std::collections::BTreeMap;
use toml::Spanned;

/// A spanned number: written as a number (`0.08`) or as text, an expression of numbers with
/// units and parameters (`"80 mm"`, `"2 * crank"`, [`crate::parameters`]) whose value is in the
/// model's units.
#[derive(Debug, Clone, PartialEq)]
pub struct Num(Spanned<f64>);

impl Num {
    /// `value` at `span`.
    pub fn new(span: std::ops::Range<usize>, value: f64) -> Self {
        Self(Spanned::new(span, value))
    }

    /// The value.
    pub fn into_inner(self) -> f64 {
        self.0.into_inner()
    }
}

impl std::ops::Deref for Num {
    type Target = Spanned<f64>;
    fn deref(&self) -> &Spanned<f64> {
        &self.0
    }
}

impl<'de> Deserialize<'de> for Num {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = Spanned::<NumberOrText>::deserialize(d)?;
        let span = s.span();
        let value = match s.into_inner() {
            NumberOrText::Number(x) => x,
            NumberOrText::Text(t) => crate::parameters::number_in_scope(&t)
                .map_err(<D::Error as serde::de::Error>::custom)?,
        };
        Ok(Self::new(span, value))
    }
}

/// A number as TOML writes it, or a text to evaluate.
enum NumberOrText {
    Number(f64),
    Text(String),
}

impl<'de> Deserialize<'de> for NumberOrText {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = NumberOrText;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a number (or a text such as \"80 mm\" or \"2 * crank\")")
            }
            fn visit_f64<E>(self, v: f64) -> Result<NumberOrText, E> {
                Ok(NumberOrText::Number(v))
            }
            fn visit_i64<E>(self, v: i64) -> Result<NumberOrText, E> {
                Ok(NumberOrText::Number(v as f64))
            }
            fn visit_u64<E>(self, v: u64) -> Result<NumberOrText, E> {
                Ok(NumberOrText::Number(v as f64))
            }
            fn visit_str<E>(self, v: &str) -> Result<NumberOrText, E> {
                Ok(NumberOrText::Text(v.to_string()))
            }
        }
        d.deserialize_any(V)
    }
}
/// A spanned 3-vector.
pub type Vec3 = Spanned<[Num; 3]>;
/// A spanned name.
pub type Name = Spanned<String>;

/// The whole file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelFile {
    /// `[model]`: name and notes.
    pub model: Spanned<ModelSection>,
    /// `[ground]`: points and vectors on the fixed frame.
    #[serde(default)]
    pub ground: Option<Spanned<GroundSection>>,
    /// `[[body]]`.
    #[serde(default)]
    pub body: Vec<Spanned<BodySection>>,
    /// `[[joint]]`.
    #[serde(default)]
    pub joint: Vec<Spanned<JointSection>>,
    /// `[[curve]]`: points held on curves (slots, tracks, paths).
    #[serde(default)]
    pub curve: Vec<Spanned<CurveSection>>,
    /// `[[cam]]`: cam pairs (a follower's curve tangent to a cam profile).
    #[serde(default)]
    pub cam: Vec<Spanned<CamSection>>,
    /// `[[surface]]`: points held on surfaces.
    #[serde(default)]
    pub surface: Vec<Spanned<SurfaceSection>>,
    /// `[[driver]]`.
    #[serde(default)]
    pub driver: Vec<Spanned<DriverSection>>,
    /// `[[coupler]]`: gears, racks and pinions, screws.
    #[serde(default)]
    pub coupler: Vec<Spanned<CouplerSection>>,
    /// `[[force]]`: force elements (dynamic analysis).
    #[serde(default)]
    pub force: Vec<Spanned<ForceSection>>,
    /// `[[limit]]`: end stops on joint coordinates.
    #[serde(default)]
    pub limit: Vec<Spanned<LimitSection>>,
    /// `[[friction]]`: Coulomb friction in joints (dynamic analyses).
    #[serde(default)]
    pub friction: Vec<Spanned<FrictionSection>>,
    /// `[[material]]`: contact materials of the collision shapes.
    #[serde(default)]
    pub material: Vec<Spanned<MaterialSection>>,
    /// `[[shape]]`: collision shapes on bodies and the ground (dynamic analyses).
    #[serde(default)]
    pub shape: Vec<Spanned<ShapeSection>>,
    /// `[urdf]`: the file is an overlay on a URDF robot ([`crate::overlay`]).
    #[serde(default)]
    pub urdf: Option<Spanned<UrdfSection>>,
    /// `[analysis]`.
    pub analysis: Option<Spanned<AnalysisSection>>,
    /// The keys written in the sections with vocabularies, with their spans (not a key of the
    /// file: read off the parsed document, [`parse`]).
    #[serde(skip)]
    pub keys: crate::vocabulary::KeySpans,
    /// `[parameters]`: named values (read off the parsed document before the rest, [`parse`]).
    #[serde(default, rename = "parameters")]
    pub parameters_table: Option<serde::de::IgnoredAny>,
    /// The parameters, evaluated with the values given from outside ([`Source::set`]).
    #[serde(skip)]
    pub parameters: std::sync::Arc<crate::parameters::Parameters>,
}

/// `[model]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelSection {
    /// Used for the default output directory `out/<name>/`.
    pub name: Name,
    /// Free text.
    #[serde(default)]
    pub description: Option<String>,
    /// Must be "SI" (m, kg, s, rad) if given.
    #[serde(default)]
    pub units: Option<Name>,
    /// Gravity [m/s²] (used by dynamic analysis; ignored by kinematics).
    #[serde(default)]
    pub gravity: Option<Vec3>,
}

/// `[urdf]`: the robot this file adds to ([`crate::overlay`]).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UrdfSection {
    /// The URDF file, relative to this file's directory.
    pub file: Name,
    /// `"fixed"` (default): the root link is the ground; `"floating"`: it moves freely.
    #[serde(default)]
    pub base: Option<Name>,
    /// `"couple"` (default): mimic joints as gear couplers; `"free"`: as free joints.
    #[serde(default)]
    pub mimic: Option<Name>,
    /// The position limits as stops (default true).
    #[serde(default)]
    pub limits: Option<bool>,
    /// Joints' `<dynamics damping>` as dampers (default false).
    #[serde(default)]
    pub damping: Option<bool>,
    /// Joints' `<dynamics friction>` as constant friction (default false).
    #[serde(default)]
    pub friction: Option<bool>,
    /// The robot's collision shapes touch each other too (default false; with `collision`).
    #[serde(default)]
    pub self_collision: Option<bool>,
    /// The links' `<collision>` elements as contact shapes of this `[[material]]` (default:
    /// none).
    #[serde(default)]
    pub collision: Option<Name>,
}

/// `[ground]`.
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct GroundSection {
    /// Named points in global coordinates \[m\].
    #[serde(default)]
    pub points: BTreeMap<Name, Vec3>,
    /// Named direction vectors in global coordinates.
    #[serde(default)]
    pub vectors: BTreeMap<Name, Vec3>,
}

/// Inertia: a full 3×3 matrix or `{ diag = [...] }`.
#[derive(Debug)]
pub enum InertiaSpec {
    /// The full matrix in body coordinates [kg m²].
    Matrix([[Real; 3]; 3]),
    /// Principal moments.
    Diag {
        /// [Ixx, Iyy, Izz].
        diag: [Real; 3],
    },
}

/// The inertia's words, for its messages.
const INERTIA_FORMS: &str = "inertia must be a 3×3 matrix [[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], \
                             [Ixz, Iyz, Izz]] or { diag = [Ixx, Iyy, Izz] } (numbers in kg m²)";

impl<'de> Deserialize<'de> for InertiaSpec {
    // By hand rather than `untagged`, so that a number's own message (an unknown parameter)
    // reaches the user instead of "did not match any variant".
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = InertiaSpec;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(INERTIA_FORMS)
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut a: A,
            ) -> Result<InertiaSpec, A::Error> {
                let mut rows = Vec::new();
                while let Some(row) = a.next_element::<Vec<Real>>()? {
                    let row: [Real; 3] =
                        (row.try_into()).map_err(|_| serde::de::Error::custom(INERTIA_FORMS))?;
                    rows.push(row);
                }
                let rows: [[Real; 3]; 3] =
                    (rows.try_into()).map_err(|_| serde::de::Error::custom(INERTIA_FORMS))?;
                Ok(InertiaSpec::Matrix(rows))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut a: A,
            ) -> Result<InertiaSpec, A::Error> {
                let mut diag = None;
                while let Some(key) = a.next_key::<String>()? {
                    if key != "diag" || diag.is_some() {
                        return Err(serde::de::Error::custom(INERTIA_FORMS));
                    }
                    let row = a.next_value::<Vec<Real>>()?;
                    diag = Some(
                        row.try_into()
                            .map_err(|_| serde::de::Error::custom(INERTIA_FORMS))?,
                    );
                }
                diag.map(|diag| InertiaSpec::Diag { diag })
                    .ok_or_else(|| serde::de::Error::custom(INERTIA_FORMS))
            }
        }
        d.deserialize_any(V)
    }
}

/// A number without its place (within a value whose place is kept, such as the inertia):
/// written as a number or as text, as [`Num`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Real(pub f64);

impl<'de> Deserialize<'de> for Real {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        match NumberOrText::deserialize(d)? {
            NumberOrText::Number(x) => Ok(Self(x)),
            NumberOrText::Text(t) => crate::parameters::number_in_scope(&t)
                .map(Self)
                .map_err(<D::Error as serde::de::Error>::custom),
        }
    }
}

/// `orientation = { ... }`: exactly one of the forms.
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct OrientationSpec {
    /// [e0, e1, e2, e3] (normalized if within 1e-6 of unit length).
    #[serde(default)]
    pub euler_parameters: Option<Spanned<[Num; 4]>>,
    /// Rotation axis (global), with `angle`.
    #[serde(default)]
    pub axis: Option<Vec3>,
    /// Rotation angle \[rad\], with `axis`.
    #[serde(default)]
    pub angle: Option<Num>,
    /// z-x-z Euler angles \[rad\].
    #[serde(default)]
    pub euler313: Option<Vec3>,
    /// x-y-z (Bryant) angles \[rad\].
    #[serde(default)]
    pub euler123: Option<Vec3>,
    /// The body z axis in global coordinates (with `x`).
    #[serde(default)]
    pub z: Option<Vec3>,
    /// The body x axis in global coordinates (with `z`; its part ⟂ z is used).
    #[serde(default)]
    pub x: Option<Vec3>,
}

/// `[[body]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySection {
    /// Unique name ("ground" is reserved).
    pub name: Name,
    /// \[kg\].
    #[serde(default)]
    pub mass: Option<Num>,
    /// [kg m²] about the body origin (the centre of mass), body axes.
    #[serde(default)]
    pub inertia: Option<Spanned<InertiaSpec>>,
    /// Initial (estimated) position of the body origin \[m\].
    #[serde(default)]
    pub position: Option<Vec3>,
    /// Initial (estimated) orientation; identity if absent.
    #[serde(default)]
    pub orientation: Option<Spanned<OrientationSpec>>,
    /// Named points in body coordinates \[m\].
    #[serde(default)]
    pub points: BTreeMap<Name, Vec3>,
    /// Named points given in global coordinates at the initial pose \[m\].
    #[serde(default)]
    pub global_points: BTreeMap<Name, Vec3>,
    /// Named directions in body coordinates.
    #[serde(default)]
    pub vectors: BTreeMap<Name, Vec3>,
    /// Named directions given in global coordinates at the initial pose.
    #[serde(default)]
    pub global_vectors: BTreeMap<Name, Vec3>,
    /// Initial velocity of the body origin (centre of mass), global [m/s] (dynamic analysis).
    #[serde(default)]
    pub velocity: Option<Vec3>,
    /// Initial angular velocity, global components [rad/s] (dynamic analysis).
    #[serde(default)]
    pub angular_velocity: Option<Vec3>,
    /// Initial angular velocity, body components [rad/s] (dynamic analysis).
    #[serde(default)]
    pub angular_velocity_local: Option<Vec3>,
    /// What the animation draws for this body (derived from its points and joints if absent).
    #[serde(default)]
    pub geometry: Option<Spanned<Vec<Spanned<GeometrySpec>>>>,
}

/// One item of a body's `geometry = [...]`: a primitive or a mesh file, placed in the body
/// frame (crates/cli/src/geometry.rs reads it; docs/animation.md describes it).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeometrySpec {
    /// "box", "cylinder", "sphere" or "mesh".
    pub shape: Name,
    /// Box edge lengths \[m\].
    #[serde(default)]
    pub size: Option<Vec3>,
    /// Cylinder or sphere radius \[m\].
    #[serde(default)]
    pub radius: Option<Num>,
    /// Cylinder length \[m\].
    #[serde(default)]
    pub length: Option<Num>,
    /// Cylinder axis in the item's frame (default z).
    #[serde(default)]
    pub axis: Option<Vec3>,
    /// Origin of the item in body coordinates \[m\] (default the body origin).
    #[serde(default)]
    pub position: Option<Vec3>,
    /// Orientation of the item relative to the body frame (the forms of a body's orientation).
    #[serde(default)]
    pub orientation: Option<Spanned<OrientationSpec>>,
    /// Mesh file (.stl or .obj), relative to the model file.
    #[serde(default)]
    pub file: Option<Name>,
    /// Factor from the mesh file's coordinates to metres (default 1; 0.001 for millimetres).
    #[serde(default)]
    pub scale: Option<Num>,
}

/// `[[joint]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointSection {
    /// Unique name.
    pub name: Name,
    /// A kind of the joint table (`cardan_constraints::KINDS`), e.g. revolute.
    #[serde(rename = "type")]
    pub kind: Name,
    /// Body i ("ground" allowed).
    pub body_i: Name,
    /// Body j.
    pub body_j: Name,
    /// Point on body i.
    pub point_i: Name,
    /// Point on body j.
    pub point_j: Name,
    /// Joint axis (z of the joint marker) on body i.
    #[serde(default)]
    pub axis_i: Option<Name>,
    /// Joint axis on body j.
    #[serde(default)]
    pub axis_j: Option<Name>,
    /// Reference direction ⟂ axis on body i (zero of the joint angle).
    #[serde(default)]
    pub x_axis_i: Option<Name>,
    /// Reference direction ⟂ axis on body j.
    #[serde(default)]
    pub x_axis_j: Option<Name>,
    /// Length ℓ \[m\] of a spherical_spherical, rev_cyl, cyl_sph or rev_rev joint (default: its
    /// initial value).
    #[serde(default)]
    pub length: Option<Num>,
    /// Offset h \[m\] of the plane along axis_i (point_in_plane, line_in_plane, planar, rev_rev;
    /// default 0).
    #[serde(default)]
    pub offset: Option<Num>,
    /// Angle α \[rad\] of an angle or cone joint (default: its initial value).
    #[serde(default)]
    pub angle: Option<Num>,
    /// The joint's effort rating (SI: N m for an angle, N for a slide; a URDF `<limit effort>`):
    /// a driver effort beyond it is a warning.
    #[serde(default)]
    pub effort_limit: Option<Num>,
    /// The joint's rate rating (SI: rad/s or m/s; a URDF `<limit velocity>`): a driven rate
    /// beyond it is a warning.
    #[serde(default)]
    pub rate_limit: Option<Num>,
}

/// `function = { kind = ..., ... }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FunctionSpec {
    /// constant, polynomial, harmonic, ramp, spline, expression.
    pub kind: Name,
    /// expression: the formula of t (`cardan_constraints::expression`).
    #[serde(default)]
    pub text: Option<Name>,
    /// constant: the value.
    #[serde(default)]
    pub value: Option<Num>,
    /// polynomial: c0, c1, ... (f = Σ c_k t^k).
    #[serde(default)]
    pub coefficients: Option<Spanned<Vec<Num>>>,
    /// harmonic: a.
    #[serde(default)]
    pub amplitude: Option<Num>,
    /// harmonic: ω [rad/s].
    #[serde(default)]
    pub frequency: Option<Num>,
    /// harmonic: φ \[rad\].
    #[serde(default)]
    pub phase: Option<Num>,
    /// harmonic: b.
    #[serde(default)]
    pub offset: Option<Num>,
    /// ramp: start time \[s\].
    #[serde(default)]
    pub t0: Option<Num>,
    /// ramp: end time \[s\].
    #[serde(default)]
    pub t1: Option<Num>,
    /// ramp: value before t0.
    #[serde(default)]
    pub f0: Option<Num>,
    /// ramp: value after t1.
    #[serde(default)]
    pub f1: Option<Num>,
    /// spline: knot times \[s\].
    #[serde(default)]
    pub times: Option<Spanned<Vec<Num>>>,
    /// spline: knot values.
    #[serde(default)]
    pub values: Option<Spanned<Vec<Num>>>,
}

/// `[[driver]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DriverSection {
    /// Unique name.
    pub name: Name,
    /// rotation, translation, distance, coordinate, general_motion, path.
    #[serde(rename = "type")]
    pub kind: Name,
    /// rotation / translation: the driven joint.
    #[serde(default)]
    pub joint: Option<Name>,
    /// path: the `[[curve]]` whose parameter is driven.
    #[serde(default)]
    pub curve: Option<Name>,
    /// path: the function is the arc length travelled.
    #[serde(default)]
    pub arc_length: Option<Spanned<bool>>,
    /// distance, general_motion: body i.
    #[serde(default)]
    pub body_i: Option<Name>,
    /// distance: point on body i; general_motion: the origin of frame i.
    #[serde(default)]
    pub point_i: Option<Name>,
    /// distance, general_motion: body j.
    #[serde(default)]
    pub body_j: Option<Name>,
    /// distance: point on body j; general_motion: the origin of frame j.
    #[serde(default)]
    pub point_j: Option<Name>,
    /// coordinate: the body.
    #[serde(default)]
    pub body: Option<Name>,
    /// coordinate: the point.
    #[serde(default)]
    pub point: Option<Name>,
    /// coordinate: "x", "y" or "z".
    #[serde(default)]
    pub coordinate: Option<Name>,
    /// general_motion: z of frame i (a vector of body i; default: the body frame).
    #[serde(default)]
    pub axis_i: Option<Name>,
    /// general_motion: x of frame i.
    #[serde(default)]
    pub x_axis_i: Option<Name>,
    /// general_motion: z of frame j.
    #[serde(default)]
    pub axis_j: Option<Name>,
    /// general_motion: x of frame j.
    #[serde(default)]
    pub x_axis_j: Option<Name>,
    /// general_motion: the rotation sequence, e.g. "xyz" (default) or "zxz".
    #[serde(default)]
    pub order: Option<Name>,
    /// general_motion: three functions, the translations along x_i, y_i, z_i \[m\].
    #[serde(default)]
    pub translation: Option<Spanned<Vec<Spanned<FunctionSpec>>>>,
    /// general_motion: three functions, the angles of the sequence \[rad\].
    #[serde(default)]
    pub rotation: Option<Spanned<Vec<Spanned<FunctionSpec>>>>,
    /// The time function (every type but general_motion).
    #[serde(default)]
    pub function: Option<Spanned<FunctionSpec>>,
}

/// `[[coupler]]`: one equation between the coordinates of two joints.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CouplerSection {
    /// Unique name among joints, couplers, drivers and forces.
    pub name: Name,
    /// gear, rack_pinion, screw.
    #[serde(rename = "type")]
    pub kind: Name,
    /// gear: the joint of gear i (revolute or cylindrical).
    #[serde(default)]
    pub joint_i: Option<Name>,
    /// gear: the joint of gear j.
    #[serde(default)]
    pub joint_j: Option<Name>,
    /// gear: pitch radius of gear i \[m\] (negative: internal gear).
    #[serde(default)]
    pub radius_i: Option<Num>,
    /// gear: pitch radius of gear j \[m\].
    #[serde(default)]
    pub radius_j: Option<Num>,
    /// gear: the signed speed ratio dθ_j/dθ_i instead of the radii.
    #[serde(default)]
    pub ratio: Option<Num>,
    /// rack_pinion, screw: the joint whose slide moves (prismatic or cylindrical).
    #[serde(default)]
    pub slide_joint: Option<Name>,
    /// rack_pinion, screw: the joint whose angle turns (revolute or cylindrical).
    #[serde(default)]
    pub angle_joint: Option<Name>,
    /// screw: one cylindrical joint (slide and angle).
    #[serde(default)]
    pub joint: Option<Name>,
    /// rack_pinion: the pinion's pitch radius \[m\].
    #[serde(default)]
    pub radius: Option<Num>,
    /// screw: advance per revolution \[m\] (negative: left-hand thread).
    #[serde(default)]
    pub pitch: Option<Num>,
    /// The law's constant c [rad for a gear, m otherwise] (default: its initial value).
    #[serde(default)]
    pub constant: Option<Num>,
}

/// `[[curve]]`: a point of body j held on a curve fixed in body i
/// ([`crate::vocabulary::CURVES`]).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveSection {
    /// Unique name among joints, curves, couplers, drivers and forces.
    pub name: Name,
    /// line, circle, helix or spline.
    #[serde(rename = "type")]
    pub kind: Name,
    /// The body carrying the curve.
    pub body_i: Name,
    /// The body whose point follows the curve.
    pub body_j: Name,
    /// The point of body j on the curve.
    pub point_j: Name,
    /// line, circle, helix: the origin or centre on body i.
    #[serde(default)]
    pub point_i: Option<Name>,
    /// line, circle, helix: the direction or axis on body i.
    #[serde(default)]
    pub axis_i: Option<Name>,
    /// circle, helix: where u = 0 lies, seen from the centre.
    #[serde(default)]
    pub x_axis_i: Option<Name>,
    /// circle, helix: R \[m\].
    #[serde(default)]
    pub radius: Option<Num>,
    /// helix: advance per turn \[m\].
    #[serde(default)]
    pub pitch: Option<Num>,
    /// spline: the points in body i's coordinates \[m\].
    #[serde(default)]
    pub points: Option<Spanned<Vec<Vec3>>>,
    /// spline: closed and periodic.
    #[serde(default)]
    pub closed: Option<Spanned<bool>>,
    /// spline: cubic or quintic.
    #[serde(default)]
    pub interpolation: Option<Name>,
    /// u at the drawn pose \[m\].
    #[serde(default)]
    pub initial_u: Option<Num>,
}

/// `[[surface]]`: a point of body j held on a surface fixed in body i
/// ([`crate::vocabulary::SURFACES`]).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceSection {
    /// Unique name among all elements.
    pub name: Name,
    /// plane, sphere, cylinder, torus or patch.
    #[serde(rename = "type")]
    pub kind: Name,
    /// The body carrying the surface.
    pub body_i: Name,
    /// The body whose point stays on it.
    pub body_j: Name,
    /// The point of body j on the surface.
    pub point_j: Name,
    /// plane, sphere, cylinder, torus: the origin or centre on body i.
    #[serde(default)]
    pub point_i: Option<Name>,
    /// plane, sphere, cylinder, torus: the normal or axis on body i.
    #[serde(default)]
    pub axis_i: Option<Name>,
    /// plane, sphere, cylinder, torus: where u = 0 lies.
    #[serde(default)]
    pub x_axis_i: Option<Name>,
    /// sphere, cylinder, torus: R \[m\].
    #[serde(default)]
    pub radius: Option<Num>,
    /// torus: the tube's radius \[m\].
    #[serde(default)]
    pub tube_radius: Option<Num>,
    /// patch: the 16 control points in body i's coordinates \[m\].
    #[serde(default)]
    pub points: Option<Spanned<Vec<Vec3>>>,
    /// u at the drawn pose.
    #[serde(default)]
    pub initial_u: Option<Num>,
    /// v at the drawn pose.
    #[serde(default)]
    pub initial_v: Option<Num>,
}

/// `[[cam]]`: a follower's curve on body j in tangent contact with a cam profile on body i
/// ([`crate::vocabulary::CAMS`]).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CamSection {
    /// Unique name among joints, curves, cams, couplers, drivers and forces.
    pub name: Name,
    /// flat or roller.
    pub follower: Name,
    /// The cam.
    pub body_i: Name,
    /// The cam plane's normal on body i.
    pub axis_i: Name,
    /// disc or spline.
    pub profile: Name,
    /// disc: its centre on body i.
    #[serde(default)]
    pub point_i: Option<Name>,
    /// disc: R \[m\].
    #[serde(default)]
    pub radius: Option<Num>,
    /// disc: where u = 0 lies.
    #[serde(default)]
    pub x_axis_i: Option<Name>,
    /// spline: the profile's points in body i's coordinates \[m\].
    #[serde(default)]
    pub points: Option<Spanned<Vec<Vec3>>>,
    /// spline: cubic or quintic.
    #[serde(default)]
    pub interpolation: Option<Name>,
    /// The follower.
    pub body_j: Name,
    /// The face's point or the roller's centre on body j.
    pub point_j: Name,
    /// The face's direction or the roller's axis on body j.
    #[serde(default)]
    pub axis_j: Option<Name>,
    /// roller: r \[m\].
    #[serde(default)]
    pub roller_radius: Option<Num>,
    /// u at the drawn pose \[m\].
    #[serde(default)]
    pub initial_u: Option<Num>,
    /// w at the drawn pose \[m\].
    #[serde(default)]
    pub initial_w: Option<Num>,
}

/// `[[limit]]`: a lower bound, an upper bound or both on one coordinate of a joint (end
/// stops), with impacts or a compliant law ([`crate::vocabulary::LIMITS`]).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LimitSection {
    /// Unique name among joints, couplers, drivers, forces, limits and frictions.
    pub name: Name,
    /// The joint whose coordinate is limited.
    pub joint: Name,
    /// The coordinate's name (angle, slide, distance...; default: the kind's own).
    #[serde(default)]
    pub coordinate: Option<Name>,
    /// lo \[rad or m\].
    #[serde(default)]
    pub lower: Option<Num>,
    /// hi \[rad or m\].
    #[serde(default)]
    pub upper: Option<Num>,
    /// "impact" (default) or "compliant".
    #[serde(default)]
    pub law: Option<Name>,
    /// impact: Newton's coefficient of restitution e ∈ \[0, 1\].
    #[serde(default)]
    pub restitution: Option<Num>,
    /// compliant: k \[N/mⁿ or N m/radⁿ\].
    #[serde(default)]
    pub stiffness: Option<Num>,
    /// compliant: c \[N s/mⁿ⁺¹ or N m s/radⁿ⁺¹\].
    #[serde(default)]
    pub damping: Option<Num>,
    /// compliant: n ≥ 1.
    #[serde(default)]
    pub exponent: Option<Num>,
}

/// `[[friction]]`: Coulomb friction in one joint from its reaction
/// ([`crate::vocabulary::FRICTIONS`]).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrictionSection {
    /// Unique name among joints, couplers, drivers, forces, limits and frictions.
    pub name: Name,
    /// The joint (revolute, prismatic, cylindrical or spherical).
    pub joint: Name,
    /// "coulomb" (default) or "constant".
    #[serde(default)]
    pub law: Option<Name>,
    /// μ ≥ 0.
    #[serde(default)]
    pub coefficient: Option<Num>,
    /// The pin, journal or ball radius r \[m\] of a rotating joint.
    #[serde(default)]
    pub radius: Option<Num>,
    /// A load N₀ ≥ 0 \[N\] added to the reaction.
    #[serde(default)]
    pub preload: Option<Num>,
    /// v_s > 0 of the regularized sign \[m/s or rad/s\].
    #[serde(default)]
    pub stiction_velocity: Option<Num>,
    /// law "constant": a slide's friction force F_c ≥ 0 \[N\].
    #[serde(default)]
    pub force: Option<Num>,
    /// law "constant": a pin's or ball's friction torque T_c ≥ 0 \[N m\].
    #[serde(default)]
    pub torque: Option<Num>,
}

/// `[[material]]`: a contact material ([`crate::vocabulary::MATERIALS`]).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSection {
    /// Unique name among the materials.
    pub name: Name,
    /// "hunt_crossley" (default).
    #[serde(default)]
    pub law: Option<Name>,
    /// K \[N/mⁿ\] of F = K δⁿ.
    #[serde(default)]
    pub stiffness: Option<Num>,
    /// n of F = K δⁿ (default 1.5).
    #[serde(default)]
    pub exponent: Option<Num>,
    /// E \[Pa\] (Hertz's stiffness from the shapes' curvature).
    #[serde(default)]
    pub youngs_modulus: Option<Num>,
    /// ν.
    #[serde(default)]
    pub poisson_ratio: Option<Num>,
    /// e ∈ (0, 1].
    #[serde(default)]
    pub restitution: Option<Num>,
    /// μ_d ≥ 0.
    #[serde(default)]
    pub friction: Option<Num>,
    /// μ_s ≥ μ_d.
    #[serde(default)]
    pub friction_static: Option<Num>,
    /// v_s \[m/s\].
    #[serde(default)]
    pub slip_velocity: Option<Num>,
    /// Two material names: this is their pair's law, not a material of shapes.
    #[serde(default)]
    pub between: Option<Spanned<Vec<Name>>>,
}

/// `[[shape]]`: a collision shape fixed in a body ([`crate::vocabulary::SHAPES`]).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShapeSection {
    /// Unique name among the shapes.
    pub name: Name,
    /// sphere, capsule, cylinder, box, plane, convex_mesh or mesh.
    #[serde(rename = "type")]
    pub kind: Name,
    /// The body (ground allowed).
    pub body: Name,
    /// The material's name.
    pub material: Name,
    /// A point of the body: the shape's centre (default the body's reference point).
    #[serde(default)]
    pub point: Option<Name>,
    /// A vector of the body: the shape's z axis (default the body's z).
    #[serde(default)]
    pub axis: Option<Name>,
    /// A vector of the body: the shape's x axis (its part across `axis`).
    #[serde(default)]
    pub x_axis: Option<Name>,
    /// sphere, capsule, cylinder: r \[m\].
    #[serde(default)]
    pub radius: Option<Num>,
    /// capsule, cylinder: ℓ \[m\].
    #[serde(default)]
    pub length: Option<Num>,
    /// box: edge lengths \[m\].
    #[serde(default)]
    pub size: Option<Vec3>,
    /// convex_mesh, mesh: an STL or OBJ file, relative to the model file.
    #[serde(default)]
    pub file: Option<Name>,
    /// convex_mesh, mesh: from the file's coordinates to the model's length unit.
    #[serde(default)]
    pub scale: Option<Num>,
    /// convex_mesh: points whose hull is the shape \[m\].
    #[serde(default)]
    pub points: Option<Spanned<Vec<Vec3>>>,
    /// The collision groups (1 – 32) the shape belongs to.
    #[serde(default)]
    pub groups: Option<Spanned<Vec<Num>>>,
    /// The groups it collides with.
    #[serde(default)]
    pub collides_with: Option<Spanned<Vec<Num>>>,
}

/// `[[force]]`: one force element (used by dynamic analysis only).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForceSection {
    /// Unique name among joints, drivers and forces.
    pub name: Name,
    /// point_force, torque, spring_damper, rotational_spring_damper,
    /// translational_spring_damper.
    #[serde(rename = "type")]
    pub kind: Name,
    /// point_force / torque: the body.
    #[serde(default)]
    pub body: Option<Name>,
    /// point_force: the point of application.
    #[serde(default)]
    pub point: Option<Name>,
    /// point_force / torque: a constant vector [N or N m].
    #[serde(default)]
    pub value: Option<Vec3>,
    /// point_force / torque: three time functions (x, y, z) instead of `value`.
    #[serde(default)]
    pub components: Option<Spanned<Vec<Spanned<FunctionSpec>>>>,
    /// point_force / torque: "global" (default) or "body".
    #[serde(default)]
    pub frame: Option<Name>,
    /// spring_damper: body i.
    #[serde(default)]
    pub body_i: Option<Name>,
    /// spring_damper: point on body i.
    #[serde(default)]
    pub point_i: Option<Name>,
    /// spring_damper: body j.
    #[serde(default)]
    pub body_j: Option<Name>,
    /// spring_damper: point on body j.
    #[serde(default)]
    pub point_j: Option<Name>,
    /// spring_damper [N/m] / rotational_spring_damper [N m/rad]: k ≥ 0.
    #[serde(default)]
    pub stiffness: Option<Num>,
    /// spring_damper [N s/m] / rotational_spring_damper [N m s/rad]: c ≥ 0.
    #[serde(default)]
    pub damping: Option<Num>,
    /// spring_damper: free length ℓ0 \[m\] (default: the initial distance).
    #[serde(default)]
    pub free_length: Option<Num>,
    /// spring_damper: actuator tension f_a(t) \[N\], added to the spring-damper tension.
    #[serde(default)]
    pub actuator: Option<Spanned<FunctionSpec>>,
    /// rotational / translational_spring_damper: the joint.
    #[serde(default)]
    pub joint: Option<Name>,
    /// rotational_spring_damper: rest angle θ0 \[rad\] (default 0).
    #[serde(default)]
    pub rest_angle: Option<Num>,
    /// translational_spring_damper: rest position s0 \[m\] of the slide (default 0).
    #[serde(default)]
    pub rest_position: Option<Num>,
}

/// `[analysis]`.
///
/// One field per key of the file's flat `[analysis]` table (22), which is why it is not
/// grouped into sub-structs: `#[serde(flatten)]` would drop the keys' spans (toml's `Spanned`
/// does not survive serde's buffering) and cannot be combined with `deny_unknown_fields`. Which
/// keys an analysis kind takes is the vocabulary's business (`vocabulary::ANALYSES`), not this
/// struct's.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnalysisSection {
    /// "kinematic", "dynamic", "inverse_dynamics", "static", "quasi_static" or "modal".
    pub kind: Name,
    /// Start time \[s\] (default 0).
    #[serde(default)]
    pub t_start: Option<Num>,
    /// End time \[s\] (required except by static and modal analyses).
    #[serde(default)]
    pub t_end: Option<Num>,
    /// static, modal: the time at which the drivers are held \[s\] (default 0).
    #[serde(default)]
    pub time: Option<Num>,
    /// static, quasi_static, modal: equal load increments tried first (default 1).
    #[serde(default)]
    pub load_steps: Option<Spanned<i64>>,
    /// modal: how many of the lowest modes to compute (default all on the dense path, 10 on
    /// the sparse path of large models).
    #[serde(default)]
    pub modes: Option<Spanned<i64>>,
    /// modal, and dynamic with linearize_at: the force elements (point_force, torque) that are
    /// the inputs of the state-space model written with the modes.
    #[serde(default)]
    pub inputs: Option<Vec<Name>>,
    /// dynamic: the time \[s\] of the state about which the run is linearized (modes and
    /// state-space matrices written with the run's outputs).
    #[serde(default)]
    pub linearize_at: Option<Num>,
    /// Number of steps (the grid has steps + 1 times).
    #[serde(default)]
    pub steps: Option<Spanned<i64>>,
    /// kinematic: output step \[s\] (alternative to steps); dynamic: the integration step \[s\]
    /// (generalized-α; DOPRI5 with fixed steps).
    #[serde(default)]
    pub dt: Option<Num>,
    /// dynamic: output step \[s\] (alternative to steps).
    #[serde(default)]
    pub output_dt: Option<Num>,
    /// dynamic: "dopri5" (default) or "generalized_alpha".
    #[serde(default)]
    pub integrator: Option<Name>,
    /// dynamic, dopri5: relative tolerance (default 1e-6).
    #[serde(default)]
    pub rtol: Option<Num>,
    /// dynamic, dopri5: absolute tolerance (default 1e-8).
    #[serde(default)]
    pub atol: Option<Num>,
    /// dynamic, dopri5: largest step \[s\].
    #[serde(default)]
    pub h_max: Option<Num>,
    /// dynamic, generalized_alpha: spectral radius at infinity ρ∞ ∈ [0, 1] (default 0.8).
    #[serde(default)]
    pub rho_inf: Option<Num>,
    /// dynamic, generalized_alpha: Newton tolerance (default 1e-10).
    #[serde(default)]
    pub newton_tolerance: Option<Num>,
    /// kinematic, inverse_dynamics: the position solves' tolerance on the scaled residual
    /// (default 1e-10); static kinds: the equilibrium's tolerance.
    #[serde(default)]
    pub tolerance: Option<Num>,
    /// kinematic, inverse_dynamics: the position solves' tolerance on the scaled residual
    /// (default 1e-10); `tolerance` is its older name, with the same meaning.
    #[serde(default)]
    pub position_tolerance: Option<Num>,
    /// static, quasi_static, modal: the equilibrium's tolerance (default 1e-10); `tolerance`
    /// is its older name, with the same meaning.
    #[serde(default)]
    pub equilibrium_tolerance: Option<Num>,
    /// What to write.
    #[serde(default)]
    pub outputs: Option<Spanned<OutputsSection>>,
    /// Plot format: "svg" (default) or "none".
    #[serde(default)]
    pub plots: Option<Name>,
    /// kinematic: "refuse" (default) or "hold": degrees of freedom no driver prescribes are
    /// held still by least change, as OndselSolver does.
    #[serde(default)]
    pub free_dof: Option<Name>,
    /// kinematic, inverse_dynamics: "refuse" (default) or "drop": an over-constrained model
    /// whose redundant joints disagree runs with the disagreeing rows dropped and left open.
    #[serde(default)]
    pub inconsistent_joints: Option<Name>,
}

/// `[analysis.outputs]`.
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct OutputsSection {
    /// "body.point": positions, velocities and accelerations (points.csv, point_velocities.csv,
    /// point_accelerations.csv). Given (even empty), only the listed groups are written.
    #[serde(default)]
    pub points: Option<Vec<Name>>,
    /// Joint names: joint coordinates (joints.csv).
    #[serde(default)]
    pub joints: Option<Vec<Name>>,
    /// Body names: position and Euler parameters (bodies.csv), ω (body_velocities.csv).
    #[serde(default)]
    pub bodies: Option<Vec<Name>>,
    /// dynamic: joint names whose reactions are written (reactions.csv); default all joints.
    #[serde(default)]
    pub reactions: Option<Vec<Name>>,
    /// dynamic and inverse dynamics: write energy.csv (default true).
    #[serde(default)]
    pub energy: Option<bool>,
    /// inverse dynamics: write mass_matrix.csv and bias_forces.csv (default false).
    #[serde(default)]
    pub joint_space: Option<bool>,
    /// inverse dynamics: "body.point" whose Jacobians are written (jacobians.csv).
    #[serde(default)]
    pub jacobians: Vec<Name>,
}

pub use crate::limits::{
    MAX_ARRAY_LEN, MAX_BODIES, MAX_ELEMENTS, MAX_EXPRESSION_LEN, MAX_FILE_BYTES, MAX_NESTING,
};

/// Parses the file; TOML syntax errors and type errors carry line and column, unknown keys get
/// the nearest valid key.
///
/// Hostile input is rejected before the TOML parser sees it when a cheap scan can tell (size
/// over [`MAX_FILE_BYTES`], brackets nested deeper than [`MAX_NESTING`], more element headers
/// than [`MAX_BODIES`] + 3 × [`MAX_ELEMENTS`]), and after parsing otherwise ([`MAX_BODIES`],
/// [`MAX_ELEMENTS`], [`MAX_ARRAY_LEN`]),
/// so time and memory stay bounded by the file size limit.
pub fn parse(src: &Source) -> Result<ModelFile, Error> {
    prescan(src)?;
    let located = |e: toml::de::Error| {
        let span = e.span().unwrap_or(0..0);
        let message = in_context(&src.text, span.start, improve_message(e.message()));
        src.error_at(span, message)
    };
    // Parsed once: the keys of the vocabulary sections are read off the document (with their
    // spans, for the table-driven key checks) before it is deserialized.
    let doc = toml::de::DeTable::parse(&src.text).map_err(located)?;
    let keys = crate::vocabulary::KeySpans::collect(doc.get_ref());
    let parameters = std::sync::Arc::new(crate::parameters::Parameters::read(
        src,
        doc.get_ref(),
        &src.set,
    )?);
    let mut file = crate::parameters::with_scope(parameters.clone(), || {
        ModelFile::deserialize(toml::de::Deserializer::from(doc))
    })
    .map_err(located)?;
    file.keys = keys;
    file.parameters = parameters;
    check_counts(src, &file)?;
    Ok(file)
}

/// Size, nesting depth and element-count limits checked on the raw text.
fn prescan(src: &Source) -> Result<(), Error> {
    let text = &src.text;
    if text.len() > MAX_FILE_BYTES {
        return Err(src.error(format!(
            "the model file is {} bytes long; at most {MAX_FILE_BYTES} bytes (128 MiB) are accepted",
            text.len()
        )));
    }
    // Bracket depth outside strings and comments (an upper bound on TOML nesting).
    let bytes = text.as_bytes();
    let (mut depth, mut k, mut headers, mut bodies) = (0usize, 0usize, 0usize, 0usize);
    let mut line_start = true;
    while k < bytes.len() {
        let c = bytes[k];
        match c {
            b'#' => {
                while k < bytes.len() && bytes[k] != b'\n' {
                    k += 1;
                }
                continue;
            }
            b'"' | b'\'' => {
                // Skip a string (basic strings honour backslash escapes; multi-line strings are
                // skipped as a run of one-line strings, which is enough for a bound).
                k += 1;
                while k < bytes.len() && bytes[k] != c && bytes[k] != b'\n' {
                    if c == b'"' && bytes[k] == b'\\' {
                        k += 1;
                    }
                    k += 1;
                }
            }
            b'[' | b'{' => {
                if line_start && c == b'[' && bytes.get(k + 1) == Some(&b'[') {
                    headers += 1;
                    bodies += usize::from(bytes[k..].starts_with(b"[[body]]"));
                }
                depth += 1;
                if depth > MAX_NESTING {
                    return Err(src.error_at(
                        k..k + 1,
                        format!(
                            "arrays or tables nested more than {MAX_NESTING} levels deep; a model file needs at most 3"
                        ),
                    ));
                }
            }
            b']' | b'}' => depth = depth.saturating_sub(1),
            _ => {}
        }
        if c == b'\n' {
            line_start = true;
        } else if !c.is_ascii_whitespace() {
            line_start = false;
        }
        k += 1;
    }
    if bodies > MAX_BODIES || headers - bodies > 8 * MAX_ELEMENTS {
        return Err(src.error(format!(
            "the model file declares {headers} [[...]] tables ({bodies} of them [[body]]); at \
             most {MAX_BODIES} bodies, \
             {MAX_ELEMENTS} joints, {MAX_ELEMENTS} curves, {MAX_ELEMENTS} cams, \
             {MAX_ELEMENTS} couplers, {MAX_ELEMENTS} drivers, {MAX_ELEMENTS} forces, \
             {MAX_ELEMENTS} limits and {MAX_ELEMENTS} frictions are accepted"
        )));
    }
    Ok(())
}

/// The name, count, limit and the span of the first element over the limit of one list.
fn count<T>(
    what: &'static str,
    list: &[Spanned<T>],
    max: usize,
) -> (&'static str, usize, usize, Option<std::ops::Range<usize>>) {
    (what, list.len(), max, list.get(max).map(Spanned::span))
}

/// Element counts and array lengths of a parsed file.
fn check_counts(src: &Source, file: &ModelFile) -> Result<(), Error> {
    let counts = [
        count("bodies", &file.body, MAX_BODIES),
        count("joints", &file.joint, MAX_ELEMENTS),
        count("curves", &file.curve, MAX_ELEMENTS),
        count("cams", &file.cam, MAX_ELEMENTS),
        count("surfaces", &file.surface, MAX_ELEMENTS),
        count("couplers", &file.coupler, MAX_ELEMENTS),
        count("drivers", &file.driver, MAX_ELEMENTS),
        count("forces", &file.force, MAX_ELEMENTS),
        count("limits", &file.limit, MAX_ELEMENTS),
        count("frictions", &file.friction, MAX_ELEMENTS),
        count("materials", &file.material, MAX_ELEMENTS),
        count("shapes", &file.shape, MAX_BODIES),
    ];
    for (what, n, max, first_extra) in counts {
        if n > max {
            return Err(src.error_at(
                first_extra.unwrap_or(0..0),
                format!("the model file declares {n} {what}; at most {max} are accepted"),
            ));
        }
    }
    let long = |v: &Option<Spanned<Vec<Num>>>, key: &str| -> Result<(), Error> {
        match v {
            Some(l) if l.get_ref().len() > MAX_ARRAY_LEN => Err(src.error_at(
                l.span(),
                format!(
                    "{key} has {} entries; at most {MAX_ARRAY_LEN} are accepted",
                    l.get_ref().len()
                ),
            )),
            _ => Ok(()),
        }
    };
    let function = |f: &FunctionSpec| -> Result<(), Error> {
        long(&f.coefficients, "function coefficients")?;
        long(&f.times, "spline times")?;
        long(&f.values, "spline values")?;
        match &f.text {
            Some(t) if t.get_ref().len() > MAX_EXPRESSION_LEN => Err(src.error_at(
                t.span(),
                format!(
                    "the expression is {} bytes long; at most {MAX_EXPRESSION_LEN} are accepted",
                    t.get_ref().len()
                ),
            )),
            _ => Ok(()),
        }
    };
    for d in &file.driver {
        let d = d.get_ref();
        if let Some(f) = &d.function {
            function(f.get_ref())?;
        }
        for list in [&d.translation, &d.rotation].into_iter().flatten() {
            // Their count (three) is checked when the driver is read.
            for f in list.get_ref().iter().take(3) {
                function(f.get_ref())?;
            }
        }
    }
    for f in &file.force {
        let f = f.get_ref();
        if let Some(a) = &f.actuator {
            function(a.get_ref())?;
        }
        if let Some(c) = &f.components {
            if c.get_ref().len() > MAX_ARRAY_LEN {
                return Err(src.error_at(
                    c.span(),
                    format!("components has more than {MAX_ARRAY_LEN} entries"),
                ));
            }
            for g in c.get_ref() {
                function(g.get_ref())?;
            }
        }
    }
    let cam_points = file.cam.iter().filter_map(|c| c.get_ref().points.as_ref());
    for p in (file
        .curve
        .iter()
        .filter_map(|c| c.get_ref().points.as_ref()))
    .chain(cam_points)
    {
        if p.get_ref().len() > MAX_ARRAY_LEN {
            return Err(src.error_at(
                p.span(),
                format!(
                    "points has {} entries; at most {MAX_ARRAY_LEN} are accepted",
                    p.get_ref().len()
                ),
            ));
        }
    }
    if let Some(a) = &file.analysis {
        if let Some(o) = &a.get_ref().outputs {
            let o = o.get_ref();
            let n = [&o.points, &o.joints, &o.bodies, &o.reactions]
                .iter()
                .map(|l| l.as_ref().map_or(0, Vec::len))
                .sum::<usize>();
            if n > MAX_ARRAY_LEN {
                return Err(src.error_at(
                    a.get_ref().outputs.as_ref().map_or(0..0, Spanned::span),
                    format!("[analysis.outputs] lists {n} entries; at most {MAX_ARRAY_LEN} are accepted"),
                ));
            }
        }
    }
    Ok(())
}

/// Adds what the parser's message leaves out, from the text at `at`: the key and table of a
/// duplicate key, the hint `[[body]]` for a `[body]` header, the key and range of an integer
/// too large for 64 bits.
fn in_context(text: &str, at: usize, message: String) -> String {
    let at = at.min(text.len());
    if message == "duplicate key" {
        let key = key_at(&text[at..]);
        let table = header_before(text, at);
        let first = table
            .as_ref()
            .and_then(|(_, start)| first_assignment(text, *start, at, &key))
            .map_or(String::new(), |line| {
                format!(" (first given at line {line})")
            });
        let table = table.map_or("the top level".to_string(), |(h, _)| h);
        return format!(
            "duplicate key \"{key}\" in {table}{first}; a key may appear once per table"
        );
    }
    if message.starts_with("invalid value: a table, expected an array") {
        for name in [
            "body", "joint", "curve", "cam", "coupler", "driver", "force", "limit", "friction",
        ] {
            if text[at..].starts_with(&format!("[{name}]")) {
                return format!(
                    "[{name}] declares a single table, but a model has a list of them: write \
                     [[{name}]] (one [[{name}]] table per {name})"
                );
            }
        }
    }
    if message.contains("as i128") || message.contains("as u64") {
        let line_start = text[..at].rfind('\n').map_or(0, |k| k + 1);
        let key = key_at(text[line_start..at].trim_start());
        let number = message.split('`').nth(1).unwrap_or("the number");
        return if key == "steps" {
            format!("steps = {number} is out of range: steps must be between 1 and 10000000")
        } else {
            format!("{key} = {number} is too large for an integer (64 bits); write it as a float")
        };
    }
    message
}

/// The bare key at the start of `s` (quotes removed).
fn key_at(s: &str) -> String {
    let end = s
        .find(|c: char| c.is_whitespace() || matches!(c, '=' | ',' | '}' | '.'))
        .unwrap_or(s.len());
    s[..end].trim_matches(|c| c == '"' || c == '\'').to_string()
}

/// The last table header (`[name]` or `[[name]]`, alone on its line) before `at`, with its
/// byte offset.
fn header_before(text: &str, at: usize) -> Option<(String, usize)> {
    let mut offset = 0;
    let mut found = None;
    for line in text[..at].split_inclusive('\n') {
        let t = line.split('#').next().unwrap_or("").trim();
        let inner = t.trim_start_matches('[').trim_end_matches(']');
        let is_header = t.starts_with('[')
            && t.ends_with(']')
            && !inner.is_empty()
            && inner
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'));
        if is_header {
            found = Some((t.to_string(), offset));
        }
        offset += line.len();
    }
    found
}

/// The line (from 1) of the first `key =` between `from` and `to`.
fn first_assignment(text: &str, from: usize, to: usize, key: &str) -> Option<usize> {
    let region = &text[from..to];
    let mut k = 0;
    while let Some(pos) = region[k..].find(key) {
        let start = k + pos;
        let before_ok = region[..start]
            .chars()
            .next_back()
            .is_none_or(|c| c.is_whitespace() || matches!(c, '{' | ','));
        let after = region[start + key.len()..].trim_start();
        if before_ok && after.starts_with('=') {
            return Some(text[..from + start].matches('\n').count() + 1);
        }
        k = start + key.len();
    }
    None
}

/// Rewrites serde's "unknown field `x`, expected one of `a`, `b`" into a suggestion.
fn improve_message(raw: &str) -> String {
    let raw = raw.trim_end();
    if let Some(rest) = raw.strip_prefix("unknown field `") {
        if let Some((field, tail)) = rest.split_once('`') {
            let expected: Vec<&str> = tail.split('`').skip(1).step_by(2).collect();
            let hint = did_you_mean(field, expected.iter().copied());
            let valid = if expected.is_empty() {
                "this table takes no keys".to_string()
            } else {
                format!("valid keys here: {}", expected.join(", "))
            };
            return format!("unknown key \"{field}\"{hint} ({valid})");
        }
    }
    if let Some(rest) = raw.strip_prefix("missing field `") {
        if let Some((field, _)) = rest.split_once('`') {
            return format!("missing required key \"{field}\"");
        }
    }
    let mut m = raw.replace('\n', " ");
    // serde names Rust types: say what the file needs instead.
    for (rust, plain) in [
        ("expected f64", "expected a number"),
        ("expected f32", "expected a number"),
        ("expected usize", "expected a whole number ≥ 0"),
        ("expected u64", "expected a whole number ≥ 0"),
        ("expected u32", "expected a whole number ≥ 0"),
        ("expected i64", "expected a whole number"),
        ("expected a boolean", "expected true or false"),
        ("invalid type: string", "invalid value: the string"),
        ("invalid type: integer", "invalid value: the whole number"),
        ("invalid type: floating point", "invalid value: the number"),
        ("invalid type: boolean", "invalid value: the boolean"),
        ("invalid type: sequence", "invalid value: an array"),
        ("invalid type: map", "invalid value: a table"),
        ("expected a sequence", "expected an array [...]"),
        ("expected a map", "expected a table { ... }"),
    ] {
        m = m.replace(rust, plain);
    }
    if let Some(first) = m.get(..1) {
        m = first.to_lowercase() + &m[1..];
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rust_type_names_are_not_shown() {
        let m = improve_message("invalid type: string \"heavy\", expected f64");
        assert_eq!(m, "invalid value: the string \"heavy\", expected a number");
    }

    #[test]
    fn unknown_field_message() {
        let m = improve_message("unknown field `mas`, expected one of `name`, `mass`, `inertia`");
        assert!(m.contains("did you mean \"mass\""), "{m}");
    }
}
