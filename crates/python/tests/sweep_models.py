"""Model factories and outputs of the sweep tests: module-level so that process pools and Dask
workers can unpickle them. The factory is the one of examples/python/slider_crank_sweep.py."""

import numpy as np

import cardan
from slider_crank_sweep import peak_torque, slider_crank

__all__ = ["peak_slider_force", "peak_torque", "slider_crank"]


def peak_slider_force(r: cardan.Results) -> float:
    """Largest |force| of the slide joint on the slider [N]."""
    f = np.stack([r.reactions[f"slide.slider.F.{c}"] for c in "xyz"], axis=1)
    return float(np.max(np.linalg.norm(f, axis=1)))
