"""Scenes (scenes.md): every scene in scenes/ exported (`cargo run --release -- scene`, into
out/scenes/), validated by FMPy, simulated, and its outputs equal to the full FMU's (out/fmus/) run
with the same parameters and drive, bit for bit.

The scene FMUs are built by tests/run (`cargo run --release -- scene` after the build stage).
"""

from __future__ import annotations

import math
import tomllib
import zipfile

import numpy as np
import pytest
from fmpy.validation import validate_fmu

from harness import FMU_DIR, ROOT, Extracted

SCENE_DIR = ROOT / "scenes"
SCENE_FMU_DIR = ROOT / "out" / "scenes"
HINT = "run `cargo run --release -- scene` (tests/run does) first"
FIDELITY = {"kinematic": 1, "kinetostatic": 2, "elastodynamic": 3}

SCENES = sorted(SCENE_DIR.glob("*.toml"))


def identifier(scene: dict) -> str:
    return f"{scene['mechanism']}_{scene['name'].replace('-', '_')}"


def scene_fmu(path):
    scene = tomllib.loads(path.read_text())
    fmu = SCENE_FMU_DIR / f"{identifier(scene)}.fmu"
    if not fmu.is_file():
        pytest.fail(f"{fmu} is missing: {HINT}")
    return scene, fmu


def test_there_is_a_scene_per_mechanism_and_level():
    have = {(s["mechanism"], s["fidelity"]) for s in map(lambda p: tomllib.loads(p.read_text()), SCENES)}
    for mechanism in ["GenevaKnifeDrive", "SewingTable", "Perforators", "DiscKnifeDrive"]:
        for level in FIDELITY:
            assert (mechanism, level) in have, (mechanism, level)


@pytest.mark.parametrize("path", SCENES, ids=[p.stem for p in SCENES])
def test_scene_fmu_validates_and_lists_only_what_the_scene_uses(path):
    scene, fmu = scene_fmu(path)
    assert validate_fmu(str(fmu)) == [], "fmpy.validation found problems"
    ex = Extracted.of(fmu)
    md = ex.md
    assert md.coSimulation.modelIdentifier == identifier(scene)
    outputs = sorted(v.name for v in md.modelVariables if v.causality == "output")
    assert outputs == sorted(scene["outputs"])
    inputs = {v.name for v in md.modelVariables if v.causality == "input"}
    names = {v.name for v in md.modelVariables}
    assert "model.fidelity" not in names and "drive.mode" not in names
    if scene.get("drive", {}).get("mode") == "constant_speed":
        assert not inputs & {"shaft.phi", "shaft.w", "shaft.a"}
    for name, value in scene.get("parameters", {}).items():
        if name in ex.vars and isinstance(value, float):
            assert float(ex.vars[name].start) == value, name
    exp = scene["experiment"]
    assert float(md.defaultExperiment.stopTime) == exp["stop"]
    assert float(md.defaultExperiment.stepSize) == exp["step"]
    # the scene rides along, and the documentation says what is left out
    with zipfile.ZipFile(fmu) as z:
        assert z.read("resources/scene.toml") == path.read_bytes()
        page = z.read("documentation/index.html").decode()
    assert "What this FMU leaves out, and why" in page
    assert "Computations skipped" in page and "Parameters left out" in page
    full = Extracted.of(FMU_DIR / f"{scene['mechanism']}.fmu")
    assert len(md.modelVariables) < len(full.md.modelVariables)


def _input_signal(names, stop):
    t = np.linspace(0.0, stop, 201)
    sig = np.zeros(t.shape, dtype=[("time", np.float64)] + [(n, np.float64) for n in names])
    sig["time"] = t
    for n in names:
        if n == "shaft.phi":
            sig[n] = 0.4 + 11.0 * t + 3.0 * t * t
        elif n == "shaft.w":
            sig[n] = 11.0 + 6.0 * t
        elif n == "shaft.a":
            sig[n] = 6.0
        else:
            sig[n] = 25.0 * np.sin(7.0 * t)
    return sig


@pytest.mark.parametrize("path", SCENES, ids=[p.stem for p in SCENES])
def test_scene_fmu_equals_the_full_fmu_bit_for_bit(path):
    scene, fmu = scene_fmu(path)
    ex = Extracted.of(fmu)
    full_path = FMU_DIR / f"{scene['mechanism']}.fmu"
    if not full_path.is_file():
        pytest.fail(f"{full_path} is missing: run `cargo run --release -- build` first")
    full = Extracted.of(full_path)
    # the full FMU at the scene's parameters, level and drive
    start = {}
    for name, value in scene.get("parameters", {}).items():
        var = full.vars[name]
        if var.type == "Enumeration":
            items = [i.name for i in var.declaredType.items]
            value = items.index(value) + 1
        start[name] = value
    start["model.fidelity"] = FIDELITY[scene["fidelity"]]
    drive = scene.get("drive", {})
    if drive.get("mode") == "constant_speed":
        start["drive.mode"] = 2
        start["drive.n"] = math.pi * (drive["n"] / 30.0)
        start["drive.phi0"] = drive.get("phi0", 0.0)
    stop = min(scene["experiment"]["stop"], 0.5)
    step = scene["experiment"]["step"]
    inputs = [v.name for v in ex.md.modelVariables if v.causality == "input"]
    kw = dict(stop_time=stop, output_interval=step, output=scene["outputs"])
    if inputs:
        kw["input"] = _input_signal(inputs, stop)
    tailored = ex.simulate(**kw)
    reference = full.simulate(start_values=start, **kw)
    assert len(tailored) == len(reference) == round(stop / step) + 1
    for name in scene["outputs"]:
        a, b = tailored[name], reference[name]
        assert np.all(np.isfinite(a.astype(float))), name
        if a.dtype == np.float64:  # bit patterns: -0.0 differs from 0.0, NaN equals NaN
            a, b = np.ascontiguousarray(a).view(np.uint64), np.ascontiguousarray(b).view(np.uint64)
        assert np.array_equal(a, b), name
    # something happened: the scene's first output moves
    first = tailored[scene["outputs"][0]].astype(float)
    assert np.ptp(first) > 0.0


def test_a_scene_keeps_the_lift_off_check_it_leaves_the_outputs_of():
    """The ramp-contact scene leaves out the lift-off outputs (roller.F_margin, roller.lost_contact)
    but not the check: at 130 rpm, above the lift-off speed, its roller.F goes negative and it warns
    as the full FMU does."""
    from fmpy import simulate_fmu
    from harness import captured_log
    fmu = SCENE_FMU_DIR / "Perforators_ramp_contact.fmu"
    n = 130 * math.pi / 30
    with captured_log() as log:
        r = simulate_fmu(str(fmu), start_values={"drive.n": n}, output=["roller.F"],
                         logger=log, debug_logging=False)
    assert r["roller.F"].min() < -10.0, r["roller.F"].min()
    warnings = [m for status, _, m in log if status == 1]
    assert any("roller lifts off the ramp" in m for m in warnings), warnings[:3]
