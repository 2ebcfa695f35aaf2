"""Exact partial derivatives through FMPy, a host other than our own: every FMU whose model
description says providesDirectionalDerivative="true" gives, through FMPy's
getDirectionalDerivative (FMI 2.0 Co-Simulation and Model Exchange at every fidelity level, FMI
3.0 Co-Simulation, and FMI 3.0's getAdjointDerivative), the Jacobian that central differences of
its own values give; every FMU offers them."""

from __future__ import annotations

import xml.etree.ElementTree as ET
import zipfile
from ctypes import c_double

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.fmi2 import FMU2Model, FMU2Slave
from fmpy.fmi3 import FMU3Slave

from harness import FMU_DIR, Extracted, fmu_paths

FMU3_DIR = FMU_DIR / "fmi3"


def offering() -> list[str]:
    return [p.stem for p in fmu_paths()
            if read_model_description(str(p)).coSimulation.providesDirectionalDerivative]


def test_the_descriptions_say_which_fmus_offer_partials():
    # every FMU, in both versions
    assert set(offering()) == {p.stem for p in fmu_paths()} == {
        "MainShaft", "SewingTable", "Perforators", "LegacyNeedleDrive", "GenevaKnifeDrive",
        "DiscKnifeDrive"}
    for p in fmu_paths():
        md = read_model_description(str(p))
        flags = {md.coSimulation.providesDirectionalDerivative}
        if md.modelExchange is not None:
            flags.add(md.modelExchange.providesDirectionalDerivative)
        assert len(flags) == 1, p.stem
        # FMI 3.0 (read from the XML: FMPy keeps only the adjoint flag of the two)
        with zipfile.ZipFile(FMU3_DIR / p.name) as z:
            root = ET.fromstring(z.read("modelDescription.xml"))
        for tag in ("CoSimulation", "ModelExchange"):
            for e in root.findall(tag):
                assert e.get("providesDirectionalDerivatives") == e.get("providesAdjointDerivatives"), p.stem
                assert (e.get("providesDirectionalDerivatives") == "true") == next(iter(flags)), p.stem


def _levels(model):
    """(model, level) for every `model.fidelity` level (None for an FMU without one)."""
    md = read_model_description(str(FMU_DIR / f"{model}.fmu"))
    has = any(v.name == "model.fidelity" for v in md.modelVariables)
    return [(model, level) for level in ((1, 2, 3) if has else (None,))]


def _set_level(fmu, md, level):
    """Sets `model.fidelity` before initialization; skips a level the FMU refuses (it says so
    at initialization: LegacyNeedleDrive has no elastodynamic level)."""
    if level is None:
        return
    vr = next(v.valueReference for v in md.modelVariables if v.name == "model.fidelity")
    fmu.setInteger([vr], [level])


def _initialize(fmu, model, level):
    try:
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
    except Exception as e:  # FMPy raises on fmi2Error: this FMU has no such level
        fmu.freeInstance()
        pytest.skip(f"{model} refuses model.fidelity = {level}: {e}")


def _knowns_unknowns(md):
    inputs = [v for v in md.modelVariables if v.causality == "input" and v.type in ("Real", "Float64")]
    outputs = [v for v in md.modelVariables if v.causality == "output" and v.type in ("Real", "Float64")
               and v.variability == "continuous"]
    return inputs, outputs


def _excited(values):
    return [v if v != 0.0 else 3.0 + i for i, v in enumerate(values)]


def _assert_close(exact, fd, what):
    """The exact column against central differences `fd = (d, magnitude, h)`: within 1e-6 of
    the column's scale, plus the differences' rounding error, 1e-14 of the value over h."""
    d, mag, h = fd
    exact = np.asarray(exact)
    scale = np.maximum(np.maximum(np.abs(exact), np.abs(d)), 1e-3)
    bad = np.abs(exact - d) > 1e-6 * scale + 1e-14 * mag / h
    assert not bad.any(), f"{what}: exact {exact[bad]}, central differences {d[bad]}"


def _central(set_known, get_unknowns, x0, i, step=1e-5):
    h = step * max(abs(x0[i]), 1.0)
    up, down = list(x0), list(x0)
    up[i] += h
    down[i] -= h
    set_known(up)
    a = np.asarray(get_unknowns())
    set_known(down)
    b = np.asarray(get_unknowns())
    set_known(x0)
    return (a - b) / (2 * h), np.maximum(np.abs(a), np.abs(b)), h


def _cs2_turning(ex, kr, steps, level=None):
    """An FMI 2.0 Co-Simulation instance at `level` after `steps` steps of 10 ms with its inputs
    `kr` away from zero (a load on the drive): the instance and those inputs."""
    fmu = FMU2Slave(guid=ex.md.guid, unzipDirectory=ex.dir,
                    modelIdentifier=ex.md.coSimulation.modelIdentifier, instanceName="cs")
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    _set_level(fmu, ex.md, level)
    _initialize(fmu, ex.md.modelName, level)
    x0 = _excited(fmu.getReal(kr))
    fmu.setReal(kr, x0)
    for k in range(steps):
        fmu.doStep(currentCommunicationPoint=k * 1e-2, communicationStepSize=1e-2)
    return fmu, x0


def _check_co_simulation(path, level, what):
    ex = Extracted.of(path)
    inputs, outputs = _knowns_unknowns(ex.md)
    kr = [v.valueReference for v in inputs]
    ur = [v.valueReference for v in outputs]
    fmu, x0 = _cs2_turning(ex, kr, 50, level)
    # the inputs set now: the shaft's instant is now, for the columns as for the differences
    fmu.setReal(kr, x0)
    for i, v in enumerate(inputs):
        exact = fmu.getDirectionalDerivative(ur, [kr[i]], [1.0])
        fd = _central(lambda x: fmu.setReal(kr, x), lambda: fmu.getReal(ur), x0, i)
        _assert_close(exact, fd, f"{what} CS d/d{v.name}")
    fmu.terminate()
    fmu.freeInstance()


