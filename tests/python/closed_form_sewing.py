"""Independent NumPy closed forms of the sewing table and the perforators (sewing-table.md,
perforators.md, motion-laws.md), written from the spec alone, for the cross-check files and the
coupling test. Default parameters; angles in rad, lengths in m."""

from __future__ import annotations

import math

import numpy as np

DEG = math.pi / 180.0
UNIT = 0.030
FORWARD, DWELL_SEW, RETURN = 82 * DEG, 110 * DEG, 90 * DEG


def table_stroke(l1=1.0, R=11.0, alpha2=20 * DEG, unit=UNIT):
    a1 = math.asin(l1 / R)
    a1a2 = 2 * R * math.sin(alpha2 / 2)
    k0 = R * math.cos(alpha2 / 2) - R * math.sin(math.pi / 2 - (a1 + alpha2))
    return math.sqrt(a1a2 ** 2 - k0 ** 2) * unit


def cycloidal(u):
    u = np.clip(u, 0.0, 1.0)
    return u - np.sin(2 * np.pi * u) / (2 * np.pi), 1 - np.cos(2 * np.pi * u), 2 * np.pi * np.sin(2 * np.pi * u)


def table_motion(phi, w, a):
    """table.x, table.v, table.a of the default cyclogram (cycloidal both ways)."""
    h = table_stroke()
    psi = np.mod(phi, 2 * np.pi)
    x = np.zeros_like(psi)
    d1 = np.zeros_like(psi)
    d2 = np.zeros_like(psi)
    fw = psi < FORWARD
    L, L1, L2 = cycloidal(psi / FORWARD)
    x[fw], d1[fw], d2[fw] = h * L[fw], h * L1[fw] / FORWARD, h * L2[fw] / FORWARD ** 2
    dw = (psi >= FORWARD) & (psi < FORWARD + DWELL_SEW)
    x[dw] = h
    rt = (psi >= FORWARD + DWELL_SEW) & (psi < FORWARD + DWELL_SEW + RETURN)
    L, L1, L2 = cycloidal((psi - FORWARD - DWELL_SEW) / RETURN)
    x[rt], d1[rt], d2[rt] = h * (1 - L[rt]), -h * L1[rt] / RETURN, -h * L2[rt] / RETURN ** 2
    return x, d1 * w, d2 * w * w + d1 * a, d1


def perforator_s(x_t):
    """perforators.s for synth.mode = exact: S·L(x_t/(h/2)) rising, S·(1 − L(...)) falling, S = 30 mm."""
    h = table_stroke()
    S = 1.0 * UNIT
    rise = x_t <= h / 2
    return np.where(rise, S * cycloidal(x_t / (h / 2))[0], S * (1 - cycloidal((x_t - h / 2) / (h / 2))[0]))


def compare(result, wants, rtol=1e-9):
    """The columns of `result` that differ from their closed form `wants` ((name, array), ...) by
    more than rtol of the closed form's largest magnitude, the first bad row of each."""
    out = []
    for name, want in wants:
        got = result[name]
        scale = np.max(np.abs(want)) + 1e-300
        bad = np.abs(got - want) > rtol * scale
        if np.any(bad):
            i = int(np.argmax(bad))
            out.append(f"{name} at row {i}: FMU {got[i]!r}, closed form {want[i]!r}")
    return out


def mismatches_table(result, rtol=1e-9):
    x, v, a, _ = table_motion(result["shaft.phi"], result["shaft.w"], result["shaft.a"])
    return compare(result, (("table.x", x), ("table.v", v), ("table.a", a)), rtol)


def mismatches_perforators(result, rtol=1e-9):
    x, _, _, dx = table_motion(result["shaft.phi"], result["shaft.w"], result["shaft.a"])
    s = perforator_s(x)
    tau = -result["table.F"] * dx
    return compare(result, (("table.x", x), ("perforators.s", s), ("shaft.tau", tau)), rtol)
