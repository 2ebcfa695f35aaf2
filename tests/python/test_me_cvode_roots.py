"""Model Exchange under CVODE's root finding the way fmusim (Reference-FMUs) drives it: one CVODE
memory for the whole run, `CVode(..., CV_NORMAL)` to each output point, the event indicators as
its root functions, and `CVodeReInit` after an event only when the FMU says its continuous
states changed (fmusim's FMI2MESimulation.c / FMICVode.c). FMPy re-initializes CVODE after every
event, which hides an event indicator that rests at zero: after a root return CVODE checks the
indicators at the root and a tiny step later, and aborts with `cvRcheck2: Root found at and very
near t` when one of them is exactly zero at both. Run for every FMU with Model Exchange at the
elastodynamic level, constant speed (`drive.mode` = 2) and driven through its inputs, and for
every scene with Model Exchange, each to its stop time; and through FMPy's own simulate_fmu.

The CVODE is FMPy's bundled SUNDIALS (fmpy.sundials: CVodeCreate, CVodeInit, CVodeRootInit,
CVode, CVodeGetRootInfo), with fmusim's settings: BDF, dense linear solver, relative tolerance
1e-4 (fmusim's default), absolute tolerance nominal times that, CVODE's default step limits.
"""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Model, fmi2Discard
from fmpy.sundials import CVodeSolver

from harness import FMU_DIR, ROOT, Extracted, captured_log, callbacks_with

SCENE_DIR = ROOT / "scenes"
SCENE_FMU_DIR = ROOT / "out" / "scenes"
MECHANISMS = ["GenevaKnifeDrive", "SewingTable", "Perforators", "DiscKnifeDrive"]
RTOL = 1e-4  # fmusim's default without --tolerance


def is_close(a: float, b: float) -> bool:
    """fmusim's FMIIsClose."""
    if not (math.isfinite(a) and math.isfinite(b)):
        return False
    if abs(a - b) <= 1e-13:
        return True
    return abs(a - b) / max(abs(a), abs(b)) <= 1e-13


class ShaftInput:
    """The shaft inputs of `drive.mode` = input, `shaft(t)` = (phi, w, a) (None: no inputs), set
    as fmusim's FMIApplyInput sets a continuous input."""

    def __init__(self, fmu, ex: Extracted, shaft):
        self.fmu, self.shaft = fmu, shaft
        if shaft is not None:
            self.vr = [ex.vars[n].valueReference for n in ("shaft.phi", "shaft.w", "shaft.a")]

    def apply(self, time, continuous=True, discrete=True, after_event=False):
        if self.shaft is not None:
            self.fmu.setReal(self.vr, list(self.shaft(time)))


def constant_speed(w):
    return lambda t: (w * t, w, 0.0)


def run_down(w, t_stop):
    """The shaft braked uniformly from w to a standstill at t_stop, then at rest: every rigid
    speed of the mechanism rests at exactly zero from then on."""
    a = -w / t_stop

    def shaft(t):
        if t < t_stop:
            return (w * t + 0.5 * a * t * t, w + a * t, a)
        return (0.5 * w * t_stop, 0.0, 0.0)
    return shaft


class HostCVode(CVodeSolver):
    """FMPy's CVODE set-up (fmpy.sundials), which fmusim's FMICVode.c equals, with two things
    fmusim does differently and FMI asks for:
    - fmusim sets the inputs only where it evaluates the event indicators, so that its
      right-hand side runs on the inputs of the last root-function call; with a stiff chain that
      is enough to exhaust CVODE's 500 steps (DiscKnifeDrive driven at 300 rpm: `mxstep` at
      t = 4.8 ms). This host sets them for the right-hand side too (no inputs: no difference).
    - fmi2Discard from fmi2GetDerivatives (the states of a Newton iterate outside the model's
      domain) is CVODE's recoverable failure here, a smaller step (FMI 2.0 on fmi2Discard);
      fmusim treats every status above fmi2OK as unrecoverable. Any other failure stops CVODE.
    """

    def f(self, t, y, ydot, user_data):
        # the inputs of time t, set after fmi2SetTime(t) as FMI 2.0 (3.2.3) sets them: the
        # FMU takes them as the shaft at its current time
        self.set_time(t)
        self.input.apply(t)
        try:
            return super().f(t, y, ydot, user_data)
        except FMICallException as e:
            return 1 if e.status == fmi2Discard else -1


