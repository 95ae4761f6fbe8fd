"""Model factories and outputs of the sweep tests: module-level so that process pools and Dask
workers can unpickle them. The factory is the one of examples/python/slider_crank_sweep.py."""

from pathlib import Path

import numpy as np

import cardan
from slider_crank_sweep import peak_torque, slider_crank

__all__ = ["parametric", "peak_slider_force", "peak_torque", "slider_crank"]

_PARAMETRIC = Path(__file__).resolve().parents[3] / "examples" / "slider_crank_parametric.toml"


def parametric(crank: float, speed: float) -> cardan.Model:
    """examples/slider_crank_parametric.toml with its crank (m) and speed (rad/s) set."""
    return cardan.load(_PARAMETRIC).with_parameters(crank=crank, speed=speed)


def peak_slider_force(r: cardan.Results) -> float:
    """Largest |force| of the slide joint on the slider [N]."""
    f = np.stack([r.reactions[f"slide.slider.F.{c}"] for c in "xyz"], axis=1)
    return float(np.max(np.linalg.norm(f, axis=1)))
