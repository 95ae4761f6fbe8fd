"""Small ASMT assemblies for the joint kinds the ten testapp files do not use, and OndselSolver's
solutions of them (crates/asmt/tests/small.rs compares cardan with these).

  python bench/peers/asmt_refs.py OUT_DIR      # writes OUT_DIR/<name>.asmt and <name>.solved.asmt

Each model is written here as text in OndselSolver's layout (TAB indentation), solved once by
pyondsel 0.0.3 (`pyondsel.solve_raw.solve_asmt_raw`, OndselSolver's C++ code) and stored with its
solution. Rerun after changing a model; the references are committed as test data.

- angle: shaft A turns about global z (driven, angle pi/2 + 0.3 sin 2 pi t), shaft B about global
  x; an AngleJoint holds A's marker z (perpendicular to z) at 60 degrees from B's marker z, so
  sin(phi) cos(psi) = cos 60 deg fixes B (never near parallel axes, where OndselSolver's row
  loses rank).
- cv: a constant-velocity joint between shaft A (revolute about global x, driven 2 pi t) and
  shaft B (revolute about an axis 30 degrees from x in the xy-plane), both axes through the
  origin, the joint at the origin (its point rows are redundant with the revolutes: 3 rows).
- screw_cyl: a screw on a single cylindrical joint: a part on a cylindrical joint along global z,
  turned 2 pi t by a rotational motion, advancing 0.25 per turn.
"""

import math
import os
import sys

IDENTITY = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def rot_x(a):
    c, s = math.cos(a), math.sin(a)
    return ((1.0, 0.0, 0.0), (0.0, c, -s), (0.0, s, c))


def rot_z(a):
    c, s = math.cos(a), math.sin(a)
    return ((c, -s, 0.0), (s, c, 0.0), (0.0, 0.0, 1.0))


def rot_axis(u, a):
    """Rotation by a about the unit vector u (Rodrigues)."""
    c, s = math.cos(a), math.sin(a)
    x, y, z = u
    return ((c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s),
            (y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s),
            (z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)))


def mul(m, v):
    return tuple(sum(m[i][k] * v[k] for k in range(3)) for i in range(3))


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def mat(rows):
    """Rotation matrix with the given columns (x, y, z axes)."""
    x, y, z = rows
    return tuple((x[i], y[i], z[i]) for i in range(3))


def fmt(v):
    return "\t".join(repr(float(x)) for x in v)


def marker(name, pos, rot, depth):
    t = "\t" * depth
    out = [f"{t}Marker", f"{t}\tName", f"{t}\t\t{name}", f"{t}\tPosition3D", f"{t}\t\t{fmt(pos)}",
           f"{t}\tRotationMatrix"]
    out += [f"{t}\t\t{fmt(r)}" for r in rot]
    return out


def refpoint(markers, depth):
    t = "\t" * depth
    out = [f"{t}RefPoint", f"{t}\tPosition3D", f"{t}\t\t{fmt((0, 0, 0))}", f"{t}\tRotationMatrix"]
    out += [f"{t}\t\t{fmt(r)}" for r in IDENTITY]
    out.append(f"{t}\tMarkers")
    for m in markers:
        out += marker(*m, depth + 2)
    return out


def part(name, pos, rot, markers, omega=(0.0, 0.0, 0.0), mass=1.0, inertias=(1, 1, 1),
         cm=(0, 0, 0), cm_rot=IDENTITY):
    """A part; `mass`, `inertias` (principal moments), `cm` and `cm_rot` its mass marker."""
    out = ["\t\tPart", "\t\t\tName", f"\t\t\t\t{name}", "\t\t\tPosition3D", f"\t\t\t\t{fmt(pos)}",
           "\t\t\tRotationMatrix"]
    out += [f"\t\t\t\t{fmt(r)}" for r in rot]
    out += ["\t\t\tVelocity3D", f"\t\t\t\t{fmt((0, 0, 0))}", "\t\t\tOmega3D", f"\t\t\t\t{fmt(omega)}",
            "\t\t\tFeatureOrder", "\t\t\tPrincipalMassMarker", "\t\t\t\tName", "\t\t\t\t\tMassMarker",
            "\t\t\t\tPosition3D", f"\t\t\t\t\t{fmt(cm)}", "\t\t\t\tRotationMatrix"]
    out += [f"\t\t\t\t\t{fmt(r)}" for r in cm_rot]
    out += ["\t\t\t\tMass", f"\t\t\t\t\t{float(mass)!r}", "\t\t\t\tMomentOfInertias", f"\t\t\t\t\t{fmt(inertias)}",
            "\t\t\t\tDensity", "\t\t\t\t\t1.0", "\t\t\tRefPoints"]
    out += refpoint(markers, 4)
    out += ["\t\t\tRefCurves", "\t\t\tRefSurfaces"]
    return out


def joint(kind, name, mi, mj, extra=()):
    out = [f"\t\t\t{kind}", "\t\t\t\tName", f"\t\t\t\t\t{name}", "\t\t\t\tMarkerI", f"\t\t\t\t\t{mi}",
           "\t\t\t\tMarkerJ", f"\t\t\t\t\t{mj}"]
    for k, v in extra:
        out += [f"\t\t\t\t{k}", f"\t\t\t\t\t{v}"]
    return out


