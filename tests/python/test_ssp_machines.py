"""The two machines as SSP 1.0 files (`cargo run --release -- ssp`, out/ssp/), run as exported with
FMPy 0.3.32's `fmpy.ssp.simulate_ssp`: a fixed-step master that steps every FMU with the inputs of
the previous communication point, then applies the connections.

That function reads the SSD's parameter binding but sets only a `parameter_set` handed to it, and it
does not read the `DefaultExperiment` (without arguments it runs 1 s in steps of 10 ms). So the
machine's values are the start values of FMUs tailored to it, and these tests pass no parameters:
- with no arguments at all, each machine runs its first second as the machine it is;
- over the SSD's own experiment (its stop time, the step of its fixed-step master), the run equals
  the catalog FMUs run by hand with the SSD's parameter binding, and gives the figures of
  docs/machines.md (computed there by the Rust models under the same master);
- the SSD is valid SSP 1.0 (the schema FMPy ships), and a designer finds the forces, the shaft
  torques and the motor's torque, speed and power in the result.
"""

from __future__ import annotations

import math
import re
import zipfile
from functools import lru_cache
from pathlib import Path

import fmpy
import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.ssp.simulation import simulate_ssp
from fmpy.ssp.ssd import read_ssd
from lxml import etree

ROOT = Path(__file__).resolve().parents[2]
SSP_DIR = ROOT / "out" / "ssp"
FMU_DIR = ROOT / "out" / "fmus"
SCHEMA = Path(fmpy.__file__).parent / "ssp" / "schema" / "SystemStructureDescription.xsd"
NS = {
    "ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
    "ssc": "http://ssp-standard.org/SSP1/SystemStructureCommon",
    "oms": "https://raw.githubusercontent.com/OpenModelica/OMSimulator/master/schema/oms.xsd",
}
MACHINES = ["ThreadSewingMachine", "ThreeKnifeTrimmer", "ThreadSewingMachineLegacy"]
RPM = math.pi / 30

# what a designer reads of each component: main forces, shaft torque; the drive's motor
DESIGNER = {
    "drive": ["shaft.w", "motor.tau", "motor.w", "motor.P", "shaft.tau_load"],
    "table": ["table.x", "cam.F", "cam.sigma_H", "table.F_inertia", "shaft.tau"],
    "perforators": ["perforators.s", "rod.F", "roller.F", "pierce.Q_T", "table.F", "shaft.tau"],
    "needles": ["perforators.s", "rod.F", "roller.F", "roller.sigma_H", "pierce.Q_T", "shaft.tau"],
    "side_left": ["knife.s", "rod.F", "knife.F_cut", "geneva.F", "shaft.tau"],
    "side_right": ["knife.s", "rod.F", "knife.F_cut", "geneva.F", "shaft.tau"],
    "front": ["knife.s", "rod.F", "knife.F_cut", "geneva.F", "shaft.tau"],
}


def ssp(name: str) -> Path:
    path = SSP_DIR / f"{name}.ssp"
    if not path.is_file():
        pytest.fail(f"{path} is missing: run `cargo run --release -- build` and `cargo run --release -- ssp`")
    return path


def ssd_tree(path: Path):
    with zipfile.ZipFile(path) as z:
        return etree.fromstring(z.read("SystemStructure.ssd"))


def experiment(path: Path) -> tuple[float, float]:
    """The SSD's stop time and the step of its fixed-step master (OMSimulator's annotation)."""
    root = ssd_tree(path)
    stop = float(root.find("ssd:DefaultExperiment", NS).get("stopTime"))
    master = root.find(
        "ssd:System/ssd:Annotations/ssc:Annotation/oms:Annotations/oms:SimulationInformation/oms:FixedStepMaster", NS
    )
    return stop, float(master.get("stepSize"))


def start_value(path: Path, component: str, variable: str) -> float:
    """The start value of a variable in the FMU a component of the SSP is."""
    source = ssd_tree(path).find(f"ssd:System/ssd:Elements/ssd:Component[@name='{component}']", NS).get("source")
    with zipfile.ZipFile(path) as z, z.open(source) as f:
        md = read_model_description(f, validate=False)
    return float(next(v.start for v in md.modelVariables if v.name == variable))


@lru_cache(maxsize=None)
def run(name: str):
    """The machine over the SSD's own experiment, no parameters passed."""
    path = ssp(name)
    stop, step = experiment(path)
    return simulate_ssp(str(path), stop_time=stop, step_size=step)


