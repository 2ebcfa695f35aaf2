"""Shared helpers of the FMPy tests and of make_reference.py: where things are, simulating an
FMU with FMPy, evaluating it point by point, and the FMI cross-check files.

A note on timing, which every input-driven comparison here relies on: FMPy's co-simulation loop
(`fmpy.simulation.simulateCS`) sets the inputs interpolated at t_k, calls fmi2DoStep(t_k, h) and
then records the outputs at t_k + h. Over the step the FMU moves its shaft as the inputs of t_k
say (shaft.phi + shaft.w*tau + shaft.a*tau^2/2, at every fidelity level) and leaves its shaft
inputs where that leads, so the row at t_k + h holds the outputs at the end of the step: those of
the input at t_k + h itself wherever the input is a parabola in t over the step (exactly for
phi = w*t). The first row is recorded after initialization with the inputs of t_0. The tests record
the three shaft inputs alongside the outputs and compare every row with the closed form at the
inputs that the FMU held; `check_no_input_lag` asserts that those are the input at the row's own
time, as a Model Exchange run has them.
"""

from __future__ import annotations

import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path

import numpy as np

import fmpy
from fmpy.fmi2 import FMU2Slave
from fmpy.model_description import read_model_description
from fmpy.util import read_csv, read_ref_opt_file

ROOT = Path(__file__).resolve().parents[2]
FMU_DIR = ROOT / "out" / "fmus"
MD_DIR = ROOT / "modelDescription"
CROSS_CHECK_DIR = ROOT / "fmus"

SHAFT_INPUTS = ["shaft.phi", "shaft.w", "shaft.a"]


# --- FMU log messages -----------------------------------------------------------------------------
# FMPy formats the FMU's printf-style messages in a native proxy (fmpy/logging) that keeps ONE
# global Python logger, replaced by every custom logger (also simulate_fmu(logger=...)). Instances
# made later with FMPy's default callbacks then call that last logger; if it has been garbage
# collected the process segfaults. So every logger made here is kept alive for the whole process,
# and after each use the global proxy is pointed back at FMPy's printing logger.

_ALIVE: list = []
_PRINTING_LOGGER = None


def restore_default_logger():
    """Points FMPy's global logger proxy back at printing (fmpy.fmi1.printLogMessage)."""
    global _PRINTING_LOGGER
    from ctypes import byref
    from fmpy.fmi1 import printLogMessage
    from fmpy.fmi2 import fmi2CallbackFunctions, fmi2CallbackLoggerTYPE
    from fmpy.logging import addLoggerProxy
    if _PRINTING_LOGGER is None:
        _PRINTING_LOGGER = fmi2CallbackLoggerTYPE(printLogMessage)
    functions = fmi2CallbackFunctions()
    functions.logger = _PRINTING_LOGGER
    addLoggerProxy(byref(functions))
    _ALIVE.append(functions)


class LogCapture(list):
    """An FMI 2.0 logger callback that records (status, category, message) with str fields."""

    def __call__(self, env, instance, status, category, message):
        self.append((status, (category or b"").decode(errors="replace"), (message or b"").decode(errors="replace")))

    def errors(self) -> list[str]:
        return [m for status, _, m in self if status >= 3]


@contextmanager
def captured_log():
    """A LogCapture to pass as simulate_fmu(logger=...) or to callbacks_with(); kept alive, and
    FMPy's logger proxy restored afterwards."""
    log = LogCapture()
    _ALIVE.append(log)
    try:
        yield log
    finally:
        restore_default_logger()


def callbacks_with(logger):
    """fmi2CallbackFunctions whose logger is `logger` (formatted by FMPy's proxy), kept alive."""
    from ctypes import byref
    from fmpy import calloc, free
    from fmpy.fmi2 import (fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                           fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)
    from fmpy.logging import addLoggerProxy
    callbacks = fmi2CallbackFunctions()
    callbacks.logger = fmi2CallbackLoggerTYPE(logger)
    callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
    callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
    addLoggerProxy(byref(callbacks))
    _ALIVE.append((logger, callbacks))
    return callbacks


