"""Perforators against shared/spec/perforators.md, through FMPy: the paper's synthesis and its
stroke error, the spec's reference values for both synthesis modes, the top at 41 deg, lift-off."""

from __future__ import annotations

import math

import numpy as np
import pytest

import closed_form_sewing as cf
from harness import FMU_DIR, Extracted, captured_log

W = 100 * math.pi / 30
DEG = math.pi / 180


@pytest.fixture(scope="module")
def perf() -> Extracted:
    path = FMU_DIR / "Perforators.fmu"
    if not path.is_file():
        pytest.fail(f"{path} is missing: run `cargo run --release -- build`")
    return Extracted.of(path)


def test_synthesis_and_stroke_error(perf):
    for mode, gamma in ((1, 28.93), (2, 28.27)):
        got = perf.get_after_init(["synth.nu", "synth.gamma_sum", "synth.S_sum", "synth.stroke_error",
                                   "perforators.stroke"], {"synth.mode": mode})
        assert round(math.degrees(got["synth.nu"]), 2) == 28.79
        assert round(math.degrees(got["synth.gamma_sum"]), 2) == gamma
        assert round(got["synth.S_sum"], 4) == 0.7023
        assert round(100 * got["synth.stroke_error"], 1) == 2.3
    assert got["perforators.stroke"] == pytest.approx(0.030, rel=1e-12)


def phi_at_table(x_frac):
    """Shaft angle of the forward travel where the cycloidal table is at x_frac of its stroke."""
    lo, hi = 0.0, 82 * DEG
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if cf.cycloidal(np.array([mid / (82 * DEG)]))[0][0] < x_frac:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@pytest.mark.parametrize("mode, x_frac, s_mm, g_deg, rise_mm", [
    (1, 0.25, 15.342, 14.077, 9.521),
    (1, 0.5, 30.685, 28.931, 21.068),
    (2, 0.5, 30.000, 28.271, 20.532),
])
def test_reference_values(perf, mode, x_frac, s_mm, g_deg, rise_mm):
    out = perf.probe([(phi_at_table(x_frac), W, 0.0)], ["perforators.s", "lever.gamma", "roller.rise"],
                     start_values={"synth.mode": mode})
    assert round(1000 * out["perforators.s"][0], 3) == s_mm
    assert round(math.degrees(out["lever.gamma"][0]), 3) == g_deg
    assert round(1000 * out["roller.rise"][0], 3) == rise_mm


def test_top_at_41_degrees_and_needle_law(perf):
    phi = np.linspace(0, 82 * DEG, 821)
    out = perf.probe([(p, W, 0.0) for p in phi], ["perforators.s", "table.x"])
    assert abs(math.degrees(phi[np.argmax(out["perforators.s"])]) - 41.0) < 0.11
    np.testing.assert_allclose(out["perforators.s"], cf.perforator_s(out["table.x"]), rtol=1e-9, atol=1e-14)


def test_lift_off_flag_and_warning(perf):
    phi = np.linspace(0, 2 * math.pi, 721)
    with captured_log() as log:
        out = perf.probe([(p, W, 0.0) for p in phi], ["roller.lost_contact", "roller.F_margin"],
                         start_values={"spring.M0": 0.5}, logger=log)
    assert np.any(out["roller.lost_contact"])
    assert any(status == 1 and "shaft angle" in m for status, _, m in log), list(log)
    out = perf.probe([(p, W, 0.0) for p in phi], ["roller.lost_contact", "roller.F_margin"])
    assert not np.any(out["roller.lost_contact"]) and np.all(out["roller.F_margin"] > 0)


@pytest.mark.parametrize("fidelity", [2, 3])
def test_lift_off_is_warned_once_per_turn_with_the_count_and_the_worst(fidelity):
    """Above the lift-off speed the warning comes once per shaft turn (and once for the turn the
    run ends in), counting that turn's lift-offs and naming its worst: the kinetostatic level the
    largest pull the ramp would need, at least the turn's most negative roller.F sampled by the
    host; the elastodynamic level the count of bounces (23 a turn at 130 rpm, one warning each
    before)."""
    import math
    import re
    from fmpy import simulate_fmu
    from harness import captured_log
    n, stop = 130 * math.pi / 30, 2.4
    with captured_log() as log:
        r = simulate_fmu(str(FMU_DIR / "Perforators.fmu"), stop_time=stop, output=["roller.F"],
                         start_values={"drive.n": n, "drive.mode": 2, "model.fidelity": fidelity},
                         logger=log)
    lifts = [m for s, _, m in log if s == 1 and "roller lifts off the ramp" in m]
    turns = n * stop / (2 * math.pi)
    assert math.floor(turns) <= len(lifts) <= math.ceil(turns) + 1, (turns, lifts)
    numbers = [int(re.search(r"in the shaft turn (\d+)", m).group(1)) for m in lifts]
    assert numbers == sorted(set(numbers)), "one warning per turn"
    if fidelity == 2:
        pulls = [float(re.search(r"pull with ([0-9.]+) N", m).group(1)) for m in lifts]
        assert min(pulls) >= -r["roller.F"].min() - 0.5, (pulls, r["roller.F"].min())
    else:
        counts = [int(re.search(r"lifts off the ramp (\d+) times", m).group(1)) for m in lifts[:-1]]
        assert all(c > 1 for c in counts), counts
