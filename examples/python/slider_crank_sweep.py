"""Motor torque of the bundled slider-crank against crank length and speed: a design sweep.

Run it with the package installed with its extras (`pip install ... "cardan[all]"`, README.md;
scripts/test-python installs them into target/py-venv):

    python examples/python/slider_crank_sweep.py            # local processes
    python examples/python/slider_crank_sweep.py --dask     # a local Dask cluster

It writes out/python/slider_crank_sweep.csv and .png under the current directory (`--out DIR`
for another) and exits with status 1 if a case failed. On a real cluster, pass
`client=distributed.Client("scheduler-address:8786")` to `cardan.sweep` (docs/python.md).
"""

import argparse
import os
import pathlib
import sys

import numpy as np

import cardan

ROOT = pathlib.Path(__file__).resolve().parents[2]
TEXT = (ROOT / "examples" / "slider_crank_inverse.toml").read_text()


def slider_crank(crank: float, speed: float) -> cardan.Model:
    """The slider-crank with crank length `crank` [m] and crank speed `speed` [rev/s]."""
    half = crank / 2
    text = (
        TEXT.replace("points = { A = [0.0, 0.0, -0.04], B = [0.0, 0.0, 0.04] }",
                     f"points = {{ A = [0.0, 0.0, {-half!r}], B = [0.0, 0.0, {half!r}] }}")
        .replace("position = [0.0, 0.1, 0.16]", f"position = [0.0, 0.1, {0.12 + half!r}]")
        .replace("global_points = { B = [0.0, 0.1, 0.2]", f"global_points = {{ B = [0.0, 0.1, {0.12 + crank!r}]")
        .replace("coefficients = [0.0, 6.283185307179586]", f"coefficients = [0.0, {2 * np.pi * speed!r}]")
    )
    return cardan.Model(text, f"slider_crank(crank={crank}, speed={speed})")


def peak_torque(r: cardan.Results) -> float:
    """Largest |motor torque| over one crank turn [N m]."""
    return float(np.max(np.abs(r.driver_efforts["motor.torque"])))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dask", action="store_true", help="run on a local Dask cluster")
    parser.add_argument("--out", default=os.path.join("out", "python"), help="output directory")
    args = parser.parse_args()
    params = cardan.grid(crank=np.linspace(0.04, 0.1, 7), speed=[0.5, 1.0, 2.0, 4.0])
    kwargs = dict(analysis="inverse_dynamics", outputs={"peak_torque": peak_torque},
                  options={"t_end": 1.0, "steps": 100})
    if args.dask:
        from distributed import Client, LocalCluster

        with LocalCluster(n_workers=2, threads_per_worker=1) as cluster, Client(cluster) as client:
            table = cardan.sweep(slider_crank, params, client=client, **kwargs)
    else:
        table = cardan.sweep(slider_crank, params, **kwargs)
    print(table.to_string(index=False))
    failed = table[table["status"] != "ok"]
    for _, row in failed.iterrows():
        print(f"crank={row['crank']}, speed={row['speed']}: {row['error']}", file=sys.stderr)

    out = pathlib.Path(args.out)
    os.makedirs(out, exist_ok=True)
    table.to_csv(out / "slider_crank_sweep.csv", index=False)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    for speed, group in table.groupby("speed"):
        ax.plot(group["crank"] * 1000, group["peak_torque"], marker="o", label=f"{speed:g} rev/s")
    ax.set_xlabel("crank length [mm]")
    ax.set_ylabel("peak motor torque [N m]")
    ax.set_yscale("log")
    ax.grid(True, alpha=0.3)
    ax.legend(title="crank speed")
    fig.tight_layout()
    fig.savefig(out / "slider_crank_sweep.png", dpi=120)
    print(f"wrote {out / 'slider_crank_sweep.csv'} and {out / 'slider_crank_sweep.png'}")
    if len(failed):
        sys.exit(f"{len(failed)} of {len(table)} cases failed (above)")


if __name__ == "__main__":
    main()
