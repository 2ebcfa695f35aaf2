"""The two machines as SSP 1.0 files (`cargo run --release -- ssp`, out/ssp/), run with FMPy 0.3.32's
`fmpy.ssp.simulate_ssp` (a fixed-step master: every FMU steps, then the connections are applied).

FMPy reads the ParameterBinding of the system but does not apply it by itself: the test hands it
over as `parameter_set` (names `<component>.<variable>`). Every shaft input starts at 0: the machines
start up from rest.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from fmpy.ssp.simulation import simulate_ssp
from fmpy.ssp.ssd import read_ssd

SSP_DIR = Path(__file__).resolve().parents[2] / "out" / "ssp"


def simulate(name: str, stop: float, h: float = 1e-3):
    path = SSP_DIR / f"{name}.ssp"
    if not path.is_file():
        pytest.fail(f"{path} is missing: run `cargo run --release -- build` and `cargo run --release -- ssp`")
    ssd = read_ssd(str(path))  # validates against the SSP 1.0 schema
    sets = [ps for b in ssd.system.parameterBindings for ps in b.parameterValues]
    return simulate_ssp(str(path), stop_time=stop, step_size=h, parameter_set=sets[0] if sets else None)


def test_thread_sewing_machine_starts_up_and_runs_at_its_speed():
    r = simulate("ThreadSewingMachine", 4.0)
    t, w = r["time"], r["drive.shaft.w"]
    nominal = 100 * math.pi / 30
    assert np.all(np.isfinite(w))
    steady = t > 3.0
    # just below the synchronous 100 rpm: the motor's slip under the load
    assert 0.9 * nominal < w[steady].mean() < nominal
    # every connection carries something: the table moves with the shaft, the perforators load it
    assert np.ptp(r["table.table.x"][steady]) > 0.01
    assert np.max(np.abs(r["perforators.table.F"][steady])) > 1.0
    assert np.max(np.abs(r["table.shaft.J_red"][steady])) > 0.0
    # the load the drive solves with is the table's own torque (one step late, rounding aside)
    err = np.abs(r["drive.shaft.tau_load"][steady][1:] - r["table.shaft.tau"][steady][:-1])
    assert np.max(err) < 0.05 * np.max(np.abs(r["table.shaft.tau"][steady])) + 0.5


def test_three_knife_trimmer_starts_up_and_cuts_in_its_cycle():
    r = simulate("ThreeKnifeTrimmer", 12.0, h=2e-3)
    t, w = r["time"], r["drive.shaft.w"]
    nominal = math.pi  # 30 rpm
    assert np.all(np.isfinite(w))
    steady = t > 8.0
    assert 0.85 * nominal < w[steady].mean() < nominal
    left, right, front = (r[f"{k}.knife.s"] for k in ("side_left", "side_right", "front"))
    # the side knives cut together, the front knife half a turn later: never all three at once
    np.testing.assert_array_equal(left, right)
    assert left[steady].max() > 0.13 and front[steady].max() > 0.13
    assert np.max(np.minimum(left, front)[steady]) < 1e-9
