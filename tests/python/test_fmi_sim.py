"""A second FMI host that nobody here wrote: `fmi-sim` 0.7.0 (crates.io; the simulator of the
rust-fmi project, https://github.com/jondo2010/rust-fmi) runs every FMU of out/fmus/ (at every level)
and every scene FMU of out/scenes/ in Co-Simulation and in Model Exchange, and its results equal
FMPy's (`fmpy.simulate_fmu`: same FMU, interface, start values and input file) to the cross-check
tolerance: the RelTol of the model's `fmus/<Model>/<Model>_ref.opt` (1e-6), each value relative to
the larger of itself and its column's magnitude (harness.columns_close). Integer and Boolean outputs
are equal row by row, except that a switch may come one row apart where it falls exactly on a
sample (below); an energy-balance residual is compared on the scale of the work it balances.
A scene without states declares no Model Exchange: both hosts must refuse it.

tests/run installs fmi-sim into .tools/ and names it in the environment variable FMI_SIM. Without
FMI_SIM, .tools/bin/fmi-sim is used when it exists, else the module is skipped; FMI_SIM naming a
missing binary, or another version, fails.

What the two hosts do (fmi-sim's src/sim/ against fmpy/simulation.py), and what differs:

Co-Simulation. fmi-sim sets the start values (--init-values) and the inputs of the start time
right after fmi2Instantiate, then calls fmi2SetupExperiment, fmi2EnterInitializationMode and
fmi2ExitInitializationMode; FMPy sets the start values after fmi2SetupExperiment and the inputs
in initialization mode. Then both record the outputs, set the inputs at t_k (linear
interpolation of the CSV) and call fmi2DoStep(t_k, h): the row at t_k + h holds the outputs after
the step from t_k with the inputs of t_k, whatever the FMU makes of its inputs within the step, so
the comparison holds for any step semantics of the FMU.
Differences, all in the last bits:
- fmi-sim passes the same h (the output interval) to every fmi2DoStep; FMPy passes
  t_{k+1} - t_k with t_k = k*h, which differs from h by up to 1.1e-13 relative (592 of the 600
  steps of 2 ms). Outputs computed at the end of the step (constant_speed scenes, MainShaft, the
  Perforators' contact watch) differ by up to 3e-14; a scene sampling exactly at a switch (the
  table of sewing-table-travel reaches its loading dwell at 282 deg, t = 1.07 s) can switch one
  row apart (table.phase 2 in fmi-sim, 3 in FMPy). An adaptive integrator inside fmi2DoStep turns
  the bits into its own error (solver.method = auto at its default tolerances: 3.3e-4 of
  DiscKnifeDrive's shaft.tau, 0.2 % of elastic.F in the perforators-liftoff-dynamics scene; FMPy
  stepping with a constant h reproduces fmi-sim to the bit). So the elastodynamic level is
  compared with the fixed-step rk4 (FIXED_STEP; solver.max_step below the stiffest chain's limit
  the FMU states), where both hosts take the same internal steps.
- Between samples of the input file fmi-sim interpolates v0 + f*(v1 - v0), FMPy w0*v0 + w1*v1:
  the inputs differ by up to 4e-15 relative where a step falls between samples, the outputs of
  the input-driven scenes by up to 2.2e-13 (geneva-cut-forces, shaft.P).

Model Exchange. fmi-sim integrates with forward Euler, one step per output interval (its --step
option is unused), as does FMPy's solver='Euler' (its step_size only has to divide the output
interval), with the same calls in the same order: x += h*dx, the event indicators (still at the old
time and inputs) against the previous step's, fmi2SetTime, the inputs at the new time,
fmi2CompletedIntegratorStep; state events are handled at the end of the step, not located.
fmi-sim starts its "previous" indicators at 0 instead of reading them, so an indicator positive at
the start makes an event at the first step (an fmi2EnterEventMode/fmi2NewDiscreteStates round that
changes nothing here), and it records the outputs once more before every event: rows with a
repeated time, of which the last (after the event) is compared. Forward Euler is stable at the
kinematic and kinetostatic levels with any step (their states do not move); at the elastodynamic
level only below about 2*zeta/omega of the chain's mode, so those runs take a step per mechanism
(ME_EULER_STEP) over ME_EULER_STEPS steps, after checking that Euler is stable there.
"""

from __future__ import annotations

import csv
import dataclasses
import functools
import os
import re
import subprocess
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest
from fmpy.util import read_csv, read_ref_opt_file