def motion(name, joint_path, expr):
    return ["\t\t\tRotationalMotion", "\t\t\t\tName", f"\t\t\t\t\t{name}", "\t\t\t\tMotionJoint",
            f"\t\t\t\t\t{joint_path}", "\t\t\t\tRotationZ", f"\t\t\t\t\t{expr}"]


def assembly(notes, ground_markers, parts, joints, motions, tend=1.0, hout=0.05, gravity=(0, 0, 0)):
    # The Smalltalk header and AnimationParameters, as the testapp files (OndselSolver's C++ reader
    # crashes on this text with the header "OndselSolver" and no AnimationParameters).
    out = ["freeCAD: 3D CAD with Motion Simulation  by  askoh.com", "Assembly", "\tNotes", f"\t\t{notes}", "\tName", "\t\tAssembly1",
           "\tPosition3D", f"\t\t{fmt((0, 0, 0))}", "\tRotationMatrix"]
    out += [f"\t\t{fmt(r)}" for r in IDENTITY]
    out += ["\tVelocity3D", f"\t\t{fmt((0, 0, 0))}", "\tOmega3D", f"\t\t{fmt((0, 0, 0))}",
            "\tRefPoints"]
    out += refpoint(ground_markers, 2)
    out += ["\tRefCurves", "\tRefSurfaces", "\tParts"]
    for p in parts:
        out += p
    out += ["\tKinematicIJs", "\tConstraintSets", "\t\tJoints"]
    for j in joints:
        out += j
    out.append("\t\tMotions")
    for m in motions:
        out += m
    out += ["\t\tGeneralConstraintSets", "\tForceTorques", "\tConstantGravity",
            f"\t\t{fmt(gravity)}", "\tSimulationParameters", "\t\ttstart", "\t\t\t0.0", "\t\ttend",
            f"\t\t\t{tend!r}", "\t\thmin", "\t\t\t1e-09", "\t\thmax", "\t\t\t1.0", "\t\thout",
            f"\t\t\t{hout!r}", "\t\terrorTol", "\t\t\t1e-06", "\tAnimationParameters",
            "\t\tnframe", f"\t\t\t{round(tend / hout) + 1}", "\t\ticurrent", "\t\t\t1",
            "\t\tistart", "\t\t\t1", "\t\tiend", f"\t\t\t{round(tend / hout) + 1}",
            "\t\tisForward", "\t\t\ttrue", "\t\tframesPerSecond", "\t\t\t30"]
    return "\n".join(out) + "\n"


def angle_model():
    phi0 = math.pi / 2
    # A: marker z along A's x axis, i.e. (cos phi, sin phi, 0) after turning phi about z.
    a_rot = rot_z(phi0)
    # B: marker z = B's y axis; turned psi about x: (0, cos psi, sin psi); cos psi = 0.5 / sin phi.
    psi0 = math.acos(0.5 / math.sin(phi0))
    b_rot = rot_x(psi0)
    z_along_x = mat(((0, 1, 0), (0, 0, 1), (1, 0, 0)))   # marker x = y, y = z, z = x
    z_along_y = mat(((0, 0, 1), (1, 0, 0), (0, 1, 0)))   # marker x = z, y = x, z = y
    ground = [("Marker1", (0, 0, 0), IDENTITY), ("Marker2", (0, 0, 0), z_along_x)]
    parts = [
        part("ShaftA", (0, 0, 0), a_rot, [("Axis", (0, 0, 0), IDENTITY),
                                           ("Arm", (0, 0, 0), z_along_x)]),
        part("ShaftB", (0, 0, 0), b_rot, [("Axis", (0, 0, 0), z_along_x),
                                           ("Arm", (0, 0, 0), z_along_y)]),
    ]
    joints = [
        joint("RevoluteJoint", "RevA", "/Assembly1/Marker1", "/Assembly1/ShaftA/Axis"),
        joint("RevoluteJoint", "RevB", "/Assembly1/Marker2", "/Assembly1/ShaftB/Axis"),
        joint("AngleJoint", "Angle", "/Assembly1/ShaftA/Arm", "/Assembly1/ShaftB/Arm",
              [("theIzJz", repr(math.pi / 3))]),
    ]
    motions = [motion("Drive", "/Assembly1/RevA", "0.5*pi + 0.3*sin(2.0*pi*time)")]
    return assembly("angle joint between two shafts", ground, parts, joints, motions)