def fmusim_cvode(ex: Extracted, start: dict, stop: float, interval: float, shaft=None):
    """fmusim's FMI2MESimulate with its CVODE solver, on the extracted FMU `ex`. Returns the
    counts (output points, state events, re-initializations), the states at `stop` and the
    FMU's log; raises RuntimeError with CVODE's message when CVODE fails."""
    md = ex.md
    fmu = FMU2Model(guid=md.guid, unzipDirectory=ex.dir,
                    modelIdentifier=md.modelExchange.modelIdentifier, instanceName="fmusim")
    with captured_log() as log:
        fmu.instantiate(callbacks=callbacks_with(log), loggingOn=True)
        inp = ShaftInput(fmu, ex, shaft)
        try:
            t = md.defaultExperiment.startTime and float(md.defaultExperiment.startTime) or 0.0
            fmu.setupExperiment(startTime=t)
            ex._set(fmu, start)
            fmu.enterInitializationMode()
            inp.apply(t)
            fmu.exitInitializationMode()
            more = True
            while more:
                more, terminate, *_ = fmu.newDiscreteStates()
                assert not terminate
            fmu.enterContinuousTimeMode()
            nx, nz = md.numberOfContinuousStates, md.numberOfEventIndicators
            solver = HostCVode(nx=nx, nz=nz, get_x=fmu.getContinuousStates,
                                 set_x=fmu.setContinuousStates, get_dx=fmu.getDerivatives,
                                 get_z=fmu.getEventIndicators,
                                 get_nominals=fmu.getNominalsOfContinuousStates,
                                 set_time=fmu.setTime, input=inp, startTime=t,
                                 relativeTolerance=RTOL)
            n_steps = events = resets = 0
            t0 = t
            while not (t > stop or is_close(t, stop)):
                regular = t0 + (n_steps + 1) * interval
                target = stop if regular > stop and not is_close(regular, stop) else regular
                try:
                    state_event, _, t = solver.step(t, target)
                except RuntimeError as e:  # CVODE's message, with what the FMU said
                    raise RuntimeError(f"{e}; the FMU logged: {[m for _, _, m in log][-4:]}")
                fmu.setTime(t)
                inp.apply(t)
                if is_close(t, regular):
                    n_steps += 1
                step_event, terminate = fmu.completedIntegratorStep()
                assert not terminate
                if state_event or step_event:
                    events += 1
                    fmu.enterEventMode()
                    reset, more = False, True
                    while more:
                        more, terminate, nominals, values, *_ = fmu.newDiscreteStates()
                        assert not terminate
                        reset |= nominals or values
                    fmu.enterContinuousTimeMode()
                    if reset:
                        resets += 1
                        solver.reset(t)
            x = np.zeros(max(nx, 1))
            if nx:
                fmu.getContinuousStates(np.ctypeslib.as_ctypes(x), nx)
            fmu.terminate()
            return {"steps": n_steps, "events": events, "resets": resets, "time": t,
                    "x": x[:nx], "log": list(log)}
        finally:
            fmu.freeInstance()


def me_fmus() -> list[str]:
    return [m for m in MECHANISMS + ["MainShaft"] if (FMU_DIR / f"{m}.fmu").is_file()]


def case_of(name: str) -> Extracted:
    path = FMU_DIR / f"{name}.fmu"
    if not path.is_file():
        pytest.fail(f"{path} is missing: run `cargo run --release -- build` first")
    return Extracted.of(path)


def experiment(ex: Extracted) -> tuple[float, float]:
    de = ex.md.defaultExperiment
    return float(de.stopTime), float(de.stepSize)


def elastodynamic(ex: Extracted, mode: int) -> dict:
    if "model.fidelity" not in ex.vars:  # MainShaft: one level, no drive
        return {}
    return {"model.fidelity": 3, "drive.mode": mode}