def by_hand(name: str, tmp: Path):
    """The same system with the catalog FMUs (out/fmus/) in place of the tailored ones, run with the
    SSD's parameter binding as FMPy's parameter_set: how the machine ran before it carried its own
    values."""
    path = ssp(name)
    with zipfile.ZipFile(path) as z:
        ssd = z.read("SystemStructure.ssd").decode()
    # resources/<catalog id>_<machine>_<component>.fmu -> resources/<catalog id>.fmu
    ssd, n = re.subn(rf'source="resources/(\w+?)_{name}_\w+\.fmu"', r'source="resources/\1.fmu"', ssd)
    ids = sorted(set(re.findall(r'source="resources/(\w+)\.fmu"', ssd)))
    assert n >= 3 and ids, ssd
    plain = tmp / f"{name}.ssp"
    with zipfile.ZipFile(plain, "w") as z:
        z.writestr("SystemStructure.ssd", ssd)
        for i in ids:
            fmu = FMU_DIR / f"{i}.fmu"
            if not fmu.is_file():
                pytest.fail(f"{fmu} is missing: run `cargo run --release -- build`")
            z.write(fmu, f"resources/{i}.fmu")
    sets = [ps for b in read_ssd(str(path)).system.parameterBindings for ps in b.parameterValues]
    stop, step = experiment(path)
    return simulate_ssp(str(plain), stop_time=stop, step_size=step, parameter_set=sets[0] if sets else None)


def docs_figures(name: str) -> dict[str, float]:
    """The row of docs/machines.md's table for a machine (computed by `cargo run --release -- machines`
    on the Rust models under the same fixed-step master)."""
    text = (ROOT / "docs" / "machines.md").read_text()
    row = next(line for line in text.splitlines() if line.startswith(f"| {name} |"))
    cells = [c.strip() for c in row.strip("|").split("|")]
    return {
        "rpm": float(cells[2]),
        "delta": float(cells[4].split()[0]),
        "tau_peak": float(cells[6]),
        "tau_rms": float(cells[7]),
    }


def steady_figures(r, turns: float = 4.0) -> dict[str, float]:
    """Running speed, δ = (ω_max − ω_min)/ω_mean and the motor torque's peak and RMS over the last
    whole turns (as `cargo run --release -- machines` takes them)."""
    phi, w, tau = r["drive.shaft.phi"], r["drive.shaft.w"], r["drive.motor.tau"]
    i0 = int(np.argmax(phi >= phi[-1] - turns * 2 * math.pi))
    w, tau = w[i0:], tau[i0:]
    return {
        "rpm": w.mean() / RPM,
        "delta": (w.max() - w.min()) / w.mean(),
        "tau_peak": np.abs(tau).max(),
        "tau_rms": math.sqrt(np.mean(tau**2)),
    }


@pytest.mark.parametrize("name", MACHINES)
def test_the_ssd_is_valid_ssp_1_0_and_names_omsimulators_master(name):
    path = ssp(name)
    root = ssd_tree(path)
    schema = etree.XMLSchema(etree.parse(str(SCHEMA)))
    assert schema.validate(root), schema.error_log
    # OMSimulator 3.0 imports a system only with its vendor annotation: a fixed-step master
    stop, step = experiment(path)
    assert stop > 0 and 0 < step < stop
    master = root.find(".//oms:FixedStepMaster", NS)
    assert master.get("description") == "oms-ma"
    # every component's FMU is in the archive
    with zipfile.ZipFile(path) as z:
        names = set(z.namelist())
    for c in root.iterfind("ssd:System/ssd:Elements/ssd:Component", NS):
        assert c.get("source") in names


def test_the_trimmer_runs_as_the_machine_with_no_arguments():
    # FMPy's defaults: 1 s in steps of 10 ms; the shaft starts at the trimmer's 30 rpm and turns
    # half a turn: the side knives make their stroke, the front knife (half a turn later) rests.
    # Without the machine's drive in its FMU (the catalog's 1.1 kW motor, 1:15 gear, 2 kg.m2
    # flywheel, from rest) the first cut turns the shaft backwards.
    r = simulate_ssp(str(ssp("ThreeKnifeTrimmer")))
    assert r["time"][-1] == pytest.approx(0.99)
    w = r["drive.shaft.w"]
    assert np.all((0.9 * math.pi < w) & (w <= math.pi))
    stroke = 2 * start_value(ssp("ThreeKnifeTrimmer"), "side_left", "crank.r")
    assert r["side_left.knife.s"].max() == pytest.approx(stroke, abs=1e-3)
    assert r["front.knife.s"].max() == 0.0


def test_the_sewing_machine_starts_up_with_no_arguments():
    r = simulate_ssp(str(ssp("ThreadSewingMachine")))
    w = r["drive.shaft.w"]
    assert w[0] < 0.5 * 100 * RPM  # from rest
    assert 0.9 * 100 * RPM < w[-1] < 100 * RPM  # running, just below synchronous by its slip