from harness import CROSS_CHECK_DIR, FMU_DIR, MD_DIR, ROOT, Extracted, columns_close, cross_check_paths

VERSION = "0.7.0"
SCENE_DIR = ROOT / "scenes"
SCENE_FMU_DIR = ROOT / "out" / "scenes"
LEVELS = {"kinematic": 1, "kinetostatic": 2, "elastodynamic": 3}
# the elastodynamic level in Co-Simulation: a fixed-step integrator, see the module docstring
FIXED_STEP = {"solver.method": 4, "solver.max_step": 1e-4}
# forward Euler at the elastodynamic level: a step below the chain's stability limit (with the
# cross-check drives and the scenes' speeds), and how many
ME_EULER_STEP = {"GenevaKnifeDrive": 5e-5, "SewingTable": 2e-5, "Perforators": 1e-5, "DiscKnifeDrive": 5e-6}
ME_EULER_STEPS = 4000
# residuals of a balance, compared on the scale of the terms they balance (recorded by FMPy only)
BALANCES = {"elastic.E_residual": "elastic.W"}


@functools.cache
def fmi_sim() -> str:
    """The fmi-sim binary: $FMI_SIM, else .tools/bin/fmi-sim (tests/run installs it there)."""
    path = os.environ.get("FMI_SIM")
    if path is None:
        default = ROOT / ".tools" / "bin" / "fmi-sim"
        if not default.is_file():
            pytest.skip("fmi-sim is not installed: tests/run installs it "
                        f"(cargo install fmi-sim --version {VERSION} --locked --root .tools)")
        path = str(default)
    if not (Path(path).is_file() and os.access(path, os.X_OK)):
        pytest.fail(f"FMI_SIM={path} is not an executable file "
                    f"(cargo install fmi-sim --version {VERSION} --locked --root .tools)")
    # fmi-sim prints its version as an error ("Error: fmi-sim 0.7.0", exit status 1)
    version = subprocess.run([path, "--version"], capture_output=True, text=True)
    found = re.search(r"fmi-sim (\S+)", version.stdout + version.stderr)
    if not found or found.group(1) != VERSION:
        pytest.fail(f"{path} is not fmi-sim {VERSION}: {(version.stdout + version.stderr).strip()[:200]}")
    return path


@dataclass
class Case:
    fmu: Path
    interface: str  # "CoSimulation" | "ModelExchange"
    start_values: dict = field(default_factory=dict)
    input_csv: Path | None = None  # a CSV file both hosts read
    stop: float | None = None  # None: the DefaultExperiment (fmi-sim reads it itself)
    step: float | None = None
    rel_tol: float = 1e-6
    euler_check: bool = False  # elastodynamic ME: check first that forward Euler is stable
    refused: bool = False  # a scene without states declares no Model Exchange: both hosts refuse it


def _has_me(model: str) -> bool:
    return "<ModelExchange" in (MD_DIR / f"{model}.xml").read_text()


def _levels(model: str) -> list[str]:
    """The levels a model has: none (MainShaft), or kinematic and kinetostatic, and elastodynamic
    where it is also Model Exchange (LegacyNeedleDrive is neither)."""
    md = (MD_DIR / f"{model}.xml").read_text()
    if 'name="model.fidelity"' not in md:
        return [""]
    return [lv for lv in LEVELS if lv != "elastodynamic" or _has_me(model)]


def _full_fmu_cases() -> list:
    """Every model with cross-check files, at every level, in CS and ME, with the cross-check inputs."""
    cases = []
    for d in sorted(p for p in CROSS_CHECK_DIR.iterdir() if p.is_dir()):
        model = d.name
        paths = cross_check_paths(model)
        if not paths["opt"].is_file():
            continue
        opt = read_ref_opt_file(str(paths["opt"]))
        for level in _levels(model):
            start = {"model.fidelity": LEVELS[level]} if level else {}
            for interface in ("CoSimulation", "ModelExchange"):
                case = Case(FMU_DIR / f"{model}.fmu", interface, dict(start), paths["in"], opt["StopTime"],
                            opt["StepSize"], opt["RelTol"])
                case.refused = interface == "ModelExchange" and not _has_me(model)
                if level == "elastodynamic" and interface == "CoSimulation":
                    case.start_values.update(FIXED_STEP)
                if level == "elastodynamic" and interface == "ModelExchange":
                    case.step = ME_EULER_STEP[model]
                    case.stop = ME_EULER_STEPS * case.step
                    case.euler_check = True
                name = "-".join(x for x in (model, level, "CS" if interface == "CoSimulation" else "ME") if x)
                cases.append(pytest.param(case, id=name))
    return cases


