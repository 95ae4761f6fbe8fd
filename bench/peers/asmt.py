"""OndselSolver (pyondsel) on ASMT files, for cardan-bench's ASMT section (crates/bench/src/asmt.rs).
Each command prints one line `RESULT key=value ...` per file (times exclude Python start-up and
imports).

  python asmt.py solve N FILE...      # best of N: read the file, solve its time span, write the text
  python asmt.py readback FILE...     # OndselSolver reads a written .solved.asmt back
  python asmt.py python N SITE FILE...  # cardan's Python package against pyondsel, one process

`solve` times what OndselSolver does with an assembly in FreeCAD's Assembly workbench: the file
read from disk, parsed, assembled, solved over tstart..tend by hout and written back as text with
its TimeSeries (`solve_asmt_raw`, in-process, the C++ extension that `pyondsel.solve.solve_asmt`
runs in a worker process).

`python` times the two Python packages in this one process, as a Python user meets them:
`cardan.load(FILE).run()` (cardan imported from SITE, a site-packages folder holding it: the
test environment's, `target/py-venv`; it reads the file, imports the assembly, runs the
kinematics and returns every table as numpy arrays) against pyondsel's `solve_asmt` (its public
solve, which runs OndselSolver in a worker process) and `solve_asmt_raw` (the C++ extension
called in this process), each given the file's text read here. In rounds (pyondsel's two, then
cardan), the best of each over all rounds.

`readback` checks a `.solved.asmt` that cardan wrote, in two readers of pyondsel 0.0.3:
OndselSolver's own C++ reader (`solve_asmt_raw`, which reads the whole file and solves it again;
it must succeed and give the same number of frames) and pyondsel's TimeSeries reader
(`AsmtSolver._parse`, the Python side that turns a solved text into per-part trajectories; it
must find every part with one position per time). Failures are reported, never raised.
"""

import sys
import time
import warnings

warnings.filterwarnings("ignore")


def result(**kw):
    print("RESULT " + " ".join(f"{k}={v}" for k, v in kw.items()), flush=True)


def frames(text):
    """The number of output times of a solved text (the `Time` row minus its `Input` cell)."""
    for line in text.splitlines():
        if line.startswith("Time\t") or line.startswith("Time "):
            return sum(1 for c in line.split("\t")[1:] if c.strip() not in ("", "Input"))
    return 0


def solve(n, files):
    from pyondsel.solve_raw import solve_asmt_raw

    for f in files:
        best = float("inf")
        out = ""
        for _ in range(n):
            t0 = time.perf_counter()
            with open(f, encoding="utf-8") as fh:
                text = fh.read()
            out = solve_asmt_raw(text)
            best = min(best, time.perf_counter() - t0)
        result(file=f, best=best, frames=frames(out))


def in_python(n, site, files):
    sys.path.append(site)  # after this environment's own packages (its numpy)
    import cardan
    from pyondsel.solve import solve_asmt
    from pyondsel.solve_raw import solve_asmt_raw

    def best_of(reps, call):
        best = float("inf")
        for _ in range(reps):
            t0 = time.perf_counter()
            call()
            best = min(best, time.perf_counter() - t0)
        return best

    def ondsel(solve, f):
        with open(f, encoding="utf-8") as fh:
            return solve(fh.read())

    for f in files:
        cardan.load(f).run()  # warm: imports, first-call setup
        times = {"cardan": float("inf"), "public": float("inf"), "raw": float("inf")}
        for _ in range(3):
            times["public"] = min(times["public"], best_of(max(1, n // 4), lambda: ondsel(solve_asmt, f)))
            times["raw"] = min(times["raw"], best_of(max(1, n // 4), lambda: ondsel(solve_asmt_raw, f)))
            times["cardan"] = min(times["cardan"], best_of(n, lambda: cardan.load(f).run()))
        result(file=f, **times)


def readback(files):
    from pyondsel.asmt_solver import AsmtSolver
    from pyondsel.solve_raw import solve_asmt_raw

    for f in files:
        with open(f, encoding="utf-8") as fh:
            text = fh.read()
        written = frames(text)
        parts = text.count("\nPartSeries")
        try:
            resolved = frames(solve_asmt_raw(text))
            cpp = "ok" if resolved == written else f"frames:{resolved}/{written}"
        except Exception as e:  # noqa: BLE001 - reported, not raised
            cpp = "error:" + str(e).replace(" ", "_")[:80]
        try:
            traj = AsmtSolver()._parse(text)
            complete = all(
                len(p.positions) == len(traj.times) for p in traj.parts.values()
            )
            if len(traj.times) == written and len(traj.parts) == parts and complete:
                py = "ok"
            else:
                py = f"times:{len(traj.times)}/{written},parts:{len(traj.parts)}/{parts}"
        except Exception as e:  # noqa: BLE001
            py = "error:" + str(e).replace(" ", "_")[:80]
        result(file=f, frames=written, parts=parts, cpp=cpp, python=py)


if __name__ == "__main__":
    cmd = sys.argv[1] if len(sys.argv) > 1 else ""
    if cmd == "solve":
        solve(int(sys.argv[2]), sys.argv[3:])
    elif cmd == "python":
        in_python(int(sys.argv[2]), sys.argv[3], sys.argv[4:])
    elif cmd == "readback":
        readback(sys.argv[2:])
    else:
        print(__doc__)
        sys.exit(2)
