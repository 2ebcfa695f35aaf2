"""What the two example scripts share: a machine's SSP file run at a given speed with FMPy's SSP
runner, the samples of its last shaft turn, and a plot over the shaft angle."""

from __future__ import annotations

import io
import math
import zipfile
from pathlib import Path
from types import SimpleNamespace

import numpy as np
from fmpy import read_model_description
from fmpy.ssp.simulation import simulate_ssp

RPM = math.pi / 30  # rad/s per rpm


def start_value(ssp: Path, component: str, name: str) -> float:
    """The start value of `name` in the FMU of `component` inside the SSP file."""
    with zipfile.ZipFile(ssp) as z:
        inner = next(n for n in z.namelist() if n.endswith(f"_{component}.fmu"))
        md = read_model_description(io.BytesIO(z.read(inner)))
    return float(next(v for v in md.modelVariables if v.name == name).start)


def run_machine(ssp: Path, rpm: float, turns: int, step: float | None = None) -> dict:
    """The machine in `ssp` with its main shaft at `rpm`: the drive's gear makes `rpm` the
    synchronous speed of its motor, and the shaft starts at that speed. Runs `turns` turns in
    steps of `step` (default: 1/2000 of a turn, at most 2 ms). Every recorded output by
    "component.variable", and "deg", the main-shaft angle in [0, 360)."""
    w = rpm * RPM
    n_sync = start_value(ssp, "drive", "motor.n_rated") / (1 - start_value(ssp, "drive", "motor.s_rated"))
    period = 2 * math.pi / w
    step = step or min(2e-3, period / 2000)
    params = SimpleNamespace(parameters=[
        SimpleNamespace(name="drive.gear.i", value=n_sync / w),
        SimpleNamespace(name="drive.init.w", value=w),
    ])
    r = simulate_ssp(str(ssp), stop_time=turns * period, step_size=step, parameter_set=params)
    out = {n: np.asarray(r[n]) for n in r.dtype.names}
    out["deg"] = np.degrees(np.mod(out["drive.shaft.phi"], 2 * math.pi))
    return out


def last_turn(r: dict) -> np.ndarray:
    """The indices of the last complete turn of the main shaft."""
    turn = np.floor(r["drive.shaft.phi"] / (2 * math.pi))
    last = turn[-1] - 1
    idx = np.nonzero(turn == last)[0]
    if len(idx) < 10:
        raise RuntimeError("the run is shorter than two shaft turns")
    return idx


def write_plot(path: Path, title: str, deg, panels) -> Path:
    """A PNG of `panels` over the shaft angle `deg`: each panel (y label, [(legend, values)],
    zero line)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, axes = plt.subplots(len(panels), 1, figsize=(8, 2.8 * len(panels)), sharex=True)
    for ax, (label, series, zero) in zip(np.atleast_1d(axes), panels):
        for name, y in series:
            ax.plot(deg, y, label=name, lw=1.2)
        if zero:
            ax.axhline(0.0, color="0.3", lw=0.8, ls="--")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        ax.legend(loc="best", fontsize=8)
    np.atleast_1d(axes)[-1].set_xlabel("main-shaft angle, deg")
    np.atleast_1d(axes)[0].set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
