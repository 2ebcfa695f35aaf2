"""SewingTable against shared/spec/sewing-table.md, through FMPy: the paper's synthesis as
calculated parameters, the spec's reference values at 100 rpm, the refusal of an undercut cam."""

from __future__ import annotations

import math

import numpy as np
import pytest

import closed_form_sewing as cf
from harness import FMU_DIR, Extracted, captured_log

W = 100 * math.pi / 30


@pytest.fixture(scope="module")
def table() -> Extracted:
    path = FMU_DIR / "SewingTable.fmu"
    if not path.is_file():
        pytest.fail(f"{path} is missing: run `cargo run --release -- build`")
    return Extracted.of(path)


def test_synthesis_is_the_papers(table):
    names = ["synth.alpha1", "synth.A1A2", "synth.k1", "synth.k2", "synth.alpha3", "synth.k0", "synth.l2",
             "table.stroke"]
    got = table.get_after_init(names)
    assert all(table.vars[n].causality == "calculatedParameter" for n in names)
    printed = {"synth.alpha1": 5.22, "synth.A1A2": 3.82, "synth.k1": 10.83, "synth.k2": 9.95,
               "synth.alpha3": 64.78, "synth.k0": 0.88, "synth.l2": 3.72}
    for n, p in printed.items():
        x = math.degrees(got[n]) if n in ("synth.alpha1", "synth.alpha3") else got[n]
        assert abs(x - p) <= 0.005 + 1e-12, (n, x)
    assert got["table.stroke"] == pytest.approx(cf.table_stroke(), rel=1e-14)
    assert round(got["table.stroke"], 5) == 0.11152


def test_reference_values_at_100_rpm(table):
    out = table.probe([(0.5, W, 0.0), (1.0, W, 0.0)], ["table.x", "table.v", "table.a", "table.phase"])
    assert round(out["table.x"][0], 6) == 0.024560 and round(out["table.x"][1], 6) == 0.094756
    assert round(out["table.v"][0], 5) == 1.29297 and round(out["table.v"][1], 5) == 1.07433
    assert round(out["table.a"][0], 4) == 30.4377 and round(out["table.a"][1], 4) == -35.5847
    assert list(out["table.phase"]) == [0, 0]


def test_motion_against_the_numpy_cyclogram(table):
    phi = np.linspace(0.0, 2 * math.pi, 181)
    out = table.probe([(p, W, 1.5) for p in phi], ["table.x", "table.v", "table.a"])
    x, v, a, _ = cf.table_motion(phi, W, 1.5)
    np.testing.assert_allclose(out["table.x"], x, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(out["table.v"], v, rtol=1e-12, atol=1e-13)
    np.testing.assert_allclose(out["table.a"], a, rtol=1e-10, atol=1e-10)


def test_undercut_cam_is_refused(table):
    with captured_log() as log:
        with pytest.raises(Exception):
            table.probe([(0.0, W, 0.0)], ["table.x"], start_values={"cam.R0": 0.02}, logger=log)
    text = " ".join(log.errors())
    assert "cam.R0" in text and "undercut" in text and "shaft angle" in text, text
