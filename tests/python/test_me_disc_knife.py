"""DiscKnifeDrive's elastodynamic level through Model Exchange (dynamics.md): FMPy validates the
FMU, integrates the model's states with CVode (its own solver, the baseline of dynamics.md), and
the result matches the FMU's internal solver in Co-Simulation."""

from __future__ import annotations

import numpy as np
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

from harness import FMU_DIR

DISC = str(FMU_DIR / "DiscKnifeDrive.fmu")
START = {"model.fidelity": 3, "drive.mode": 2}
OUT = ["slider.x", "slider.x_kin", "elastic.F", "rod.F_kin", "elastic.deflection", "knife.x",
       "elastic.E_residual"]
STOP = 0.25  # 300 rpm: a turn and a quarter, both dead centres, the jamming window, the wedge


def run(fmi_type: str, **kw):
    return simulate_fmu(DISC, fmi_type=fmi_type, start_time=0.0, stop_time=STOP,
                        output_interval=1e-3, start_values=dict(START, **kw.pop("start", {})),
                        output=OUT, **kw)


def test_validates_with_model_exchange():
    assert validate_fmu(DISC) == []


def test_model_exchange_with_cvode_matches_the_internal_solver():
    cs = run("CoSimulation", start={"solver.rtol": 1e-9, "solver.atol": 1e-12})
    me = run("ModelExchange", solver="CVode", relative_tolerance=1e-8)
    # the ME result has extra rows at the events it located: compare at the CS instants
    x_me = np.interp(cs["time"], me["time"], me["slider.x"])
    dx = np.max(np.abs(cs["slider.x"] - x_me))
    assert dx < 1e-6, dx
    # the rod force: the peak (the friction wedge after the jamming window) within 2 %
    fc, fm = np.max(np.abs(cs["elastic.F"])), np.max(np.abs(me["elastic.F"]))
    assert abs(fc - fm) < 2e-2 * fc, (fc, fm)
    # the elastic slider follows its rigid position to within the rod's shortening
    assert np.max(np.abs(me["slider.x"] - me["slider.x_kin"])) < 1e-4
    # the internal solver closes its energy balance
    assert np.max(np.abs(cs["elastic.E_residual"])) < 1e-3


def test_jam_free_rod_force_follows_the_kinetostatic_one_in_model_exchange():
    # no support friction (no jamming window): the dynamic rod force rings about the
    # kinetostatic one, the same in both interfaces
    start = {"support.mu": 0.0}
    cs = run("CoSimulation", start=dict(start, **{"solver.rtol": 1e-9, "solver.atol": 1e-12}))
    me = run("ModelExchange", start=start, solver="CVode", relative_tolerance=1e-8)
    f_me = np.interp(cs["time"], me["time"], me["elastic.F"])
    assert np.max(np.abs(cs["elastic.F"] - f_me)) < 2e-2 * np.max(np.abs(cs["elastic.F"]))
    assert np.max(np.abs(cs["elastic.F"] - cs["rod.F_kin"])) < np.max(np.abs(cs["rod.F_kin"]))