@pytest.mark.parametrize("model,level", [ml for m in offering() for ml in _levels(m)])
def test_co_simulation_partials_through_fmpy_equal_central_differences(model, level):
    _check_co_simulation(FMU_DIR / f"{model}.fmu", level, f"{model} (level {level})")


SCENE_FMUS = sorted((FMU_DIR.parent / "scenes").glob("*.fmu"))


def test_every_scene_is_built_for_the_partials_test():
    # one tailored FMU per example scene (`tests/run` builds them before pytest)
    assert len(SCENE_FMUS) == len(list((FMU_DIR.parents[1] / "scenes").glob("*.toml")))


@pytest.mark.parametrize("path", SCENE_FMUS, ids=[p.stem for p in SCENE_FMUS])
def test_tailored_fmus_give_the_partials_of_what_they_keep(path):
    """An FMU tailored to a scene (its level and stages fixed, variables left out) offers the
    derivatives of the outputs it keeps, equal to central differences."""
    assert read_model_description(str(path)).coSimulation.providesDirectionalDerivative
    _check_co_simulation(path, None, path.stem)


@pytest.mark.parametrize("model,level", [ml for m in offering()
                                         if read_model_description(str(FMU_DIR / f"{m}.fmu")).modelExchange
                                         for ml in _levels(m)])
def test_model_exchange_partials_through_fmpy_equal_central_differences(model, level):
    ex = Extracted.of(FMU_DIR / f"{model}.fmu")
    md = ex.md
    inputs, outputs = _knowns_unknowns(md)
    states = [d.variable.derivative for d in md.derivatives]
    ders = [d.variable for d in md.derivatives]
    fmu = FMU2Model(guid=md.guid, unzipDirectory=ex.dir,
                    modelIdentifier=md.modelExchange.modelIdentifier, instanceName="me")
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    _set_level(fmu, md, level)
    _initialize(fmu, model, level)
    fmu.newDiscreteStates()
    fmu.enterContinuousTimeMode()
    kr = [v.valueReference for v in inputs]
    u0 = _excited(fmu.getReal(kr))
    fmu.setReal(kr, u0)
    nx = len(states)
    x = (c_double * nx)()
    fmu.getContinuousStates(x, nx)
    # the drive at some speed; a mechanism's chain a little off its equilibrium (its stiffness
    # makes a larger deflection a different machine), and the differences' step to that scale
    offset, step = (1.0, 1e-5) if level is None else (1e-6, 1e-8)
    x0 = [float(v) + offset * (1.0 + 2.0 * i) * max(abs(float(v)), 1.0) for i, v in enumerate(x)]
    fmu.setContinuousStates((c_double * nx)(*x0), nx)
    unknowns = [d.valueReference for d in ders] + [v.valueReference for v in outputs]

    def values():
        dx = (c_double * nx)()
        fmu.getDerivatives(dx, nx)
        return list(dx) + list(fmu.getReal([v.valueReference for v in outputs]))

    for i, s in enumerate(states):
        exact = fmu.getDirectionalDerivative(unknowns, [s.valueReference], [1.0])
        fd = _central(lambda x: fmu.setContinuousStates((c_double * nx)(*x), nx), values, x0, i,
                      step)
        _assert_close(exact, fd, f"{model} (level {level}) ME d/d{s.name}")
    for i, v in enumerate(inputs):
        exact = fmu.getDirectionalDerivative(unknowns, [kr[i]], [1.0])
        fd = _central(lambda x: fmu.setReal(kr, x), values, u0, i)
        _assert_close(exact, fd, f"{model} (level {level}) ME d/d{v.name}")
    fmu.terminate()
    fmu.freeInstance()


@pytest.mark.parametrize("model", offering())
def test_fmi3_directional_and_adjoint_derivatives_through_fmpy_are_one_jacobian(model):
    ex = Extracted.of(FMU3_DIR / f"{model}.fmu")
    inputs, outputs = _knowns_unknowns(ex.md)
    kr = [v.valueReference for v in inputs]
    ur = [v.valueReference for v in outputs]
    fmu = FMU3Slave(guid=ex.md.instantiationToken, unzipDirectory=ex.dir,
                    modelIdentifier=ex.md.coSimulation.modelIdentifier, instanceName="cs3")
    fmu.instantiate()
    fmu.enterInitializationMode(startTime=0.0)
    fmu.exitInitializationMode()
    fmu.setFloat64(kr, _excited(fmu.getFloat64(kr)))
    for k in range(20):
        fmu.doStep(currentCommunicationPoint=k * 1e-2, communicationStepSize=1e-2)
    columns = np.array([fmu.getDirectionalDerivative(ur, [k], [1.0]) for k in kr]).T
    # (FMPy sizes the sensitivity by the unknowns unless told: FMI 3.0 has one per known)
    rows = np.array([fmu.getAdjointDerivative([u], kr, [1.0], nSensitivity=len(kr)) for u in ur])
    assert np.array_equal(columns, rows), model
    # and FMI 2.0's twin gives the same Jacobian at the same point
    fmu2, _ = _cs2_turning(Extracted.of(FMU_DIR / f"{model}.fmu"), kr, 20)
    columns2 = np.array([fmu2.getDirectionalDerivative(ur, [k], [1.0]) for k in kr]).T
    assert np.array_equal(columns, columns2), model
    for f in (fmu, fmu2):
        f.terminate()
        f.freeInstance()
