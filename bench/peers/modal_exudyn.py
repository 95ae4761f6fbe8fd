"""Exudyn side of the modal peer check (`cardan-bench --modal-peer PYTHON`, issue 26).

Reads a model description on stdin (written by crates/bench/src/modal_peer.rs, the one source
of the numbers), builds the same mechanism in Exudyn as an ObjectKinematicTree (minimal
coordinates: one angle per revolute joint) with gravity and linear springs, checks that its
drawn pose is a static equilibrium (mbs.SolveStatic) and calls mbs.ComputeODE2Eigenvalues on it.
Prints `RESULT version=<exudyn version>`, `RESULT com=<link> x y z` (each link's centre of mass
as Exudyn places it, to check the frames) and one line `RESULT f=<Hz>` per eigenfrequency,
ascending.

Why a kinematic tree and not Exudyn's rigid bodies with joints (redundant coordinates and
algebraic constraints): ComputeODE2Eigenvalues' stiffness is the Jacobian of the ODE2
right-hand side only, without the geometric stiffness of the constraint forces (the term
d(C_q^T lambda)/dq): a pendulum held by a spherical joint under gravity comes out with zero
frequency there. In minimal coordinates gravity's stiffness is part of that Jacobian.

Model lines (SI units, global frame at the drawn pose):

    gravity gx gy gz
    link NAME PARENT m cx cy cz Jxx Jyy Jzz Jxy Jxz Jyz px py pz ax ay az
        (a rigid link joined to PARENT, an earlier link or "ground", by a revolute joint at the
         point p about the axis a; c its centre of mass, J its inertia about c)
    spring BODY_I BODY_J ax ay az bx by bz k   (ends a on i, b on j; free length |b - a|)

Exudyn's stiffness here is a forward difference of the tree's forces (step: relativeEpsilon
1e-7 times minimumCoordinateSize 0.01 at these zero joint angles), so its frequencies carry an
error of order 1e-8 relative that is linear in the step: with steps of 1e-5, 1e-6 and 1e-7 they
move away from cardan's by 7e-6, 7e-7 and 7e-8 relative, i.e. they converge to cardan's as the
step shrinks (the defaults are kept here).

Requires scipy (ComputeODE2Eigenvalues imports it).
"""

import sys

import numpy as np
import exudyn as exu
from exudyn.itemInterface import (
    MarkerBodyPosition,
    MarkerKinematicTreeRigid,
    NodeGenericODE2,
    ObjectConnectorSpringDamper,
    ObjectGround,
    ObjectKinematicTree,
)


