"""Every joint kind of the ASMT import, drawn far from its assembled pose, solved by OndselSolver
(issue 53, item 2: the globalization survey).

Each case is a ground marker and one part joined by one joint of the kind, the part drawn half
a metre away and turned 30°, 60° or 90° about a skew axis, with no motion: OndselSolver assembles
it by its least-change solve, as cardan does with `free_dof = "hold"` (an ASMT file's default).
Writes every case as crates/asmt/tests/data/far/<kind>_<angle>.asmt and, where OndselSolver
solves it (a TimeSeries with frames), its solution as <kind>_<angle>.solved.asmt; the cases it
does not solve are listed in crates/asmt/tests/data/far/README.md.
`crates/asmt/tests/ondsel.rs` runs cardan on each and compares the poses (1e-9).

    target/peers-venv/bin/python bench/peers/asmt_far.py
"""

import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))
from asmt_refs import IDENTITY, assembly, joint, part, rot_axis  # noqa: E402

OUT = os.path.join(os.path.dirname(__file__), "..", "..", "crates", "asmt", "tests", "data", "far")

# (ASMT kind, extra number fields): every kind the import maps to a cardan joint.
KINDS = [
    ("FixedJoint", ()),
    ("RevoluteJoint", ()),
    ("CylindricalJoint", ()),
    ("TranslationalJoint", ()),
    ("SphericalJoint", ()),
    ("UniversalJoint", ()),
    ("PlanarJoint", ()),
    ("SphSphJoint", (("distanceIJ", "0.3"),)),
    ("PointInPlaneJoint", ()),
    ("PointInLineJoint", ()),
    ("LineInPlaneJoint", ()),
    ("NoRotationJoint", ()),
    ("ParallelAxesJoint", ()),
    ("PerpendicularJoint", ()),
    ("AngleJoint", (("theIzJz", "1.0"),)),
    ("ConstantVelocityJoint", ()),
    ("CylSphJoint", (("distanceIJ", "0.3"),)),
    ("RevCylJoint", (("distanceIJ", "0.3"),)),
    ("RevRevJoint", (("distanceIJ", "0.3"),)),
]

ANGLES = (30, 60, 90)
AXIS = (0.48, 0.6, 0.64)  # a unit skew axis


def case(kind, extra, degrees):
    r = rot_axis(AXIS, math.radians(degrees))
    link = part("Link", (0.5, 0.3, -0.2), r, [("M", (0.4, 0.0, 0.0), IDENTITY)],
                mass=2.0, inertias=(0.1, 0.2, 0.25), cm=(0.2, 0.0, 0.0))
    joints = [joint(kind, "J", "/Assembly1/G", "/Assembly1/Link/M", extra)]
    return assembly(f"{kind} drawn {degrees} degrees and half a metre off", [("G", (0, 0, 0), IDENTITY)],
                    [link], joints, [], tend=0.1, hout=0.1)


def main():
    from pyondsel.solve import solve_asmt

    os.makedirs(OUT, exist_ok=True)
    failed = []
    for kind, extra in KINDS:
        for degrees in ANGLES:
            name = f"{kind[:-5].lower()}_{degrees}"
            text = case(kind, extra, degrees)
            with open(os.path.join(OUT, f"{name}.asmt"), "w", encoding="utf-8") as f:
                f.write(text)
            try:
                solved = solve_asmt(text)
            except Exception as e:  # OndselSolver's failures are data here
                failed.append((name, str(e).splitlines()[0][:120]))
                continue
            times = next(line for line in solved.splitlines() if line.startswith("Time\t"))
            if not [c for c in times.split("\t")[1:] if c.strip() not in ("", "Input")]:
                failed.append((name, "no frames: the TimeSeries is empty (the assembly failed)"))
                continue
            with open(os.path.join(OUT, f"{name}.solved.asmt"), "w", encoding="utf-8") as f:
                f.write(solved)
            print(name, "solved")
    with open(os.path.join(OUT, "README.md"), "w", encoding="utf-8") as f:
        f.write("# Joint kinds drawn far from their assembled pose\n\n"
                "Written and solved by OndselSolver (pyondsel 0.0.3) with `bench/peers/asmt_far.py`; "
                "`crates/asmt/tests/ondsel.rs` (`every_joint_kind_drawn_far_assembles`) runs cardan on each.\n\n")
        f.write("Cases OndselSolver does not solve (no `.solved.asmt`):\n\n" if failed else "OndselSolver solves every case.\n")
        for name, why in failed:
            f.write(f"- `{name}`: {why}\n")
    print("failed:", failed)


if __name__ == "__main__":
    main()