def fmu_paths() -> list[Path]:
    """Every FMU the build wrote, sorted."""
    return sorted(FMU_DIR.glob("*.fmu"))


def model_id(fmu: Path) -> str:
    return fmu.stem


class Extracted:
    """An FMU extracted once (simulate_fmu accepts the folder: no unzip per simulation)."""

    _cache: dict[Path, "Extracted"] = {}

    def __init__(self, fmu: Path):
        self.fmu = Path(fmu)
        self.dir = fmpy.extract(str(self.fmu), tempfile.mkdtemp(prefix=f"{self.fmu.stem}-"))
        self.md = read_model_description(self.dir)
        self.vars = {v.name: v for v in self.md.modelVariables}

    @classmethod
    def of(cls, fmu: Path) -> "Extracted":
        key = Path(fmu).resolve()
        if key not in cls._cache:
            cls._cache[key] = cls(key)
        return cls._cache[key]

    @classmethod
    def cleanup(cls):
        for e in cls._cache.values():
            shutil.rmtree(e.dir, ignore_errors=True)
        cls._cache.clear()

    def outputs(self, types=("Real",)) -> list[str]:
        return [v.name for v in self.md.modelVariables if v.causality == "output" and v.type in types]

    def simulate(self, **kwargs):
        """fmpy.simulate_fmu on the extracted folder (same keywords)."""
        kwargs.setdefault("model_description", self.md)
        return fmpy.simulate_fmu(self.dir, **kwargs)

    def probe(self, points, outputs, start_values=None, logger=None):
        """The FMU as a function: for each (phi, w, a) set the shaft inputs, read `outputs`, then
        do one step of 1e-3 s (which watches the shaft's path from there: lift-off warnings).
        Returns {name: array}. Uses FMU2Slave directly, no interpolation."""
        vr = {n: self.vars[n].valueReference for n in SHAFT_INPUTS}
        fmu = FMU2Slave(guid=self.md.guid, unzipDirectory=self.dir,
                        modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName="probe")
        fmu.instantiate(callbacks=None if logger is None else callbacks_with(logger))
        try:
            fmu.setupExperiment(startTime=0.0)
            self._set(fmu, start_values or {})
            fmu.enterInitializationMode()
            fmu.exitInitializationMode()
            out = {n: [] for n in outputs}
            t, h = 0.0, 1e-3
            for phi, w, a in points:
                fmu.setReal([vr["shaft.phi"], vr["shaft.w"], vr["shaft.a"]], [phi, w, a])
                for n in outputs:
                    v = self.vars[n]
                    if v.type == "Real":
                        out[n].append(fmu.getReal([v.valueReference])[0])
                    elif v.type == "Boolean":
                        out[n].append(fmu.getBoolean([v.valueReference])[0])
                    else:
                        out[n].append(fmu.getInteger([v.valueReference])[0])
                fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
                t += h
            fmu.terminate()
            return {n: np.array(x) for n, x in out.items()}
        finally:
            fmu.freeInstance()
            if logger is not None:
                restore_default_logger()

    def get_after_init(self, names, start_values=None):
        """Values of `names` (Real) right after initialization, e.g. calculated parameters."""
        fmu = FMU2Slave(guid=self.md.guid, unzipDirectory=self.dir,
                        modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName="init")
        fmu.instantiate()
        try:
            fmu.setupExperiment(startTime=0.0)
            self._set(fmu, start_values or {})
            fmu.enterInitializationMode()
            fmu.exitInitializationMode()
            values = fmu.getReal([self.vars[n].valueReference for n in names])
            fmu.terminate()
            return dict(zip(names, values))
        finally:
            fmu.freeInstance()

    def _set(self, fmu, start_values):
        for name, value in start_values.items():
            v = self.vars[name]
            if v.type == "Real":
                fmu.setReal([v.valueReference], [float(value)])
            elif v.type == "Boolean":
                fmu.setBoolean([v.valueReference], [bool(value)])
            else:  # Integer, Enumeration
                fmu.setInteger([v.valueReference], [int(value)])


