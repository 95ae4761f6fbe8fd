"""Benchmarks of the Python package (run by `scripts/bench-python`; not part of the tests).

1. Python overhead: a kinematic run of the slider-crank with ≥ 1,000 frames through
   `Model.kinematics` against the Rust analysis time of the same run (run.json's wall time)
   and against the `cardan run` process writing the same tables (plots off).
2. Sweep: 200 inverse-dynamics slider-crank cases on 2 local worker processes against the
   same cases serially in one process; per-case overhead of the pool.

Prints a markdown table with the machine.
"""

import os
import pathlib
import platform
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[3]
sys.path.insert(0, str(ROOT / "examples" / "python"))

import cardan  # noqa: E402
from slider_crank_sweep import peak_torque, slider_crank  # noqa: E402


def best(f, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = f()
        times.append(time.perf_counter() - t0)
    return min(times), out


def overhead(frames: int, repeat: int):
    model = cardan.load(ROOT / "examples" / "slider_crank.toml")
    opts = dict(t_end=frames / 200, steps=frames)
    # Paired: each call's Python time against the Rust time of the same call.
    calls = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        r = model.kinematics(**opts)
        calls.append((time.perf_counter() - t0, r.native_seconds, r.run["wall_time_s"]))
    calls.sort(key=lambda c: c[0] - c[1])
    t_py, native, analysis = calls[len(calls) // 2]
    cli = os.environ.get("CARDAN_BIN", str(ROOT / "target" / "release" / "cardan"))
    with tempfile.TemporaryDirectory() as d:
        text = model.text.replace("t_end = 1.0", f"t_end = {opts['t_end']}").replace("steps = 200", f"steps = {frames}")
        text = text.replace('kind = "kinematic"', 'kind = "kinematic"\nplots = "none"')
        path = pathlib.Path(d) / "m.toml"
        path.write_text(text)
        t_cli, _ = best(lambda: subprocess.run([cli, "run", str(path), "-o", str(pathlib.Path(d) / "o"), "--quiet"],
                                               check=True, capture_output=True), repeat)
    return t_py, analysis, native, t_cli, len(r.t)


def sweep(cases: int):
    params = cardan.grid(crank=np.linspace(0.05, 0.1, cases // 10), speed=np.linspace(0.5, 3.0, 10))
    kw = dict(analysis="inverse_dynamics", outputs={"peak_torque": peak_torque}, options={"t_end": 1.0, "steps": 200})
    cardan.sweep_serial(slider_crank, params[:2], **kw)  # imports (pandas) before the clock
    t_serial, serial = best(lambda: cardan.sweep_serial(slider_crank, params, **kw), 2)
    from concurrent.futures import ProcessPoolExecutor

    with ProcessPoolExecutor(2) as ex:
        # The workers start and import cardan and the model module before the clock (a pool
        # is started once per session; its start-up is reported apart).
        t0 = time.perf_counter()
        cardan.sweep(slider_crank, params[:4], executor=ex, chunksize=1, **kw)
        startup = time.perf_counter() - t0
        t_pool, pooled = best(lambda: cardan.sweep(slider_crank, params, executor=ex, **kw), 2)
    assert pooled.equals(serial)
    return len(params), t_serial, t_pool, startup


def main():
    frames = 2000
    t_py, analysis, native, t_cli, n = overhead(frames, 7)
    cases, t_serial, t_pool, startup = sweep(200)
    print(f"Machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    print()
    print("| measurement | value |")
    print("|---|---|")
    print(f"| kinematic run, {n} frames: `Model.kinematics` | {t_py * 1e3:.2f} ms |")
    print(f"| the same: Rust analysis (run.json wall time) | {analysis * 1e3:.2f} ms |")
    print(f"| the same: `cardan run` process (CSV written, plots off) | {t_cli * 1e3:.2f} ms |")
    print(f"| the same: the Rust side of the call (model read and built, analysis, tables) | {native * 1e3:.2f} ms |")
    print(f"| Python overhead over the Rust side | {(t_py - native) * 1e3:.2f} ms ({(t_py / native - 1) * 100:.1f} %) |")
    print(f"| sweep of {cases} inverse-dynamics cases, serial | {t_serial:.2f} s ({t_serial / cases * 1e3:.1f} ms per case) |")
    print(f"| the same on 2 local worker processes | {t_pool:.2f} s (speed-up {t_serial / t_pool:.2f}×; per-case overhead {(2 * t_pool - t_serial) / cases * 1e3:.2f} ms) |")
    print(f"| starting the 2 workers (imports, first cases) | {startup:.2f} s |")


if __name__ == "__main__":
    main()