def _scene_cases() -> list:
    """Every scene of scenes/, in CS and ME, at its DefaultExperiment; inputs as test_scenes.py."""
    cases = []
    for path in sorted(SCENE_DIR.glob("*.toml")):
        scene = tomllib.loads(path.read_text())
        ident = f"{scene['mechanism']}_{scene['name'].replace('-', '_')}"
        opt = read_ref_opt_file(str(cross_check_paths(scene["mechanism"])["opt"]))
        elastic = scene["fidelity"] == "elastodynamic"
        for interface in ("CoSimulation", "ModelExchange"):
            case = Case(SCENE_FMU_DIR / f"{ident}.fmu", interface, rel_tol=opt["RelTol"])
            case.refused = interface == "ModelExchange" and not elastic
            if elastic and interface == "CoSimulation":
                case.start_values.update(FIXED_STEP)
            if elastic and interface == "ModelExchange":
                case.step = ME_EULER_STEP[scene["mechanism"]]
                case.stop = ME_EULER_STEPS * case.step
                case.euler_check = True
            kind = "CS" if interface == "CoSimulation" else "ME"
            cases.append(pytest.param(case, id=f"{path.stem}-{kind}"))
    return cases


def _scene_input(ex: Extracted, stop: float, path: Path) -> Path | None:
    """The inputs of test_scenes.py (a shaft speeding up, a sine load) as a CSV file, or None."""
    names = [v.name for v in ex.md.modelVariables if v.causality == "input"]
    if not names:
        return None
    t = np.linspace(0.0, stop, 201)
    columns = {}
    for n in names:
        columns[n] = {"shaft.phi": 0.4 + 11.0 * t + 3.0 * t * t, "shaft.w": 11.0 + 6.0 * t,
                      "shaft.a": np.full_like(t, 6.0)}.get(n, 25.0 * np.sin(7.0 * t))
    with open(path, "w", newline="\n") as f:
        f.write(",".join(f'"{c}"' for c in ["time"] + names) + "\n")
        for i, ti in enumerate(t):
            f.write(",".join(repr(float(x)) for x in [ti] + [columns[n][i] for n in names]) + "\n")
    return path


def run_fmi_sim(case: Case, out: Path) -> dict[str, np.ndarray]:
    """fmi-sim on the case; its CSV as {column: array} (Booleans as 0/1)."""
    cmd = [fmi_sim(), "--model", str(case.fmu), "-o", str(out)]
    if case.input_csv is not None:
        cmd += ["-i", str(case.input_csv)]
    cmd.append("co-simulation" if case.interface == "CoSimulation" else "model-exchange")
    if case.stop is not None:
        cmd += ["-s", "0.0", "-f", repr(case.stop), "--output-interval", repr(case.step)]
    if case.interface == "CoSimulation":
        cmd += ["--tolerance", repr(case.rel_tol)]  # as FMPy's relative_tolerance (fmi2SetupExperiment)
    for name, value in case.start_values.items():
        cmd += ["--init-values", f"{name}={value!r}"]
    # fmi-sim prints a line per recorded row to stdout; a backtrace on errors with RUST_BACKTRACE
    env = dict(os.environ, RUST_BACKTRACE="0")
    done = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if done.returncode != 0 or not out.is_file():
        pytest.fail(f"fmi-sim failed (status {done.returncode}): {' '.join(cmd)}\n{done.stderr[-3000:]}")
    with open(out, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]

    booleans = {"true": 1.0, "false": 0.0}
    table = np.array([[booleans[s] if s in booleans else float(s) for s in row] for row in body],
                     dtype=float).reshape(len(body), len(header))
    return {name: table[:, i] for i, name in enumerate(header)}


