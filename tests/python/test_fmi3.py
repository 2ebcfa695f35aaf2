"""The FMI 3.0 FMUs (out/fmus/fmi3/, made by the same `cargo run --release -- build` from the same
binaries and declarations as the FMI 2.0 ones) in the hosts: FMPy validates each (XSD and its
checks) and fmu-manipulation-toolbox finds it compliant with FMI 3.0; FMPy's FMI 3.0
Co-Simulation run of the cross-check inputs equals its FMI 2.0 run bit for bit in every output at
every level; fmi-sim runs each FMI 3.0 FMU and agrees with FMPy to the cross-check tolerance (as
test_fmi_sim.py holds for FMI 2.0); an FMU state taken and serialized through FMPy's FMU3Slave
replays the following steps bit for bit.

fmi-sim 0.7.0 reads FMI 3.0 descriptions with fmi-schema 0.8.0, which knows no `<Enumeration>`
variable and drops them: it runs these FMUs at their default level and cannot set an
enumeration (the level, a motion law), so the levels are compared in FMPy.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.fmi3 import FMU3Slave
from fmpy.util import read_csv, read_ref_opt_file
from fmpy.validation import validate_fmu

from harness import CROSS_CHECK_DIR, FMU_DIR, MD_DIR, Extracted, columns_close, cross_check_paths
from test_all_fmus import run_fmutool_check
from test_fmi_sim import Case, assert_switches_agree, fmi_sim, run_fmi_sim, run_fmpy

FMU3_DIR = FMU_DIR / "fmi3"
MODELS = sorted(p.name for p in CROSS_CHECK_DIR.iterdir() if p.is_dir())
LEVELS = {"kinematic": 1, "kinetostatic": 2, "elastodynamic": 3}


def fmu3(model: str) -> Path:
    path = FMU3_DIR / f"{model}.fmu"
    if not path.is_file():
        pytest.fail(f"{path} is missing: run `cargo run --release -- build` (or tests/run) first")
    return path


def test_every_fmu_has_its_fmi3_twin():
    fmi2 = sorted(p.stem for p in FMU_DIR.glob("*.fmu"))
    assert fmi2 and sorted(p.stem for p in FMU3_DIR.glob("*.fmu")) == fmi2


@pytest.mark.parametrize("model", MODELS)
def test_fmi3_fmu_is_valid(model):
    path = fmu3(model)
    problems = validate_fmu(str(path))
    assert problems == [], problems
    md = read_model_description(str(path))
    assert md.fmiVersion == "3.0" and md.coSimulation is not None
    assert md.instantiationToken == read_model_description(str(FMU_DIR / f"{model}.fmu")).guid
    proc = run_fmutool_check(path)
    out = proc.stdout + proc.stderr
    assert proc.returncode == 0 and "compliant with FMI-3.0" in out and "No semantic error" in out, out


def _levels(model: str) -> list[str]:
    """The levels of a model, from its committed description (as test_fmi_sim.py takes them:
    LegacyNeedleDrive, without Model Exchange, has no elastodynamic level)."""
    md = (MD_DIR / f"{model}.xml").read_text()
    if 'name="model.fidelity"' not in md:
        return [""]
    return [lv for lv in LEVELS if lv != "elastodynamic" or "<ModelExchange" in md]


def _cases():
    return [pytest.param(m, lv, id="-".join(x for x in (m, lv) if x)) for m in MODELS for lv in _levels(m)]


@pytest.mark.parametrize("model,level", _cases())
def test_fmi3_equals_fmi2_bit_for_bit(model, level):
    """FMPy's Co-Simulation loop over the cross-check inputs, FMI 2.0 and FMI 3.0: every output
    equal to the bit, row by row."""
    paths = cross_check_paths(model)
    opt = read_ref_opt_file(str(paths["opt"]))
    ex2, ex3 = Extracted.of(FMU_DIR / f"{model}.fmu"), Extracted.of(fmu3(model))
    outputs = ex2.outputs(types=("Real", "Integer", "Boolean"))
    assert sorted(outputs) == sorted(ex3.outputs(types=("Float64", "Int32", "Boolean")))
    kw = dict(start_time=opt["StartTime"], stop_time=opt["StopTime"], output_interval=opt["StepSize"],
              relative_tolerance=opt["RelTol"], input=read_csv(str(paths["in"])), output=outputs,
              start_values={"model.fidelity": LEVELS[level]} if level else {}, fmi_type="CoSimulation")
    r2, r3 = ex2.simulate(**kw), ex3.simulate(**kw)
    assert len(r2) == len(r3) > 100
    for name in ["time"] + outputs:
        a, b = np.asarray(r2[name], dtype=float), np.asarray(r3[name], dtype=float)
        assert np.array_equal(a.view(np.uint64), b.view(np.uint64)), f"{name}: {a[a != b][:3]} vs {b[a != b][:3]}"


def fmi_sim_case(model: str, interface: str):
    """fmi-sim (installed), the model's FMI 3.0 FMU, its fmi-sim case over the cross-check
    inputs and experiment in `interface`, and the outputs it records."""
    fmi_sim()
    paths = cross_check_paths(model)
    opt = read_ref_opt_file(str(paths["opt"]))
    path = fmu3(model)
    ex = Extracted.of(path)
    case = Case(path, interface, {}, paths["in"], opt["StopTime"], opt["StepSize"], opt["RelTol"])
    return ex, case, ex.outputs(types=("Float64", "Int32", "Boolean"))


@pytest.mark.parametrize("model", MODELS)
def test_fmi_sim_runs_the_fmi3_fmu(model, tmp_path):
    """fmi-sim's FMI 3.0 Co-Simulation of the cross-check inputs agrees with FMPy's (the same
    FMU) to the cross-check tolerance, as for FMI 2.0 in test_fmi_sim.py."""
    ex, case, outputs = fmi_sim_case(model, "CoSimulation")
    result = run_fmi_sim(case, tmp_path / "out.csv")
    assert sorted(n for n in result if n != "time") == sorted(outputs), "fmi-sim records other columns"
    reference = ex.simulate(start_time=0.0, stop_time=case.stop, output_interval=case.step,
                            relative_tolerance=case.rel_tol, input=read_csv(str(case.input_csv)),
                            output=outputs, fmi_type="CoSimulation")
    assert len(result["time"]) == len(reference)
    np.testing.assert_array_equal(result["time"], reference["time"])
    for name in outputs:
        if name.endswith("E_residual"):  # a balance: on the scale of what it balances (none here)
            continue
        if ex.vars[name].type == "Float64":
            columns_close(result[name], reference[name], rtol=case.rel_tol, name=name)
        else:
            assert_switches_agree(result[name], np.asarray(reference[name], dtype=float), name)


@pytest.mark.parametrize("model", MODELS)
def test_fmu3_state_serialized_through_fmpy_replays(model):
    ex = Extracted.of(fmu3(model))
    paths = cross_check_paths(model)
    signals = read_csv(str(paths["in"]))
    inputs = [n for n in signals.dtype.names if n != "time"]
    vr_in = [ex.vars[n].valueReference for n in inputs]
    vr_out = [ex.vars[n].valueReference for n in ex.outputs(types=("Float64",))]
    fmu = FMU3Slave(guid=ex.md.instantiationToken, unzipDirectory=ex.dir,
                    modelIdentifier=ex.md.coSimulation.modelIdentifier, instanceName="state")
    fmu.instantiate()
    try:
        fmu.enterInitializationMode(startTime=0.0)
        fmu.exitInitializationMode()

        def run(k0, n):
            rows = []
            for k in range(k0, k0 + n):
                t, h = signals["time"][k], signals["time"][k + 1] - signals["time"][k]
                fmu.setFloat64(vr_in, [float(signals[x][k]) for x in inputs])
                event, terminate, early, last = fmu.doStep(t, h)
                assert not (event or terminate or early) and last == t + h
                rows.append(fmu.getFloat64(vr_out))
            return np.array(rows)

        run(0, 50)
        state = fmu.getFMUState()
        blob = fmu.serializeFMUState(state)
        first = run(50, 50)
        fmu.setFMUState(state)
        assert np.array_equal(run(50, 50), first)
        fmu.freeFMUState(state)
        state = fmu.deserializeFMUState(blob)
        fmu.setFMUState(state)
        assert np.array_equal(run(50, 50), first)
        fmu.freeFMUState(state)
        fmu.terminate()
    finally:
        fmu.freeInstance()


# --- the scene FMUs (out/scenes/fmi3/, from `cargo run --release -- scene`) ----------------------

SCENE_FMU_DIR = FMU_DIR.parent / "scenes"
SCENES = sorted(p.stem for p in (FMU_DIR.parents[1] / "scenes").glob("*.toml"))


def _scene_fmus(scene: str) -> tuple[Path, Path]:
    import tomllib
    s = tomllib.loads((FMU_DIR.parents[1] / "scenes" / f"{scene}.toml").read_text())
    ident = f"{s['mechanism']}_{s['name'].replace('-', '_')}"
    pair = SCENE_FMU_DIR / f"{ident}.fmu", SCENE_FMU_DIR / "fmi3" / f"{ident}.fmu"
    for p in pair:
        if not p.is_file():
            pytest.fail(f"{p} is missing: run `cargo run --release -- scene` (or tests/run) first")
    return pair


@pytest.mark.parametrize("scene", SCENES)
def test_fmi3_scene_fmu_equals_its_fmi2_twin(scene, tmp_path):
    """A scene's FMI 3.0 FMU: valid, the same variables, FMPy's run equal to the FMI 2.0 one's
    bit for bit (the scene's inputs of test_scenes.py), and fmi-sim runs it."""
    from test_fmi_sim import _scene_input
    p2, p3 = _scene_fmus(scene)
    assert validate_fmu(str(p3)) == []
    ex2, ex3 = Extracted.of(p2), Extracted.of(p3)
    outputs = ex2.outputs(types=("Real", "Integer", "Boolean"))
    assert sorted(outputs) == sorted(ex3.outputs(types=("Float64", "Int32", "Boolean")))
    stop = float(ex2.md.defaultExperiment.stopTime)
    csv_in = _scene_input(ex2, stop, tmp_path / "in.csv")
    kw = dict(output=outputs, fmi_type="CoSimulation")
    if csv_in is not None:
        kw["input"] = read_csv(str(csv_in))
    r2, r3 = ex2.simulate(**kw), ex3.simulate(**kw)
    for name in ["time"] + outputs:
        a, b = np.asarray(r2[name], dtype=float), np.asarray(r3[name], dtype=float)
        assert np.array_equal(a.view(np.uint64), b.view(np.uint64)), name
    fmi_sim()
    case = Case(p3, "CoSimulation", {}, csv_in, None, None, 1e-6)
    result = run_fmi_sim(case, tmp_path / "out.csv")
    assert sorted(n for n in result if n != "time") == sorted(outputs)
    reference = run_fmpy(ex3, case, outputs)
    np.testing.assert_array_equal(result["time"], reference["time"])
    for name in outputs:
        if name.endswith("E_residual"):  # a balance residual, on its own scale: test_fmi_sim.py
            continue
        if ex3.vars[name].type == "Float64":
            columns_close(result[name], reference[name], rtol=case.rel_tol, name=name)
        else:
            assert_switches_agree(result[name], np.asarray(reference[name], dtype=float), name)


# --- events the FMI 3.0 way: FMPy with early return and Event Mode --------------------------------

EVENT_OUTPUTS = {"SewingTable": ["table.phase"], "GenevaKnifeDrive": ["knife.dwell", "knife.in_stack"],
                 "DiscKnifeDrive": ["knife.working"], "LegacyNeedleDrive": ["cam.flank"]}


@pytest.mark.parametrize("model", sorted(EVENT_OUTPUTS))
def test_fmpy_stops_at_the_events_with_early_return(model):
    """FMPy's FMI 3.0 loop with early return and Event Mode (`simulate_fmu(...,
    early_return_allowed=True, use_event_mode=True)`) over the cross-check inputs: the run stops
    at the mechanism's events between its output points (a row off the output grid, where the
    event output has just changed); on the output grid the outputs equal those of the run
    without early return to the cross-check tolerance (the steps are cut at the events). The
    output interval is 1.3 times the cross-check's, so that the events do not fall on output
    points; `roller.F_margin` is left out of the comparison: it is sampled along each
    communication step's path, so it follows where the steps end."""
    paths = cross_check_paths(model)
    opt = read_ref_opt_file(str(paths["opt"]))
    opt["StepSize"] *= 1.3
    ex = Extracted.of(fmu3(model))
    names = EVENT_OUTPUTS[model]
    outputs = names + [n for n in ex.outputs(types=("Float64",))
                       if not n.endswith(("E_residual", "F_margin"))]
    kw = dict(start_time=opt["StartTime"], stop_time=opt["StopTime"], output_interval=opt["StepSize"],
              relative_tolerance=opt["RelTol"], input=read_csv(str(paths["in"])), output=outputs,
              fmi_type="CoSimulation")
    plain = ex.simulate(**kw)
    with_events = ex.simulate(early_return_allowed=True, use_event_mode=True, **kw)
    t = with_events["time"]
    k = t / opt["StepSize"]
    on_grid = np.abs(k - np.round(k)) < 1e-6
    off = np.flatnonzero(~on_grid & (t < t[-1]))
    assert off.size > 0, "no stop between output points"
    e = np.stack([np.asarray(with_events[n], dtype=float) for n in names], axis=1)
    grid_rows = np.flatnonzero(on_grid)
    for i in off:
        # the event output changed since the last output point. FMPy records an event's time
        # twice (after the step, after Event Mode), and where its input at that time (the
        # shaft angle interpolated from the input file) rounds to the old side of the event,
        # the output is back at the old value after Event Mode, and the next step returns at
        # the next floating-point time: the rows within 1e-12 s of this one hold the change.
        j = grid_rows[grid_rows < i][-1]
        near = np.flatnonzero(np.abs(t - t[i]) < 1e-12)
        assert np.any(e[near] != e[j]), f"row {i} at t = {t[i]}: {names} = {e[near]} as at t = {t[j]}"
    # the plain run's instants (the output points and the stop time) are in the run with
    # events too (the first row at each), with the same values to the tolerance
    rows = [int(np.flatnonzero(np.abs(t - tp) < 1e-12)[0]) for tp in plain["time"]]
    grid = with_events[rows]
    for n in outputs[len(names):]:
        columns_close(grid[n], plain[n], rtol=opt["RelTol"], name=n)
    for n in names:
        assert_switches_agree(np.asarray(grid[n], dtype=float), np.asarray(plain[n], dtype=float), n)


# --- terminals and icons -----------------------------------------------------------------------

XSD = (Path(__import__("fmu_manipulation_toolbox").__file__).parent / "resources" / "fmi-3.0"
       / "fmi3TerminalsAndIcons.xsd")


def _terminals(path: Path) -> dict[str, list[tuple[str, str]]]:
    """{terminal: [(member, variable)]} of an FMI 3.0 FMU, its terminalsAndIcons.xml checked
    against the standard's schema."""
    import zipfile
    from lxml import etree
    with zipfile.ZipFile(path) as z:
        xml = z.read("terminalsAndIcons/terminalsAndIcons.xml")
        icon = z.read("terminalsAndIcons/icon.png")
    assert icon.startswith(b"\x89PNG\r\n\x1a\n"), "terminalsAndIcons/icon.png is no PNG"
    schema = etree.XMLSchema(etree.parse(str(XSD)))
    doc = etree.fromstring(xml)
    assert schema.validate(doc), schema.error_log
    return {t.get("name"): [(m.get("memberName"), m.get("variableName")) for m in t.findall("TerminalMemberVariable")]
            for t in doc.iter("Terminal")}


@pytest.mark.parametrize("model", MODELS)
def test_terminals_connect_mechanisms_to_the_main_shaft(model):
    """Every FMI 3.0 FMU has an icon and a valid terminalsAndIcons.xml; a mechanism's `shaft` and
    `shaft_reduced` terminals plug into MainShaft's `load` and `load1` (the same member names,
    the same units, inputs facing outputs), so a host connects them as one connector each."""
    terms = _terminals(fmu3(model))
    drive = _terminals(fmu3("MainShaft"))
    md = read_model_description(str(fmu3(model)))
    dmd = read_model_description(str(fmu3("MainShaft")))
    v = {x.name: x for x in md.modelVariables}
    dv = {x.name: x for x in dmd.modelVariables}
    if model == "MainShaft":
        assert sorted(terms) == ["load", "load1", "load2", "load3"]
        return
    assert sorted(terms) == ["shaft", "shaft_reduced"]
    for mine, theirs in [("shaft", "load"), ("shaft_reduced", "load1")]:
        a, b = dict(terms[mine]), dict(drive[theirs])
        assert sorted(a) == sorted(b), (mine, theirs)
        for member in a:
            x, y = v[a[member]], dv[b[member]]
            assert {x.causality, y.causality} == {"input", "output"}, (member, x.causality, y.causality)
            unit = lambda z: z.declaredType.unit if z.declaredType is not None else z.unit  # noqa: E731
            assert unit(x) == unit(y) and unit(x), (member, unit(x), unit(y))


def test_a_host_connects_by_terminal_alone(tmp_path):
    """MainShaft driving the SewingTable, wired from the terminals only (member by member,
    outputs to inputs, FMI 3.0 both): the shaft runs up towards its synchronous speed and the
    table's torque reaches the drive as load.tau."""
    drive_t, mech_t = _terminals(fmu3("MainShaft"))["load"], _terminals(fmu3("SewingTable"))["shaft"]
    exs = {m: Extracted.of(fmu3(m)) for m in ("MainShaft", "SewingTable")}
    slaves = {}
    for m, ex in exs.items():
        s = FMU3Slave(guid=ex.md.instantiationToken, unzipDirectory=ex.dir,
                      modelIdentifier=ex.md.coSimulation.modelIdentifier, instanceName=m)
        s.instantiate()
        s.enterInitializationMode(startTime=0.0)
        s.exitInitializationMode()
        slaves[m] = s
    vr = {m: {x.name: x.valueReference for x in ex.md.modelVariables} for m, ex in exs.items()}
    caus = {m: {x.name: x.causality for x in ex.md.modelVariables} for m, ex in exs.items()}
    links = []  # (from model, from variable, to model, to variable)
    for (member, dvar), (_, mvar) in zip(sorted(drive_t), sorted(mech_t)):
        if caus["MainShaft"][dvar] == "output":
            links.append(("MainShaft", dvar, "SewingTable", mvar))
        else:
            links.append(("SewingTable", mvar, "MainShaft", dvar))
    assert len(links) == 4
    t, h, speeds, taus = 0.0, 1e-3, [], []
    try:
        for _ in range(1500):
            for src, sv, dst, dvv in links:
                slaves[dst].setFloat64([vr[dst][dvv]], slaves[src].getFloat64([vr[src][sv]]))
            for s in slaves.values():
                s.doStep(t, h)
            t += h
            speeds.append(slaves["MainShaft"].getFloat64([vr["MainShaft"]["shaft.w"]])[0])
            taus.append((slaves["MainShaft"].getFloat64([vr["MainShaft"]["load.tau"]])[0],
                         slaves["SewingTable"].getFloat64([vr["SewingTable"]["shaft.tau"]])[0]))
    finally:
        for s in slaves.values():
            s.terminate()
            s.freeInstance()
    assert speeds[-1] > 5.0 and np.all(np.isfinite(speeds)), speeds[-1]
    # the drive carries the table's torque (a plain torque coupling, one step late)
    received, sent = np.array(taus).T
    assert np.max(np.abs(received)) > 0 and np.max(np.abs(received)) == pytest.approx(np.max(np.abs(sent)), rel=0.05)


# --- reference results inside every FMU (FMI-LS-REF) ---------------------------------------------

LS_REF = "extra/org.fmi-standard.fmi-ls-ref"


@pytest.mark.parametrize("version", ["2.0", "3.0"])
@pytest.mark.parametrize("model", MODELS)
def test_reference_results_inside_the_fmu(model, version, tmp_path):
    """Every FMU (FMI 2.0 and 3.0) carries its reference results in FMI-LS-REF's layout:
    `fmi-ls-manifest.xml` naming `<Model>_out.csv` (role result) and the inputs it ran on. The
    build computed them with the FMU's code, stepping it as a host does (the inputs interpolated
    in FMPy's arithmetic); they equal FMPy's run of the FMU itself over those inputs bit for bit,
    and the committed cross-check result to 1e-9, which the closed-form tests hold against the
    papers."""
    import zipfile
    from lxml import etree
    path = (FMU3_DIR if version == "3.0" else FMU_DIR) / f"{model}.fmu"
    if not path.is_file():
        pytest.fail(f"{path} is missing: run `cargo run --release -- build` (or tests/run) first")
    with zipfile.ZipFile(path) as z:
        manifest = etree.fromstring(z.read(f"{LS_REF}/fmi-ls-manifest.xml"))
        ns = "{http://fmi-standard.org/fmi-ls-manifest}"
        assert manifest.tag == "fmiReferences"
        assert manifest.get(f"{ns}fmi-ls-name") == "org.fmi-standard.fmi-ls-ref"
        related = {r.get("role"): r.get("source") for r in manifest.findall("Related")}
        assert related == {"result": f"{model}_out.csv", "input": f"{model}_in.csv"}
        for name in related.values():
            (tmp_path / name).write_bytes(z.read(f"{LS_REF}/{name}"))
    inside = read_csv(str(tmp_path / f"{model}_out.csv"))
    columns = [n for n in inside.dtype.names if n != "time"]
    paths = cross_check_paths(model)
    opt = read_ref_opt_file(str(paths["opt"]))
    ex = Extracted.of(path)
    host = ex.simulate(start_time=opt["StartTime"], stop_time=opt["StopTime"], output_interval=opt["StepSize"],
                       relative_tolerance=opt["RelTol"], input=read_csv(str(tmp_path / f"{model}_in.csv")),
                       output=columns, fmi_type="CoSimulation")
    committed = read_csv(str(paths["ref"]))
    assert len(inside) == len(host) == len(committed)
    np.testing.assert_allclose(inside["time"], host["time"], rtol=0, atol=1e-12)
    for n in columns:
        a, b = np.asarray(inside[n], dtype=float), np.asarray(host[n], dtype=float)
        assert np.array_equal(a.view(np.uint64), b.view(np.uint64)), f"{n}: {a[a != b][:3]} vs {b[a != b][:3]}"
        columns_close(inside[n], committed[n], rtol=1e-9, name=f"{n} (committed cross-check result)")


# --- Model Exchange ------------------------------------------------------------------------------

ME_MODELS = [m for m in MODELS if "<ModelExchange" in (MD_DIR / f"{m}.xml").read_text()]


@pytest.mark.parametrize("model", ME_MODELS)
def test_fmi3_model_exchange_equals_fmi2(model):
    """FMPy's Model Exchange run (CVode, events located by FMPy) of the cross-check inputs at
    the model's highest level: the FMI 3.0 FMU gives the FMI 2.0 FMU's rows, bit for bit."""
    paths = cross_check_paths(model)
    opt = read_ref_opt_file(str(paths["opt"]))
    ex2, ex3 = Extracted.of(FMU_DIR / f"{model}.fmu"), Extracted.of(fmu3(model))
    assert ex3.md.modelExchange is not None
    assert len(ex3.md.eventIndicators) == ex2.md.numberOfEventIndicators
    outputs = ex2.outputs(types=("Real", "Integer", "Boolean"))
    level = {"model.fidelity": 3} if "model.fidelity" in ex2.vars else {}
    kw = dict(start_time=opt["StartTime"], stop_time=min(opt["StopTime"], 0.3), output_interval=opt["StepSize"],
              relative_tolerance=opt["RelTol"] / 100, input=read_csv(str(paths["in"])), output=outputs,
              start_values=level, fmi_type="ModelExchange")
    r2, r3 = ex2.simulate(**kw), ex3.simulate(**kw)
    assert len(r2) == len(r3) > 30
    for name in ["time"] + outputs:
        a, b = np.asarray(r2[name], dtype=float), np.asarray(r3[name], dtype=float)
        assert np.array_equal(a.view(np.uint64), b.view(np.uint64)), f"{name}: {a[a != b][:3]} vs {b[a != b][:3]}"


def test_fmi_sim_runs_the_fmi3_main_shaft_in_model_exchange(tmp_path):
    """fmi-sim's FMI 3.0 Model Exchange (forward Euler) of MainShaft, whose states move at its
    only level, agrees with FMPy's Euler run of the same FMU to the cross-check tolerance."""
    ex, case, outputs = fmi_sim_case("MainShaft", "ModelExchange")
    from test_fmi_sim import last_row_per_time
    result = last_row_per_time(run_fmi_sim(case, tmp_path / "out.csv"))
    reference = run_fmpy(ex, case, outputs)
    assert len(result["time"]) == len(reference)
    for name in outputs:
        if ex.vars[name].type == "Float64":
            columns_close(result[name], reference[name], rtol=case.rel_tol, name=name)


def assert_reference_inside(path: Path, tmp_path: Path):
    """The FMU at `path` carries reference results (FMI-LS-REF: its default experiment on the
    inputs it lists, none with a constant-speed drive; every Real output it lists), and FMPy's
    run of the FMU over those inputs gives them bit for bit."""
    import zipfile
    ident = path.stem
    with zipfile.ZipFile(path) as z:
        names = z.namelist()
        for f in ("fmi-ls-manifest.xml", f"{ident}_out.csv", f"{ident}_in.csv"):
            assert f"{LS_REF}/{f}" in names, (path, f)
            (tmp_path / f).write_bytes(z.read(f"{LS_REF}/{f}"))
    inside = read_csv(str(tmp_path / f"{ident}_out.csv"))
    columns = [n for n in inside.dtype.names if n != "time"]
    assert columns, path
    ex = Extracted.of(path)
    de = ex.md.defaultExperiment
    stimuli = read_csv(str(tmp_path / f"{ident}_in.csv"))
    kw = dict(start_time=float(de.startTime), stop_time=float(de.stopTime),
              output_interval=float(de.stepSize), output=columns, fmi_type="CoSimulation")
    if len(stimuli.dtype.names) > 1:
        kw["input"] = stimuli
    host = ex.simulate(**kw)
    assert len(inside) == len(host)
    for n in columns:
        a, b = np.asarray(inside[n], dtype=float), np.asarray(host[n], dtype=float)
        assert np.array_equal(a.view(np.uint64), b.view(np.uint64)), f"{ident} {n}"


@pytest.mark.parametrize("scene", SCENES)
def test_reference_results_inside_the_scene_fmus(scene, tmp_path):
    """A scene's FMUs (FMI 2.0 and 3.0) carry reference results too: the scene's default
    experiment on the mechanism's cross-check inputs the scene lists; FMPy reproduces them."""
    for path in _scene_fmus(scene):
        assert_reference_inside(path, tmp_path)


@pytest.mark.parametrize("scene", SCENES)
def test_a_scene_fmu_reads_time_and_only_the_indicators_it_lists(scene):
    """`time` reads as the instance's time; the event indicators read as variables exactly where
    the FMU lists them (Model Exchange), and an FMU that lists none refuses their value
    references."""
    from fmpy.fmi1 import FMICallException
    ex = Extracted.of(_scene_fmus(scene)[1])
    t_vr = ex.vars["time"].valueReference
    listed = [v.valueReference for v in ex.md.modelVariables if v.name.startswith("event.indicator_")]
    fmu = FMU3Slave(guid=ex.md.instantiationToken, unzipDirectory=ex.dir,
                    modelIdentifier=ex.md.coSimulation.modelIdentifier, instanceName="vars")
    fmu.instantiate()
    try:
        fmu.enterInitializationMode(startTime=0.25)
        fmu.exitInitializationMode()
        assert fmu.getFloat64([t_vr]) == [0.25]
        if listed:
            assert len(fmu.getFloat64(listed)) == len(listed)
        else:
            with pytest.raises(FMICallException):
                fmu.getFloat64([t_vr + 1])
    finally:
        fmu.freeInstance()