def cv_model():
    beta = math.radians(30.0)
    b_axis = (math.cos(beta), math.sin(beta), 0.0)
    z_along_x = mat(((0, 1, 0), (0, 0, 1), (1, 0, 0)))
    # B's axis marker: z along b, x = global z, y = z cross x.
    zb = b_axis
    xb = (0.0, 0.0, 1.0)
    yb = (zb[1] * xb[2] - zb[2] * xb[1], zb[2] * xb[0] - zb[0] * xb[2], zb[0] * xb[1] - zb[1] * xb[0])
    along_b = mat((xb, yb, zb))
    # OndselSolver's CV markers face each other: I's z along A's axis (+x), J's z along -b.
    # J's marker (fixed in B) faces I's: z_J = -b, x_J = global z, y_J = z_J x x_J. B is then
    # turned about b by gamma so that OndselSolver's row x_I.y_J + y_I.x_J = 0 holds as drawn.
    facing = mat((xb, tuple(-c for c in yb), tuple(-c for c in zb)))
    x_i, y_i = (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)

    def row(g):
        r = rot_axis(zb, g)
        xj = mul(r, xb)
        yj = mul(r, tuple(-c for c in yb))
        return dot(x_i, yj) + dot(y_i, xj)

    # The root nearest gamma = 0: scan outwards for a sign change, then bisect.
    lo, hi = None, None
    for k in range(1, 64):
        for a, b in ((0.05 * (k - 1), 0.05 * k), (-0.05 * k, -0.05 * (k - 1))):
            if lo is None and row(a) * row(b) <= 0:
                lo, hi = a, b
        if lo is not None:
            break
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if row(lo) * row(mid) <= 0:
            hi = mid
        else:
            lo = mid
    b_rot = rot_axis(zb, 0.5 * (lo + hi))
    ground = [("Marker1", (0, 0, 0), z_along_x), ("Marker2", (0, 0, 0), along_b)]
    parts = [
        part("ShaftA", (0, 0, 0), IDENTITY, [("Axis", (0, 0, 0), z_along_x),
                                             ("Joint", (0, 0, 0), z_along_x)]),
        part("ShaftB", (0, 0, 0), b_rot, [("Axis", (0, 0, 0), along_b),
                                             ("Joint", (0, 0, 0), facing)]),
    ]
    joints = [
        joint("RevoluteJoint", "RevA", "/Assembly1/Marker1", "/Assembly1/ShaftA/Axis"),
        joint("RevoluteJoint", "RevB", "/Assembly1/Marker2", "/Assembly1/ShaftB/Axis"),
        joint("ConstantVelocityJoint", "CV", "/Assembly1/ShaftA/Joint", "/Assembly1/ShaftB/Joint"),
    ]
    motions = [motion("Drive", "/Assembly1/RevA", "2.0*pi*time")]
    return assembly("constant-velocity joint between two shafts", ground, parts, joints, motions)


def bent_cv_model():
    """The cv model with shaft B on a cylindrical joint whose axis passes 0.24 from the joint
    point (issue 53, item 2): over-constrained and inconsistent as drawn. OndselSolver drops one
    cylindrical row as redundant and runs with it violated by 0.24."""
    text = cv_model()
    # Shaft B's ground marker moved 0.24 along global z, its joint made cylindrical.
    text = text.replace("\t\t\tRevoluteJoint\n\t\t\t\tName\n\t\t\t\t\tRevB",
                        "\t\t\tCylindricalJoint\n\t\t\t\tName\n\t\t\t\t\tCylB")
    marker2 = "\t\t\t\t\t\tMarker2\n\t\t\t\t\tPosition3D\n\t\t\t\t\t\t0.0\t0.0\t0.0"
    assert marker2 in text and "CylB" in text
    return text.replace(marker2, marker2[:-3] + "0.24").replace(
        "constant-velocity joint between two shafts", "bent two-shaft drive, inconsistent as drawn")


def screw_cyl_model():
    ground = [("Marker1", (0, 0, 0), IDENTITY)]
    parts = [part("Nut", (0.1, 0.0, 0.2), IDENTITY, [("Axis", (-0.1, 0.0, 0.0), IDENTITY)])]
    joints = [
        joint("CylindricalJoint", "Cyl", "/Assembly1/Marker1", "/Assembly1/Nut/Axis"),
        joint("ScrewJoint", "Screw", "/Assembly1/Marker1", "/Assembly1/Nut/Axis",
              [("pitch", "0.25")]),
    ]
    motions = [motion("Drive", "/Assembly1/Cyl", "2.0*pi*time")]
    return assembly("screw on a single cylindrical joint", ground, parts, joints, motions)


MODELS = {"angle": angle_model, "cv": cv_model, "screw_cyl": screw_cyl_model, "bent_cv": bent_cv_model}


def main(out):
    # In a worker process: OndselSolver crashes (SIGSEGV) on some ill-posed models.
    from pyondsel.solve import solve_asmt as solve_asmt_raw

    os.makedirs(out, exist_ok=True)
    for name, build in MODELS.items():
        if len(sys.argv) > 2 and name not in sys.argv[2:]:
            continue
        text = build()
        with open(os.path.join(out, f"{name}.asmt"), "w", encoding="utf-8") as f:
            f.write(text)
        solved = solve_asmt_raw(text)
        with open(os.path.join(out, f"{name}.solved.asmt"), "w", encoding="utf-8") as f:
            f.write(solved)
        times = next(l for l in solved.splitlines() if l.startswith("Time\t"))
        print(name, "frames", sum(1 for c in times.split("\t")[1:] if c.strip() not in ("", "Input")))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "crates/asmt/tests/data/small")
