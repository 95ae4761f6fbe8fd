"""cardan's side of the peer comparison scripts (limits_exudyn.py, limits_mujoco.py), shared by
them: their `RESULT key=value ...` lines, a run of the release CLI (`target/release/cardan run
<model> -o <dir> --quiet`) on a model text in a temporary directory, reading the CSV files it
writes, and putting a run's histories (cardan's or the peer's) on the common output grid. Not
part of any test suite; the scripts import it as a sibling module (Python puts a script's
directory first on sys.path).
"""

import csv
import json
import os
import subprocess
import tempfile
import time

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
CARDAN = os.path.join(ROOT, "target", "release", "cardan")


def result(**kw):
    print("RESULT " + " ".join(f"{k}={v}" for k, v in kw.items()), flush=True)


def require_cardan():
    """Stops the script when the release CLI has not been built."""
    if not os.path.exists(CARDAN):
        raise SystemExit(f"{CARDAN} missing: cargo build --release -p cardan-cli")


def read_csv(path):
    """An output CSV of cardan: its header and its rows as floats."""
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], [[float(x) for x in r] for r in rows[1:] if r]


def col(head, rows, name):
    """The column `name` (header text, unit included) of read_csv's rows."""
    i = head.index(name)
    return [r[i] for r in rows]


def run_model(text, name, csvs):
    """Writes the model text to a temporary directory as `name`, runs `cardan run` on it and
    returns the wall time of the whole process (start-up and writing all output files included),
    {file: (head, rows)} for each output CSV file named in csvs (e.g. "joints.csv") and the
    parsed run.json."""
    stem = os.path.splitext(name)[0]
    with tempfile.TemporaryDirectory(prefix=f"cardan_{stem}_") as tmp:
        model = os.path.join(tmp, name)
        with open(model, "w") as f:
            f.write(text)
        out = os.path.join(tmp, "out")
        t0 = time.perf_counter()
        subprocess.run([CARDAN, "run", model, "-o", out, "--quiet"], check=True,
                       stdout=subprocess.DEVNULL)
        wall = time.perf_counter() - t0
        tables = {c: read_csv(os.path.join(out, c)) for c in csvs}
        with open(os.path.join(out, "run.json")) as f:
            info = json.load(f)
    return wall, tables, info


def on_grid(d, t_end, dt):
    """Keeps the samples of a run's dict of histories d (d["t"] the times; every array as long as
    d["t"] is indexed, anything else kept as is) on the output grid 0, dt, ..., t_end (index
    k = round(t / dt)); stops the script when a grid time is missing."""
    import numpy as np
    n = int(round(t_end / dt)) + 1
    k = np.rint(d["t"] / dt).astype(int)
    ok = (np.abs(d["t"] - k * dt) < 1e-9) & (k < n)
    idx = np.full(n, -1)
    idx[k[ok]] = np.nonzero(ok)[0]
    if (idx < 0).any():
        raise SystemExit(f"missing output times, e.g. t = {np.nonzero(idx < 0)[0][0] * dt}")
    return {key: (v[idx] if hasattr(v, "shape") and v.shape[:1] == d["t"].shape else v)
            for key, v in d.items()}