def last_row_per_time(result: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """fmi-sim's Model Exchange rows without the ones recorded before an event (same time, earlier)."""
    t = result["time"]
    keep = np.append(t[1:] != t[:-1], True)
    return {name: column[keep] for name, column in result.items()}


def run_fmpy(ex: Extracted, case: Case, outputs: list[str]) -> np.ndarray:
    de = ex.md.defaultExperiment
    stop = case.stop if case.stop is not None else float(de.stopTime)
    step = case.step if case.step is not None else float(de.stepSize)
    kw = dict(start_time=0.0, stop_time=stop, output_interval=step, start_values=case.start_values,
              output=outputs, fmi_type=case.interface)
    if case.input_csv is not None:
        kw["input"] = read_csv(str(case.input_csv))
    if case.interface == "CoSimulation":
        kw["relative_tolerance"] = case.rel_tol
    else:
        kw.update(solver="Euler", step_size=step, record_events=False)
    return ex.simulate(**kw)


def assert_euler_is_stable(ex: Extracted, case: Case):
    """Forward Euler at case.step: the chain force's peak within 10 % of the FMU's own integrator."""
    kw = dict(start_time=0.0, stop_time=case.stop, output=["elastic.F"], start_values=case.start_values)
    if case.input_csv is not None:
        kw["input"] = read_csv(str(case.input_csv))
    own = ex.simulate(fmi_type="CoSimulation", output_interval=case.step, **kw)
    euler = ex.simulate(fmi_type="ModelExchange", solver="Euler", output_interval=case.step,
                        step_size=case.step, record_events=False, **kw)
    peak_own, peak_euler = np.max(np.abs(own["elastic.F"])), np.max(np.abs(euler["elastic.F"]))
    assert np.all(np.isfinite(euler["elastic.F"])) and abs(peak_euler - peak_own) <= 0.1 * peak_own, (
        f"forward Euler with h = {case.step} s is no step for this chain (peak chain force {peak_euler} N, "
        f"the FMU's integrator {peak_own} N): lower ME_EULER_STEP")


@pytest.mark.parametrize("case", _full_fmu_cases() + _scene_cases())
def test_fmi_sim_equals_fmpy(case: Case, tmp_path):
    if not case.fmu.is_file():
        pytest.fail(f"{case.fmu} is missing: run tests/run (or `cargo run --release -- build` and "
                    "`cargo run --release -- scene`) first")
    binary = fmi_sim()  # skip or fail before any work
    ex = Extracted.of(case.fmu)
    if case.refused:
        assert ex.md.modelExchange is None
        cmd = [binary, "--model", str(case.fmu), "-o", str(tmp_path / "out.csv"), "model-exchange"]
        done = subprocess.run(cmd, capture_output=True, text=True, env=dict(os.environ, RUST_BACKTRACE="0"))
        assert done.returncode != 0 and "ModelExchange not supported" in done.stderr, done.stderr
        with pytest.raises(Exception, match="not supported"):
            ex.simulate(fmi_type="ModelExchange")
        return
    if case.fmu.parent == SCENE_FMU_DIR:
        stop = case.stop if case.stop is not None else float(ex.md.defaultExperiment.stopTime)
        case = dataclasses.replace(case, input_csv=_scene_input(ex, stop, tmp_path / "in.csv"))
    if case.euler_check:
        assert_euler_is_stable(ex, case)
    outputs = ex.outputs(types=("Real", "Integer", "Boolean"))
    balanced = {r: w for r, w in BALANCES.items() if r in outputs}
    reference = run_fmpy(ex, case, outputs + sorted(set(balanced.values())))
    result = run_fmi_sim(case, tmp_path / "out.csv")
    if case.interface == "ModelExchange":
        result = last_row_per_time(result)
    assert sorted(n for n in result if n != "time") == sorted(outputs), "fmi-sim records other columns"
    # the same instants: fmi-sim took the DefaultExperiment where no times were given
    assert len(result["time"]) == len(reference), (len(result["time"]), len(reference))
    np.testing.assert_array_equal(result["time"], reference["time"])
    for name in outputs:
        if name in balanced:
            scale = np.max(np.abs(reference[balanced[name]]))
            np.testing.assert_allclose(result[name], reference[name], rtol=0, atol=case.rel_tol * scale,
                                       err_msg=f"{name} on the scale of {balanced[name]}")
        elif ex.vars[name].type == "Real":
            columns_close(result[name], reference[name], rtol=case.rel_tol, name=name)
        else:
            assert_switches_agree(result[name], reference[name].astype(float), name)


def assert_switches_agree(actual, expected, name):
    """A discrete output equal row by row, except on a row where it switches and the two hosts' end
    times of the step (t_k + h against t_k + (t_{k+1} - t_k)) fall on either side of the switch:
    there fmi-sim's value must be FMPy's of the row before or after (the switch one row apart)."""
    for i in np.flatnonzero(actual != expected):
        neighbours = {expected[j] for j in (i - 1, i + 1) if 0 <= j < len(expected)}
        assert actual[i] in neighbours, (f"{name} row {i}: {actual[i]} (fmi-sim), {expected[i]} (FMPy), "
                                         f"FMPy's rows around it {sorted(neighbours)}")