def axis_frame(a):
    """A rotation matrix whose third column is the unit vector along a."""
    z = np.asarray(a, dtype=float)
    z = z / np.linalg.norm(z)
    t = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = t - z * (t @ z)
    x = x / np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def build(lines):
    """The Exudyn MainSystem of the model lines (module docs), the tree, the link names."""
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddObject(ObjectGround())
    gravity = [0.0, 0.0, 0.0]
    links = []
    springs = []
    for line in lines:
        w = line.split()
        if not w:
            continue
        if w[0] == "gravity":
            gravity = [float(x) for x in w[1:4]]
        elif w[0] == "link":
            v = [float(x) for x in w[3:]]
            jxx, jyy, jzz, jxy, jxz, jyz = v[4:10]
            links.append(
                {
                    "name": w[1],
                    "parent": w[2],
                    "m": v[0],
                    "c": np.array(v[1:4]),
                    "J": np.array([[jxx, jxy, jxz], [jxy, jyy, jyz], [jxz, jyz, jzz]]),
                    "p": np.array(v[10:13]),
                    "R": axis_frame(v[13:16]),
                }
            )
        elif w[0] == "spring":
            springs.append(w)
        else:
            raise ValueError(f"unknown model line: {line}")
    index = {l["name"]: i for i, l in enumerate(links)}
    parents, transforms, offsets, inertias, coms, masses = [], [], [], [], [], []
    for l in links:
        if l["parent"] == "ground":
            parents.append(-1)
            rp, pp = np.eye(3), np.zeros(3)
        else:
            k = index[l["parent"]]
            parents.append(k)
            rp, pp = links[k]["R"], links[k]["p"]
        # Joint frame: origin p, axes R (its z the joint axis), relative to the parent's.
        transforms.append(rp.T @ l["R"])
        offsets.append(rp.T @ (l["p"] - pp))
        coms.append(l["R"].T @ (l["c"] - l["p"]))
        inertias.append(l["R"].T @ l["J"] @ l["R"])
        masses.append(l["m"])
    n = len(links)
    node = mbs.AddNode(
        NodeGenericODE2(
            referenceCoordinates=[0.0] * n,
            initialCoordinates=[0.0] * n,
            initialCoordinates_t=[0.0] * n,
            numberOfODE2Coordinates=n,
        )
    )
    tree = mbs.AddObject(
        ObjectKinematicTree(
            nodeNumber=node,
            jointTypes=[exu.JointType.RevoluteZ] * n,
            linkParents=parents,
            jointTransformations=exu.Matrix3DList(transforms),
            jointOffsets=exu.Vector3DList(offsets),
            linkInertiasCOM=exu.Matrix3DList(inertias),
            linkCOMs=exu.Vector3DList(coms),
            linkMasses=masses,
            gravity=gravity,
        )
    )

    def marker(body, x):
        if body == "ground":
            return mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground, localPosition=list(x)))
        l = links[index[body]]
        return mbs.AddMarker(
            MarkerKinematicTreeRigid(
                objectNumber=tree,
                linkNumber=index[body],
                localPosition=list(l["R"].T @ (x - l["p"])),
            )
        )

    for w in springs:
        a = np.array([float(x) for x in w[3:6]])
        b = np.array([float(x) for x in w[6:9]])
        mbs.AddObject(
            ObjectConnectorSpringDamper(
                markerNumbers=[marker(w[1], a), marker(w[2], b)],
                referenceLength=float(np.linalg.norm(b - a)),
                stiffness=float(w[9]),
            )
        )
    com_markers = [(l["name"], marker(l["name"], l["c"])) for l in links]
    mbs.Assemble()
    return mbs, com_markers


def main():
    mbs, com_markers = build(sys.stdin.read().splitlines())
    settings = exu.SimulationSettings()
    settings.staticSolver.newton.relativeTolerance = 1e-14
    settings.staticSolver.newton.absoluteTolerance = 1e-14
    settings.staticSolver.numberOfLoadSteps = 1
    # A mass-proportional term in the Newton matrix only (the residual, hence the equilibrium,
    # is unchanged): keeps the matrix regular along free (rigid-mode) directions.
    settings.staticSolver.stabilizerODE2term = 1.0
    settings.staticSolver.verboseMode = 0
    settings.solution.file.write = False
    settings.solution.sensors.writePeriod = 1e10
    settings.linearSolver.solverType = exu.LinearSolverType.EXUdense
    ok = mbs.SolveStatic(settings, updateInitialValues=True)
    if not ok:
        print("ERROR static solve failed")
        sys.exit(1)
    f, _ = mbs.ComputeODE2Eigenvalues(
        settings, convert2Frequencies=False, useAbsoluteValues=False
    )
    print(f"RESULT version={exu.__version__}")
    q = mbs.systemData.GetODE2Coordinates()
    print(f"RESULT equilibrium_shift={float(np.max(np.abs(q))) if len(q) else 0.0:.3e}")
    for name, m in com_markers:
        x = mbs.GetMarkerOutput(m, exu.OutputVariableType.Position)
        print(f"RESULT com={name} {x[0]:.17e} {x[1]:.17e} {x[2]:.17e}")
    for w2 in f:
        hz = np.sign(w2) * np.sqrt(abs(w2)) / (2.0 * np.pi)
        print(f"RESULT f={hz:.17e}")


if __name__ == "__main__":
    main()
