"""The elastodynamic level through Model Exchange: FMPy integrates the model's states with
CVode (its own solver, the baseline of dynamics.md) and the result matches the FMU's internal
solver in Co-Simulation. `fmpy validate` covers the ModelExchange element (test_all_fmus.py)."""

from __future__ import annotations

import numpy as np
from fmpy import simulate_fmu

from harness import FMU_DIR

GENEVA = str(FMU_DIR / "GenevaKnifeDrive.fmu")
START = {"model.fidelity": 3, "drive.mode": 2}
OUT = ["knife.s", "knife.s_kin", "elastic.F", "elastic.deflection"]


def run(fmi_type: str, **kw):
    return simulate_fmu(GENEVA, fmi_type=fmi_type, start_time=0.0, stop_time=0.3,
                        output_interval=1e-3, start_values=dict(START, **kw.pop("start", {})),
                        output=OUT, **kw)


def test_model_exchange_with_cvode_matches_the_internal_solver():
    cs = run("CoSimulation", start={"solver.rtol": 1e-9, "solver.atol": 1e-12})
    me = run("ModelExchange", solver="CVode", relative_tolerance=1e-8)
    # the ME result has extra rows at the events it located: compare at the CS instants
    s_me = np.interp(cs["time"], me["time"], me["knife.s"])
    ds = np.max(np.abs(cs["knife.s"] - s_me))
    assert ds < 1e-6, ds
    # the chain force: the peak (cutting and the ring after cut-through) within 1 %
    fc, fm = np.max(np.abs(cs["elastic.F"])), np.max(np.abs(me["elastic.F"]))
    assert abs(fc - fm) < 1e-2 * fc, (fc, fm)
    # the elastic knife follows its rigid position to within the chain's deflection
    assert np.max(np.abs(me["knife.s"] - me["knife.s_kin"])) < 1e-3


