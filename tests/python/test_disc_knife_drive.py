"""DiscKnifeDrive against shared/spec/disc-knife-drive.md, through FMPy.

Reference values of the spec, the trend of paper 004's Fig. 2, the NumPy geometry of
disc_knife_closed_form.py (independent of the Rust code), a power balance from the FMU's own
outputs, and a parameter set that cannot assemble.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave

import disc_knife_closed_form as dk
from harness import FMU_DIR, Extracted, captured_log, callbacks_with

PI = math.pi
W = 10.0 * PI  # 300 rpm
SPEC_OUTPUTS = {"slider.x", "slider.v", "slider.a", "holder.beta", "holder.w", "holder.eps", "knife.x",
                "knife.y", "knife.vx", "knife.vy", "knife.ax", "knife.ay", "support.x", "support.y",
                "knife.working", "cut.Fx", "cut.Fy", "rod.F", "guide.N", "support.N", "pinC.F", "pinD.F",
                "shaft.tau", "shaft.P"}


@pytest.fixture(scope="module")
def disc() -> Extracted:
    path = FMU_DIR / "DiscKnifeDrive.fmu"
    if not path.is_file():
        pytest.fail(f"{path} is missing: run `cargo run --release -- build` first")
    return Extracted.of(path)


def printed(x, reference, decimals):
    """x prints as `reference` with `decimals` decimals."""
    return abs(x - reference) <= 0.5 * 10.0 ** -decimals * (1 + 1e-9)


def turn(n):
    return np.linspace(0.0, 2 * PI, n, endpoint=False)


def probe_turn(disc, n, outputs, start_values=None, w=W):
    return disc.probe([(phi, w, 0.0) for phi in turn(n)], outputs, start_values=start_values)


def test_outputs_and_defaults_are_those_of_the_spec(disc):
    variables = {v.name: v for v in disc.md.modelVariables if v.causality == "output"}
    outputs = set(variables)
    # the spec's outputs, the self-locking flag (see the FMU's documentation), the split of
    # shaft.tau a main-shaft drive couples with (docs/machines.md) and the outputs of the
    # elastodynamic level (dynamics.md; each says so in its description)
    known = SPEC_OUTPUTS | {"sliders.locked", "shaft.tau0", "shaft.J_red"}
    extra = {n for n in outputs - known if "elastodynamic" not in (variables[n].description or "")}
    assert known <= outputs and not extra, sorted(extra)
    assert disc.vars["knife.working"].type == "Boolean"
    assert disc.vars["assembly.branch"].type == "Integer"
    assert disc.vars["kinematics.series"].type == "Boolean"
    p = dk.Params()
    for field, name in dk.Params.NAMES.items():
        assert float(disc.vars[name].start) == pytest.approx(getattr(p, field), rel=1e-15), name
    starts = {"holder.m": 0.8, "slider5.m": 0.3, "slider7.m": 0.2, "rod.m": 0.15, "crank.J": 2e-4,
              "guide.mu": 0.1, "support.mu": 0.1, "cut.F": 150.0, "feed.V": 0.2}
    for name, value in starts.items():
        assert float(disc.vars[name].start) == value, name
    assert float(disc.vars["drive.n"].start) == pytest.approx(W, rel=1e-15)  # 300 rpm


@pytest.mark.parametrize("phi, x_c, beta, sx, sy", [
    (0.0, 57.000, 58.002, 62.829, 9.329),
    (PI / 2, 32.909, 11.679, 43.681, 2.227),
    (PI, 19.000, -40.122, 27.411, -7.089),
])
def test_spec_reference_values(disc, phi, x_c, beta, sx, sy):
    out = disc.probe([(phi, W, 0.0)], ["slider.x", "holder.beta", "knife.x", "knife.y"])
    assert printed(out["slider.x"][0] * 1e3, x_c, 3), out["slider.x"][0]
    assert printed(math.degrees(out["holder.beta"][0]), beta, 3), out["holder.beta"][0]
    assert printed(out["knife.x"][0] * 1e3, sx, 3), out["knife.x"][0]
    assert printed(out["knife.y"][0] * 1e3, sy, 3), out["knife.y"][0]


def test_series_form_reference_value(disc):
    out = disc.probe([(PI / 2, W, 0.0)], ["slider.x"], start_values={"kinematics.series": True})
    assert printed(out["slider.x"][0] * 1e3, 33.250, 3)


def test_fig2_trend(disc):
    """The y-range of S shrinks from alpha = 45 through 55 to 70 deg (spec: 16.4, 10.4, 5.9 mm);
    x of S spans 27.4 to 62.8 mm at 45 deg."""
    ranges = {}
    for alpha, expected in [(45, 16.4), (55, 10.4), (70, 5.9)]:
        out = probe_turn(disc, 7200, ["knife.x", "knife.y"], {"support.alpha": math.radians(alpha)})
        ranges[alpha] = np.ptp(out["knife.y"]) * 1e3
        assert printed(ranges[alpha], expected, 1), (alpha, ranges[alpha])
        if alpha == 45:
            assert printed(out["knife.x"].min() * 1e3, 27.4, 1)
            assert printed(out["knife.x"].max() * 1e3, 62.8, 1)
    assert ranges[45] > ranges[55] > ranges[70]


@pytest.mark.parametrize("changes", [
    {},
    {"assembly.branch": -1},
    {"support.alpha": math.radians(70)},
    {"crank.e": 0.004, "support.alpha": math.radians(60)},
    {"kinematics.series": True},
    {"holder.lS": 0.3, "support.alpha": math.radians(50)},
], ids=["defaults", "branch-1", "alpha70", "offset", "series", "lS0.3"])
def test_kinematics_match_the_numpy_geometry(disc, changes):
    names = ["slider.x", "slider.v", "holder.beta", "support.x", "support.y", "knife.x", "knife.y",
             "knife.vx", "knife.vy"]
    phis = turn(360) + 0.01
    out = disc.probe([(phi, W, 0.0) for phi in phis], names, start_values=changes)
    fields = {v: k for k, v in dk.Params.NAMES.items()}
    p = dk.Params(**{fields[k]: v for k, v in changes.items() if k in fields},
                  branch=changes.get("assembly.branch", 1), series=changes.get("kinematics.series", False))
    ref = dk.evaluate(phis, W, p)
    for n in names:
        scale = np.max(np.abs(ref[n]))
        np.testing.assert_allclose(out[n], ref[n], rtol=0, atol=1e-9 * scale, err_msg=n)


def test_numpy_geometry_is_not_vacuous():
    """The check make_reference.py runs before writing does fail on a wrong model."""
    phi = turn(50)
    good = dk.evaluate(phi, W)
    result = np.zeros(50, dtype=[("shaft.phi", float), ("shaft.w", float), ("knife.x", float), ("knife.y", float)])
    result["shaft.phi"], result["shaft.w"] = phi, W
    result["knife.x"], result["knife.y"] = good["knife.x"], good["knife.y"]
    assert dk.mismatches(result) == []
    result["knife.y"] += 1e-6  # 1 micrometre
    assert dk.mismatches(result)


def test_working_stroke_is_half_the_turn(disc):
    out = probe_turn(disc, 720, ["knife.working", "slider.v", "cut.Fx", "cut.Fy"])
    working = out["knife.working"].astype(bool)
    assert np.array_equal(working, out["slider.v"] > 0)
    assert abs(working.mean() - 0.5) < 0.01
    force = np.hypot(out["cut.Fx"], out["cut.Fy"])
    np.testing.assert_allclose(force[working], 150.0, rtol=1e-12)
    assert np.all(force[~working] == 0.0)


def test_power_balance_without_friction(disc):
    """shaft.P = d(kinetic energy)/dt - power of the cutting force, from the FMU's outputs alone
    (velocity of D and dE/dt by central differences over a fine turn; rod half at the crank pin,
    half at C, as the FMU's documentation says)."""
    n = 7200
    names = ["shaft.P", "slider.v", "knife.vx", "knife.vy", "support.x", "support.y", "cut.Fx", "cut.Fy"]
    out = probe_turn(disc, n, names, {"guide.mu": 0.0, "support.mu": 0.0})
    dphi = 2 * PI / n

    def ddt(x):  # periodic central difference in time at constant speed
        return (np.roll(x, -1) - np.roll(x, 1)) / (2 * dphi) * W

    vdx, vdy = ddt(out["support.x"]), ddt(out["support.y"])
    m5, m7, mh = 0.3 + 0.15 / 2, 0.2, 0.8
    energy = 0.5 * (m5 * out["slider.v"] ** 2 + m7 * (vdx ** 2 + vdy ** 2)
                    + mh * (out["knife.vx"] ** 2 + out["knife.vy"] ** 2))
    cut_power = out["cut.Fx"] * out["knife.vx"] + out["cut.Fy"] * out["knife.vy"]
    balance = ddt(energy) - cut_power
    np.testing.assert_allclose(out["shaft.P"], balance, rtol=0, atol=2e-3 * np.max(np.abs(out["shaft.P"])))
    # and the mean power over the turn is the work of the cutting force
    assert out["shaft.P"].mean() == pytest.approx(-cut_power.mean(), rel=1e-3)


def test_self_locking_is_flagged_where_the_geometry_says(disc):
    out = probe_turn(disc, 3600, ["sliders.locked", "holder.beta"])
    locked = out["sliders.locked"].astype(bool)
    t = np.abs(np.tan(out["holder.beta"] + math.radians(45)))
    assert locked.any()
    assert np.array_equal(locked, t < 0.1)


def test_a_holder_that_cannot_assemble_is_refused(disc):
    fmu = FMU2Slave(guid=disc.md.guid, unzipDirectory=disc.dir,
                    modelIdentifier=disc.md.coSimulation.modelIdentifier, instanceName="bad")
    with captured_log() as log:
        fmu.instantiate(callbacks=callbacks_with(log))
        try:
            fmu.setupExperiment(startTime=0.0)
            fmu.setReal([disc.vars["support.xQ"].valueReference], [0.075])
            fmu.enterInitializationMode()
            with pytest.raises(FMICallException):
                fmu.exitInitializationMode()
            message = log.errors()[-1]
            assert "holder.l4" in message and "crank angles" in message, message
            found = re.search(r"from (-?[0-9.]+) deg to (-?[0-9.]+) deg", message)
            assert found, message
            start, end = (math.radians(float(x)) for x in found.groups())
            # just outside those angles the NumPy geometry assembles, in between it cannot
            dk.evaluate(np.array([start - 1e-3, end + 1e-3]), W, dk.Params(xQ=0.075))
            with pytest.raises(ValueError):
                dk.evaluate(np.array([0.5 * (start + end)]), W, dk.Params(xQ=0.075))
            # corrected, it initializes
            fmu.setReal([disc.vars["support.xQ"].valueReference], [0.060])
            fmu.exitInitializationMode()
            fmu.terminate()
        finally:
            fmu.freeInstance()
