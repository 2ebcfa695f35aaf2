"""MainShaft driving a GenevaKnifeDrive in a plain co-simulation loop (FMPy FMU2Slave instances).

Two couplings of the same machine (the trimmer's drive: 30 rpm at the main shaft, gear 1:50):
- split: the mechanism's shaft.tau0 and shaft.J_red go to MainShaft's load1.tau0, load1.J_red, and
  MainShaft solves (J_drive + J_red)*a = M - tau0 - friction: the inertia is implicit;
- plain: the mechanism's whole shaft.tau goes to MainShaft's load.tau: its inertia torque
  J_red*a then uses the acceleration of the previous step, a_{n+1} = (M - tau0 - J_red*a_n)/J_drive,
  a loop of gain -J_red/J_drive that diverges whatever the step once J_red > J_drive.
"""

from __future__ import annotations

import math

import numpy as np
from fmpy.fmi2 import FMU2Slave

from harness import FMU_DIR, Extracted

W = math.pi  # rad/s: the trimmer's 30 rpm


def instance(ex: Extracted, name: str, start: dict[str, float]) -> FMU2Slave:
    fmu = FMU2Slave(guid=ex.md.guid, unzipDirectory=ex.dir, modelIdentifier=ex.md.coSimulation.modelIdentifier,
                    instanceName=name)
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    for n, v in start.items():
        fmu.setReal([ex.vars[n].valueReference], [v])
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    return fmu


# The knife drive without the cutting load (the inertia is what matters here; with the cut, a
# small flywheel lets the shaft stall, which is physics, not numerics) and with a heavy knife
# housing (40 kg instead of 12 kg): its reduced inertia then peaks above the drive's.
KNIFE = {"cut.F_max": 0.0, "knife.m": 40.0}


def co_simulate(coupling: str, h: float, fly_j: float, stop: float = 2.0):
    """Returns (t, w, a, J_red) rows until `stop` or until the speed leaves [0, 3*W] (diverged)."""
    ms_ex = Extracted.of(FMU_DIR / "MainShaft.fmu")
    gv_ex = Extracted.of(FMU_DIR / "GenevaKnifeDrive.fmu")
    vm = {n: ms_ex.vars[n].valueReference for n in ("shaft.phi", "shaft.w", "shaft.a", "load.tau",
                                                      "load1.tau0", "load1.J_red")}
    vg = {n: gv_ex.vars[n].valueReference for n in ("shaft.phi", "shaft.w", "shaft.a", "shaft.tau",
                                                      "shaft.tau0", "shaft.J_red")}
    ms = instance(ms_ex, "drive", {"gear.i": 50.0, "fly.J": fly_j, "init.w": W})
    gv = instance(gv_ex, "knife", KNIFE)
    rows = []
    t = 0.0
    try:
        for _ in range(int(round(stop / h))):
            shaft = ms.getReal([vm["shaft.phi"], vm["shaft.w"], vm["shaft.a"]])
            gv.setReal([vg["shaft.phi"], vg["shaft.w"], vg["shaft.a"]], shaft)
            tau, tau0, j_red = gv.getReal([vg["shaft.tau"], vg["shaft.tau0"], vg["shaft.J_red"]])
            if coupling == "split":
                ms.setReal([vm["load1.tau0"], vm["load1.J_red"]], [tau0, j_red])
            else:
                ms.setReal([vm["load.tau"]], [tau])
            rows.append((t, shaft[1], shaft[2], j_red))
            if not (math.isfinite(shaft[1]) and 0.0 <= shaft[1] <= 3 * W and abs(shaft[2]) < 1e4):
                break
            ms.doStep(currentCommunicationPoint=t, communicationStepSize=h)
            gv.doStep(currentCommunicationPoint=t, communicationStepSize=h)
            t += h
    finally:
        for fmu in (ms, gv):
            fmu.terminate()
            fmu.freeInstance()
    return np.array(rows)


def diverged(r: np.ndarray, stop: float, h: float) -> bool:
    return len(r) < int(round(stop / h))


def test_split_coupling_is_stable_where_the_plain_one_diverges():
    fly_j = 0.0  # the drive's inertia is the motor's alone: 50^2 * 0.0035 = 8.75 kg.m2
    split = co_simulate("split", 1e-3, fly_j)
    assert not diverged(split, 2.0, 1e-3), f"split coupling diverged at t = {split[-1, 0]}"
    # the Geneva drive's reduced inertia does exceed the drive's during the index
    assert split[:, 3].max() > 8.75, split[:, 3].max()
    # plain torque coupling: diverges, and a ten times smaller step does not save it
    for h in (1e-3, 1e-4):
        plain = co_simulate("plain", h, fly_j)
        assert diverged(plain, 2.0, h), f"plain coupling with h = {h} stayed bounded"


def test_split_coupling_converges_with_the_step():
    coarse = co_simulate("split", 2e-3, 0.0)
    fine = co_simulate("split", 5e-4, 0.0)
    t = coarse[:, 0]
    w_fine = np.interp(t, fine[:, 0], fine[:, 1])
    err = np.max(np.abs(coarse[:, 1] - w_fine))
    assert err < 0.02 * W, err
    # the speed does fluctuate (the coupling carries the load): not a trivially flat result
    assert np.ptp(fine[:, 1]) > 0.05 * W


def test_both_couplings_agree_when_the_flywheel_dominates():
    # J_drive = 200 + 8.75 >> J_red: the plain coupling is stable and close to the split one
    split = co_simulate("split", 1e-3, 200.0)
    plain = co_simulate("plain", 1e-3, 200.0)
    assert not diverged(plain, 2.0, 1e-3)
    assert np.max(np.abs(split[:, 1] - plain[:, 1])) < 1e-3 * W


def test_model_exchange_with_cvode_matches_the_independent_start_up():
    """The same binary as Model Exchange: FMPy integrates shaft.phi, shaft.w with CVode."""
    from main_shaft_reference import LOAD, startup

    ex = Extracted.of(FMU_DIR / "MainShaft.fmu")
    assert ex.md.modelExchange is not None
    r = ex.simulate(fmi_type="ModelExchange", start_values=dict(LOAD), stop_time=3.0, output_interval=0.01,
                    relative_tolerance=1e-8, output=["shaft.phi", "shaft.w", "shaft.a"])
    phi, w = startup(r["time"][::30])
    np.testing.assert_allclose(r["shaft.w"][::30], w, rtol=1e-5, atol=1e-5 * np.max(w))
    np.testing.assert_allclose(r["shaft.phi"][::30], phi, rtol=1e-5, atol=1e-5 * np.max(phi))
