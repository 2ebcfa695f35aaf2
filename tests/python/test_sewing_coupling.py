"""SewingTable and Perforators coupled in a host (FMPy FMU2Slave instances, a simple
co-simulation loop): Perforators.table.F -> SewingTable.table.F_ext. The coupled shaft torque
must equal the sum of the two mechanisms' power divided by the speed: the table alone (a third
instance with table.F_ext = 0) plus the perforators' share (Perforators.shaft.P)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fmpy.fmi2 import FMU2Slave

from harness import FMU_DIR, Extracted

W = 100 * math.pi / 30  # rad/s, the nominal 100 rpm


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


def co_simulate(guide_f: float, eps: float = 0.0, turns: float = 1.0, h: float = 5e-4):
    table_ex = Extracted.of(FMU_DIR / "SewingTable.fmu")
    perf_ex = Extracted.of(FMU_DIR / "Perforators.fmu")
    vr_t = {n: table_ex.vars[n].valueReference for n in ("shaft.phi", "shaft.w", "shaft.a", "table.F_ext",
                                                         "shaft.tau", "shaft.P", "table.x")}
    vr_p = {n: perf_ex.vars[n].valueReference for n in ("shaft.phi", "shaft.w", "shaft.a", "table.F", "shaft.P",
                                                        "table.x")}
    coupled = instance(table_ex, "coupled", {"guide.f": guide_f})
    alone = instance(table_ex, "alone", {"guide.f": guide_f})
    perf = instance(perf_ex, "perforators", {})
    rows = []
    t, w0 = 0.0, W
    n = int(round(turns * 2 * math.pi / W / h))
    try:
        for _ in range(n):
            phi, w = w0 * t + 0.5 * eps * t * t, w0 + eps * t
            shaft = [phi, w, eps]
            for fmu, vr in ((coupled, vr_t), (alone, vr_t), (perf, vr_p)):
                fmu.setReal([vr["shaft.phi"], vr["shaft.w"], vr["shaft.a"]], shaft)
            # the coupling: the perforator drive's force on the table
            f_table, p_perf, x_p = perf.getReal([vr_p["table.F"], vr_p["shaft.P"], vr_p["table.x"]])
            coupled.setReal([vr_t["table.F_ext"]], [f_table])
            tau, x_t = coupled.getReal([vr_t["shaft.tau"], vr_t["table.x"]])
            (p_alone,) = alone.getReal([vr_t["shaft.P"]])
            rows.append((t, w, tau, p_alone, p_perf, f_table, x_t, x_p))
            for fmu in (coupled, alone, perf):
                fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
            t += h
    finally:
        for fmu in (coupled, alone, perf):
            fmu.terminate()
            fmu.freeInstance()
    return np.array(rows)


def test_coupled_torque_is_the_sum_of_the_powers_over_the_speed():
    # without guide friction the table's force balance is linear in F_ext: equal to round-off
    for eps in (0.0, 3.0):
        r = co_simulate(guide_f=0.0, eps=eps)
        t, w, tau, p_alone, p_perf, f_table, x_t, x_p = r.T
        np.testing.assert_allclose(x_t, x_p, rtol=0, atol=1e-15)  # both ride the same cyclogram
        expected = (p_alone + p_perf) / w
        assert np.max(np.abs(tau - expected)) <= 1e-9 * np.max(np.abs(expected))
        # the perforators do load the table: their share is not negligible
        assert np.max(np.abs(p_perf)) > 0.05 * np.max(np.abs(p_alone))
        assert np.max(np.abs(f_table)) > 1.0


def test_coupled_torque_with_guide_friction():
    # with rolling friction on m*g + |Fn*sin(theta)| the perforators' force also changes the guide
    # load: the sum holds to the friction coefficient's order
    r = co_simulate(guide_f=0.005)
    t, w, tau, p_alone, p_perf, *_ = r.T
    expected = (p_alone + p_perf) / w
    err = np.max(np.abs(tau - expected))
    assert err <= 0.01 * np.max(np.abs(expected))
    assert err > 0.0  # and it is not the frictionless case
