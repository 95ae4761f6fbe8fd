"""Under-driven ASMT assemblies and OndselSolver's solutions of them (issue 53, item 1).

OndselSolver runs an assembly with fewer motions than degrees of freedom: the free parts hold
still by a least-change solve (the mass-weighted metric of `Part::fillqsuWeights`) from the
drawn pose at tstart and from each output time to the next. This script writes small assemblies
of that kind and solves each with pyondsel 0.0.3 (OndselSolver's C++ code, in-process), storing

    crates/asmt/tests/data/underdriven/<name>.asmt          the assembly (written here)
    crates/asmt/tests/data/underdriven/<name>.solved.asmt   OndselSolver's solution

which `crates/asmt/tests/ondsel.rs` compares with cardan's `free_dof = "hold"` runs (positions
and rotations to 1e-9). Run from the repository root with the peers venv
(`cargo xtask bench --peers` creates it):

    target/peers-venv/bin/python bench/peers/asmt_underdriven.py

The assemblies are SI, written by this script; masses and inertias differ between parts so that
the weights matter, and the drawn poses are off their assembled ones so that the first solve
moves them.
"""

import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))
from asmt_refs import IDENTITY as I3, assembly as write_assembly, joint, motion, part as write_part, rot_axis  # noqa: E402

OUT = os.path.join(os.path.dirname(__file__), "..", "..", "crates", "asmt", "tests", "data", "underdriven")
GRAVITY = (0.0, 0.0, -9.81)


def rot(axis, angle):
    n = math.sqrt(sum(a * a for a in axis))
    return rot_axis(tuple(a / n for a in axis), angle)


def part(name, pos, r, m, j, markers, cm=(0, 0, 0)):
    """A part with mass m and principal moments j; markers (name, position[, rotation])."""
    marks = [(mk[0], mk[1], mk[2] if len(mk) > 2 else I3) for mk in markers]
    return write_part(name, pos, r, marks, mass=m, inertias=j, cm=cm)


def rotation_motion(name, joint_path, expr):
    return motion(name, joint_path, expr)


def assembly(name, ground, parts, joints, motions, tend=1.0, hout=0.1):
    marks = [(mk[0], mk[1], mk[2] if len(mk) > 2 else I3) for mk in ground]
    text = write_assembly("cardan bench/peers/asmt_underdriven.py", marks, parts, joints, motions,
                          tend=tend, hout=hout, gravity=GRAVITY)
    return text.replace("\tName\n\t\tAssembly1\n", f"\tName\n\t\t{name}\n", 1)


def crane():
    """A driven jib (revolute about z) with a hook hanging from its tip by a spherical joint:
    three free DOF (the hook's rotations), the hook dragged along as little as its weights allow."""
    jib = part("Jib", (0, 0, 0), I3, 2.0, (1, 1, 1), [("O", (0, 0, 0)), ("Tip", (1, 0, 0))])
    hook = part("Hook", (1.5, 0, 0.02), rot((0, 0, 1), 0.05), 1.0, (0.1, 0.2, 0.3), [("M", (-0.5, 0, 0))])
    joints = [joint("RevoluteJoint", "Slew", "/Crane/G", "/Crane/Jib/O"), joint("SphericalJoint", "Ball", "/Crane/Jib/Tip", "/Crane/Hook/M")]
    motions = [rotation_motion("Slewing", "/Crane/Slew", "0.5*pi*time")]
    return assembly("Crane", [("G", (0, 0, 0))], [jib, hook], joints, motions)


def rssr():
    """A spatial RSSR four-bar whose coupler is a body with a ball at each end: one motion
    (the crank), two DOF (the coupler's spin about its own axis is free and held)."""
    a, b = 0.1, 0.2
    crank = part("Crank", (0, 0, 0), I3, 0.5, (1e-4, 2e-4, 2e-4), [("O", (0, 0, 0)), ("P", (a, 0, 0))], cm=(0.05, 0, 0))
    # Rocker pivot G2 = (0.3, 0.15, 0.1), rocker along its x axis (turned about y), tip Q at b.
    psi = 1.9224062931447934
    rr = rot((0, 1, 0), -psi)
    q = (0.3 + b * math.cos(-psi), 0.15, 0.1 - b * math.sin(-psi))
    rocker = part("Rocker", (0.3, 0.15, 0.1), rr, 0.8, (3e-4, 1e-3, 1e-3), [("G", (0, 0, 0), rot((1, 0, 0), math.pi / 2)), ("Q", (b, 0, 0))])
    # The coupler from P = (a, 0, 0) to Q, drawn 3 mm off and turned 0.2 rad about its axis.
    mid = ((a + q[0]) / 2 + 0.003, q[1] / 2, q[2] / 2)
    half = ((q[0] - a) / 2, q[1] / 2, q[2] / 2)
    L = math.sqrt(sum(h * h for h in half))
    coupler = part("Coupler", mid, rot(tuple(h / L for h in half), 0.2), 0.3, (1e-4, 5e-3, 5e-3),
                   [("P", (-half[0], -half[1], -half[2])), ("Q", half)])
    ground = [("O", (0, 0, 0)), ("G2", (0.3, 0.15, 0.1), rot((1, 0, 0), math.pi / 2))]
    joints = [
        joint("RevoluteJoint", "CrankPivot", "/RSSR/O", "/RSSR/Crank/O"),
        joint("RevoluteJoint", "RockerPivot", "/RSSR/G2", "/RSSR/Rocker/G"),
        joint("SphericalJoint", "BallP", "/RSSR/Crank/P", "/RSSR/Coupler/P"),
        joint("SphericalJoint", "BallQ", "/RSSR/Rocker/Q", "/RSSR/Coupler/Q"),
    ]
    motions = [rotation_motion("Motor", "/RSSR/CrankPivot", "2*pi*time")]
    return assembly("RSSR", ground, [crank, rocker, coupler], joints, motions, tend=1.0, hout=0.05)


def pendulum():
    """A pendulum on a revolute joint and no motion at all (FreeCAD's gyroscope or pendulum
    before a motion is added), drawn 5 mm and 0.1 rad off its joint: assembled by least change,
    then held still."""
    bob = part("Bob", (0.005, 0.0, -0.5), rot((0.3, 0.9, 0.3162277660168379), 0.1), 1.5, (0.02, 0.03, 0.015), [("Pin", (0, 0, 0.5), rot((1, 0, 0), math.pi / 2))], cm=(0, 0, -0.05))
    joints = [joint("RevoluteJoint", "Hinge", "/Pendulum/G", "/Pendulum/Bob/Pin")]
    return assembly("Pendulum", [("G", (0, 0, 0), rot((1, 0, 0), math.pi / 2))], [bob], joints, [], tend=0.5, hout=0.1)


CASES = {"crane": crane, "rssr_spin": rssr, "pendulum_free": pendulum}


def main():
    from pyondsel.solve_raw import solve_asmt_raw

    os.makedirs(OUT, exist_ok=True)
    for name, make in CASES.items():
        text = make()
        solved = solve_asmt_raw(text)
        with open(os.path.join(OUT, f"{name}.asmt"), "w", encoding="utf-8") as f:
            f.write(text)
        with open(os.path.join(OUT, f"{name}.solved.asmt"), "w", encoding="utf-8") as f:
            f.write(solved)
        frames = sum(1 for line in solved.splitlines() if line.startswith("Time"))
        print(f"{name}: written ({len(solved)} characters, {frames} Time rows)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