def nominal_w(ex: Extracted) -> float:
    return float(ex.vars["drive.n"].start)


ALL = MECHANISMS + ["MainShaft"]


@pytest.mark.parametrize("name", ALL)
def test_fmusim_cvode_runs_every_me_fmu_at_constant_speed_to_the_stop_time(name):
    ex = case_of(name)
    stop, interval = experiment(ex)
    r = fmusim_cvode(ex, elastodynamic(ex, 2), stop, interval)
    assert is_close(r["time"], stop), r["time"]
    assert r["steps"] == round(stop / interval)
    assert np.all(np.isfinite(r["x"]))
    assert not [m for s, _, m in r["log"] if s >= 3], r["log"]
    if name != "MainShaft":
        # the mechanisms' events (phase boundaries, velocity reversals) are found, and none
        # changes the continuous states: CVODE runs on without re-initialization
        assert r["events"] >= 2 * stop * nominal_w(ex) / (2 * math.pi), r["events"]
        assert r["resets"] == 0


@pytest.mark.parametrize("name", MECHANISMS)
def test_fmusim_cvode_runs_every_me_fmu_driven_through_its_inputs(name):
    ex = case_of(name)
    stop, interval = experiment(ex)
    r = fmusim_cvode(ex, elastodynamic(ex, 1), stop, interval, constant_speed(nominal_w(ex)))
    assert is_close(r["time"], stop), r["time"]
    assert np.all(np.isfinite(r["x"]))
    assert r["events"] >= 2 * stop * nominal_w(ex) / (2 * math.pi), r["events"]
    assert r["resets"] == 0


@pytest.mark.parametrize("name", MECHANISMS)
def test_fmusim_cvode_runs_every_me_fmu_through_a_shaft_run_down_to_a_standstill(name):
    # every speed of the rigid mechanism reaches zero and stays there: the indicators that are
    # rigid speeds (and the phase ones if the shaft stops on a boundary) rest at zero
    ex = case_of(name)
    stop, interval = experiment(ex)
    w = nominal_w(ex)
    t_stop = 0.5 * stop
    r = fmusim_cvode(ex, elastodynamic(ex, 1), stop, interval, run_down(w, t_stop))
    assert is_close(r["time"], stop), r["time"]
    assert np.all(np.isfinite(r["x"]))
    assert r["events"] > 0 and r["resets"] == 0


def me_scenes():
    out = []
    for path in sorted(SCENE_DIR.glob("*.toml")):
        scene = tomllib.loads(path.read_text())
        if scene["fidelity"] == "elastodynamic":
            out.append(pytest.param(path, scene, id=path.stem))
    return out


@pytest.mark.parametrize("path,scene", me_scenes())
def test_fmusim_cvode_runs_every_me_scene_to_its_stop_time(path, scene):
    fmu = SCENE_FMU_DIR / f"{scene['mechanism']}_{scene['name'].replace('-', '_')}.fmu"
    if not fmu.is_file():
        pytest.fail(f"{fmu} is missing: run `cargo run --release -- scene` first")
    ex = Extracted.of(fmu)
    assert ex.md.modelExchange is not None
    stop, interval = experiment(ex)
    r = fmusim_cvode(ex, {}, stop, interval)
    assert is_close(r["time"], stop), r["time"]
    assert np.all(np.isfinite(r["x"]))
    assert r["events"] > 0 and r["resets"] == 0


@pytest.mark.parametrize("name", MECHANISMS)
def test_fmpy_model_exchange_with_cvode_runs_to_the_stop_time(name):
    ex = case_of(name)
    stop, interval = experiment(ex)
    out = [v.name for v in ex.md.modelVariables if v.name.startswith("elastic.")][:1]
    r = ex.simulate(fmi_type="ModelExchange", solver="CVode", start_time=0.0, stop_time=stop,
                    output_interval=interval, start_values=elastodynamic(ex, 2), output=out)
    assert math.isclose(r["time"][-1], stop)
    assert np.all(np.isfinite(r[out[0]]))
