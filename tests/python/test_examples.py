"""The two designer's examples (examples/sewing_machine.py, examples/trimmer.py) run as a user runs
them, at two speeds each: their printed answers agree with what the FMUs give on their own, their
plot is a real PNG, and a nonsense speed is refused with a clear message."""

from __future__ import annotations

import math
import re
import subprocess
import sys

import numpy as np
import pytest
from fmpy import simulate_fmu
from PIL import Image

from harness import FMU_DIR, ROOT

EXAMPLES = ROOT / "examples"


def run(script: str, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(EXAMPLES / script), *args], cwd=ROOT,
                          capture_output=True, text=True, timeout=600)


def number(pattern: str, text: str) -> float:
    m = re.search(pattern, text)
    assert m, f"{pattern!r} not in:\n{text}"
    return float(m.group(1))


def check_png(path, min_size=(600, 400)):
    with Image.open(path) as im:
        assert im.format == "PNG"
        assert im.size[0] >= min_size[0] and im.size[1] >= min_size[1], im.size
        im.load()
        extrema = im.convert("L").getextrema()
        assert extrema[0] < 100 < extrema[1], "a drawing, not a blank image"


@pytest.mark.parametrize("rpm", [100, 130])
def test_sewing_machine_answers(tmp_path, rpm):
    out = run("sewing_machine.py", "--rpm", str(rpm), "--out", str(tmp_path))
    assert out.returncode == 0, out.stderr
    text = out.stdout
    running = number(r"running ([0-9.]+) rpm", text)
    assert abs(running - rpm) < 0.02 * rpm, text  # the motor's slip under load
    # the lift-off speed of the default spring is 113.6 rpm (bindery liftoff): below it the roller
    # stays on, above it lifts off; the smallest contact force agrees with the Perforators FMU
    # alone at constant speed (its table reaction does not feed back into the perforators)
    alone = simulate_fmu(str(FMU_DIR / "Perforators.fmu"), stop_time=2 * 60 / running,
                         output_interval=1e-4, output=["roller.F"],
                         start_values={"drive.mode": 2, "drive.n": running * math.pi / 30})
    f_min = alone["roller.F"].min()
    if rpm < 113.6:
        margin = number(r"lift-off margin ([-0-9.]+) N", text)
        assert margin > 0 and abs(margin - f_min) < 0.05 * abs(f_min) + 2.0, (margin, f_min)
    else:
        assert "LIFTS OFF" in text, text
        pull = number(r"pull with ([0-9.]+) N", text)
        assert abs(-pull - f_min) < 0.1 * abs(f_min) + 5.0, (pull, f_min)
    peak = number(r"peak ([0-9.]+) N\.m, mean", text)
    assert 20 < peak < 500, text
    assert number(r"motor torque: peak ([0-9.]+) N\.m", text) < peak / 5  # through the gear
    check_png(tmp_path / f"sewing_machine_{rpm}rpm.png")


@pytest.mark.parametrize("cpm", [30, 40])
def test_trimmer_answers(tmp_path, cpm):
    out = run("trimmer.py", "--cpm", str(cpm), "--out", str(tmp_path))
    assert out.returncode == 0, out.stderr
    text = out.stdout
    running = number(r"running ([0-9.]+),", text)
    assert abs(running - cpm) < 0.05 * cpm, text
    # the cutting force is the assumed cut.F_max = 15 kN; the rod and Geneva forces as the
    # GenevaKnifeDrive FMU gives them alone at the running speed
    alone = simulate_fmu(str(FMU_DIR / "GenevaKnifeDrive.fmu"), stop_time=2 * 60 / running,
                         output_interval=1e-4, output=["rod.F", "geneva.F"],
                         start_values={"drive.mode": 2, "drive.n": running * math.pi / 30})
    for knife in ["side_left", "side_right", "front"]:
        cut = number(knife + r" knife: cutting force peak ([0-9.]+) kN", text)
        rod = number(knife + r" knife: .*rod force peak ([0-9.]+) kN", text)
        geneva = number(knife + r" knife: .*Geneva contact peak ([0-9.]+) kN", text)
        assert abs(cut - 15.0) < 0.01, text
        assert abs(rod * 1e3 - np.abs(alone["rod.F"]).max()) < 0.02 * 15.6e3, (rod, text)
        assert abs(geneva * 1e3 - np.abs(alone["geneva.F"]).max()) < 0.03 * 119e3, (geneva, text)
    peak = number(r"motor torque: peak ([0-9.]+) N\.m", text)
    rms = number(r"RMS ([0-9.]+) N\.m", text)
    assert 0 < rms < peak, text
    check_png(tmp_path / f"trimmer_{cpm}cpm.png")


@pytest.mark.parametrize("script,arg", [("sewing_machine.py", "--rpm"), ("trimmer.py", "--cpm")])
@pytest.mark.parametrize("value", ["0", "-5", "nan", "1e9"])
def test_a_nonsense_speed_is_refused_with_a_clear_message(script, arg, value):
    out = run(script, arg, value)
    assert out.returncode == 2, out
    assert arg in out.stderr and ("from 1 to" in out.stderr), out.stderr
