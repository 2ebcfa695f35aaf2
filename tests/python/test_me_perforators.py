"""The Perforators' elastodynamic level through Model Exchange: FMPy validates the FMU, integrates
the model's states (the lever's deflection from its rigid rotation, its rate, the work integral)
with CVode, its own solver, and the result matches the FMU's internal solver in Co-Simulation,
also across the roller's lift-offs and landings above the rigid lift-off speed (113.65 rpm)."""

from __future__ import annotations

import numpy as np
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

from harness import FMU_DIR

PERFORATORS = str(FMU_DIR / "Perforators.fmu")
START = {"model.fidelity": 3, "drive.mode": 2}
OUT = ["lever.gamma", "lever.gamma_kin", "elastic.F", "roller.F_kin", "contact.liftoffs",
       "contact.penetration"]


def run(fmi_type: str, stop: float, **kw):
    return simulate_fmu(PERFORATORS, fmi_type=fmi_type, start_time=0.0, stop_time=stop,
                        output_interval=1e-3, start_values=dict(START, **kw.pop("start", {})),
                        output=OUT, **kw)


def test_the_fmu_validates_with_model_exchange():
    assert validate_fmu(PERFORATORS) == []


def test_model_exchange_with_cvode_matches_the_internal_solver_at_the_nominal_speed():
    # the forward travel: rise, piercing, fall, at 100 rpm (no lift-off)
    cs = run("CoSimulation", 0.15, start={"solver.rtol": 1e-9, "solver.atol": 1e-12})
    me = run("ModelExchange", 0.15, solver="CVode", relative_tolerance=1e-8)
    g_me = np.interp(cs["time"], me["time"], me["lever.gamma"])
    assert np.max(np.abs(cs["lever.gamma"] - g_me)) < 1e-6
    # the contact force: the peak within 1 %, and close to the kinetostatic one (no lift-off)
    fc, fm = np.max(cs["elastic.F"]), np.max(me["elastic.F"])
    assert abs(fc - fm) < 1e-2 * fc, (fc, fm)
    assert np.all(cs["contact.liftoffs"] == 0) and np.all(me["contact.liftoffs"] == 0)
    # the roller stays pressed into the ramp
    assert np.min(me["contact.penetration"]) > 0


def test_model_exchange_and_co_simulation_agree_through_liftoffs_at_130_rpm():
    w = 130 * np.pi / 30
    start = {"drive.n": w}
    cs = run("CoSimulation", 0.1, start=dict(start, **{"solver.rtol": 1e-9, "solver.atol": 1e-12}))
    me = run("ModelExchange", 0.1, start=start, solver="CVode", relative_tolerance=1e-8)
    # the roller leaves the ramp near the top of the rise and lands again
    assert cs["contact.liftoffs"][-1] >= 1
    assert me["contact.liftoffs"][-1] == cs["contact.liftoffs"][-1]
    assert np.min(cs["contact.penetration"]) < 0
    g_me = np.interp(cs["time"], me["time"], me["lever.gamma"])
    assert np.max(np.abs(cs["lever.gamma"] - g_me)) < 1e-4