def shaft_input(t, phi, w, a) -> np.ndarray:
    """A structured input array for simulate_fmu (the FMI cross-check CSV layout)."""
    t = np.asarray(t, dtype=float)
    sig = np.zeros(t.shape, dtype=[("time", np.float64)] + [(n, np.float64) for n in SHAFT_INPUTS])
    sig["time"] = t
    sig["shaft.phi"] = phi
    sig["shaft.w"] = w
    sig["shaft.a"] = a
    return sig


def constant_speed_input(stop_time: float, speed: float, n: int = 2) -> np.ndarray:
    """phi = speed*t, w = speed, a = 0 on [0, stop_time]: linear, so FMPy's interpolation is exact."""
    t = np.linspace(0.0, stop_time, n)
    return shaft_input(t, speed * t, np.full_like(t, speed), np.zeros_like(t))


def check_no_input_lag(result, phi_of_t, rtol=1e-12, atol=1e-12):
    """Asserts that the recorded shaft.phi is phi_of_t at the row's own time: after
    fmi2DoStep(t_k, h) the FMU is at t_k + h (see the module docstring)."""
    np.testing.assert_allclose(result["shaft.phi"], phi_of_t(result["time"]), rtol=rtol, atol=atol,
                               err_msg="recorded shaft.phi is not the input at the row's time")


def columns_close(actual, expected, rtol=1e-9, name=""):
    """Every value within rtol, relative to the larger of the value and the column's magnitude
    (so a column crossing zero is compared on its own scale)."""
    actual = np.asarray(actual, dtype=float)
    expected = np.asarray(expected, dtype=float)
    scale = max(float(np.max(np.abs(expected))) if expected.size else 0.0, 1e-300)
    np.testing.assert_allclose(actual, expected, rtol=rtol, atol=rtol * scale, err_msg=name)


# --- FMI cross-check files ----------------------------------------------------------------------

def cross_check_paths(mid: str) -> dict[str, Path]:
    d = CROSS_CHECK_DIR / mid
    return {"in": d / f"{mid}_in.csv", "ref": d / f"{mid}_ref.csv", "opt": d / f"{mid}_ref.opt"}


def simulate_cross_check(ex: Extracted, paths: dict[str, Path], outputs: list[str], extra=(),
                         fmi_type="CoSimulation", relative_tolerance=None):
    """Simulate as the FMI cross-check rules say: inputs from _in.csv, times and the relative
    tolerance from _ref.opt (unless given: in Model Exchange, that of the host's solver, CVode)."""
    opt = read_ref_opt_file(str(paths["opt"]))
    signals = read_csv(str(paths["in"]))
    if relative_tolerance is None:
        relative_tolerance = opt["RelTol"]
    return ex.simulate(start_time=opt["StartTime"], stop_time=opt["StopTime"],
                       output_interval=opt["StepSize"], relative_tolerance=relative_tolerance,
                       fmi_type=fmi_type, input=signals, output=list(outputs) + list(extra))


def write_ref_opt(path: Path, start: float, stop: float, step: float, rel_tol: float):
    path.write_text(f"StartTime, {start!r}\nStopTime, {stop!r}\nStepSize, {step!r}\nRelTol, {rel_tol!r}\n")


def write_csv(path: Path, table: np.ndarray, columns: list[str]):
    """CSV as the cross-check rules want it: quoted header, `time` first, full precision."""
    with open(path, "w", newline="\n") as f:
        f.write(",".join(f'"{c}"' for c in ["time"] + columns) + "\n")
        for row in table:
            f.write(",".join(repr(float(row[c])) for c in ["time"] + columns) + "\n")