@pytest.mark.parametrize("name", MACHINES)
def test_the_exported_machine_equals_the_catalog_fmus_run_with_its_parameters(name, tmp_path):
    # same host, same master: the tailored FMUs compute what the catalog FMUs do with the SSD's
    # parameter binding set by hand, to the bit
    r, ref = run(name), by_hand(name, tmp_path)
    assert r.dtype.names == ref.dtype.names
    for k in r.dtype.names:
        np.testing.assert_array_equal(r[k], ref[k], err_msg=k)


@pytest.mark.parametrize("name", MACHINES)
def test_the_machine_gives_the_figures_of_docs_machines_md(name):
    # FMPy on the FMUs against the Rust models under the same master (docs/machines.md's table; its
    # runs start at the nominal speed and last 20 s and 8 s, the SSDs' 12 s and 4 s, the sewing
    # machine's from rest): equal within the table's rounding and 1 % (0.1 % for the speed)
    got, doc = steady_figures(run(name)), docs_figures(name)
    assert got["rpm"] == pytest.approx(doc["rpm"], abs=0.05 + 1e-3 * doc["rpm"])
    assert got["delta"] == pytest.approx(doc["delta"], rel=0.01, abs=5e-5)
    assert got["tau_peak"] == pytest.approx(doc["tau_peak"], rel=0.01, abs=0.05)
    assert got["tau_rms"] == pytest.approx(doc["tau_rms"], rel=0.01, abs=0.05)


def test_the_trimmers_knives_make_their_full_stroke_and_cut_in_turn():
    path = ssp("ThreeKnifeTrimmer")
    r = run("ThreeKnifeTrimmer")
    steady = r["time"] > 8.0
    left, right, front = (r[f"{k}.knife.s"] for k in ("side_left", "side_right", "front"))
    for k in ("side_left", "front"):
        stroke = 2 * start_value(path, k, "crank.r")
        assert r[f"{k}.knife.s"][steady].max() == pytest.approx(stroke, abs=1e-4)
        # the full cutting resistance of the stack, in every cycle
        assert r[f"{k}.knife.F_cut"][steady].max() == pytest.approx(start_value(path, k, "cut.F_max"))
    # the side knives cut together, the front knife half a turn later: never all three at once
    np.testing.assert_array_equal(left, right)
    assert np.max(np.minimum(left, front)[steady]) < 1e-9


@pytest.mark.parametrize("name", MACHINES)
def test_a_designer_reads_forces_shaft_torques_and_the_motor(name):
    r = run(name)
    components = {c.get("name") for c in ssd_tree(ssp(name)).iterfind(".//ssd:Component", NS)}
    for c in components:
        for v in DESIGNER[c]:
            assert f"{c}.{v}" in r.dtype.names, f"{c}.{v}"
            assert np.all(np.isfinite(r[f"{c}.{v}"])), f"{c}.{v}"
    # the motor: power = torque x speed at the motor shaft, speed = gear ratio x shaft speed
    np.testing.assert_allclose(r["drive.motor.P"], r["drive.motor.tau"] * r["drive.motor.w"], rtol=1e-12)
    i = start_value(ssp(name), "drive", "gear.i")
    np.testing.assert_allclose(r["drive.motor.w"], i * r["drive.shaft.w"], rtol=1e-12)
    # every force is a force: the mechanisms carry load in the steady run
    steady = r["time"] > r["time"][-1] / 2
    for c in components - {"drive"}:
        for v in DESIGNER[c]:
            if v.endswith(".F") or v.endswith("F_cut") or v == "shaft.tau":
                assert np.ptp(r[f"{c}.{v}"][steady]) > 1.0, f"{c}.{v}"


@pytest.mark.parametrize("name", MACHINES)
def test_every_component_carries_its_reference_results(name, tmp_path):
    """Each FMU inside the SSP carries reference results (FMI-LS-REF) of its own: the
    component's default experiment, with the machine's parameters, on its mechanism's
    cross-check inputs; FMPy's run of the FMU as extracted from the SSP reproduces them bit for
    bit."""
    from test_fmi3 import assert_reference_inside
    path = ssp(name)
    with zipfile.ZipFile(path) as z:
        members = [m for m in z.namelist() if m.startswith("resources/") and m.endswith(".fmu")]
        assert members
        for m in members:
            fmu = tmp_path / Path(m).name
            fmu.write_bytes(z.read(m))
            work = tmp_path / fmu.stem
            work.mkdir()
            assert_reference_inside(fmu, work)
