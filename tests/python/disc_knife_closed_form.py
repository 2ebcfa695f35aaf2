"""DiscKnifeDrive kinematics in NumPy, written from shared/spec/disc-knife-drive.md alone.

Independent of the Rust code: the slider position by the spec's exact formula, the support point D
as the intersection of the circle of radius l4 about C with the line EQ (a quadratic, not eq. 5's
arccos), S on CD; velocities by the closed-form derivative of x_C and of the intersection
(implicit differentiation of the two constraints |D - C| = l4 and D on EQ).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Params:
    l1: float = 0.019
    lambda2: float = 2.0
    e: float = 0.0
    l4: float = 0.022
    lS: float = 0.5
    alpha: float = math.radians(45.0)
    xQ: float = 0.060
    yQ: float = 0.010
    branch: int = 1
    series: bool = False

    # FMI variable of each field
    NAMES = {"l1": "crank.l1", "lambda2": "rod.lambda2", "e": "crank.e", "l4": "holder.l4",
             "lS": "holder.lS", "alpha": "support.alpha", "xQ": "support.xQ", "yQ": "support.yQ"}


def slider(phi, p: Params = Params()):
    """x_C and dx_C/dphi: exact (spec), or the paper's series form (1)."""
    phi = np.asarray(phi, dtype=float)
    l1, l2 = p.l1, p.lambda2 * p.l1
    if p.series:
        lam = p.lambda2
        x = l1 * (lam + np.cos(phi) - np.sin(phi) ** 2 / (2 * lam))
        dx = l1 * (-np.sin(phi) - np.sin(2 * phi) / (2 * lam))
        return x, dx
    y = l1 * np.sin(phi) - p.e
    w = np.sqrt(l2 * l2 - y * y)
    return l1 * np.cos(phi) + w, -l1 * np.sin(phi) - y * l1 * np.cos(phi) / w


def evaluate(phi, w, p: Params = Params()) -> dict:
    """Positions and velocities of C, D and S at crank angles phi, shaft speed w (arrays)."""
    x, dx = slider(phi, p)
    c = np.stack([x, np.full_like(x, p.e)])
    u = np.array([math.sin(p.alpha), math.cos(p.alpha)])[:, None]
    q = np.array([p.xQ, p.yQ])[:, None]
    # D = Q + t*u with |D - C| = l4: t^2 + 2 t u.(Q - C) + |Q - C|^2 - l4^2 = 0.
    m = q - c
    b = np.sum(u * m, axis=0)
    disc = b * b - (np.sum(m * m, axis=0) - p.l4 ** 2)
    if np.any(disc < 0):
        raise ValueError("the holder cannot assemble")
    roots = [-b + np.sqrt(disc), -b - np.sqrt(disc)]
    # The branch: beta = -alpha + branch*acos(c) puts the branch's sign on sin(beta + alpha),
    # i.e. on the component of CD along u x n-rotated: pick the root with that sign.
    n = np.array([math.cos(p.alpha), -math.sin(p.alpha)])[:, None]
    cands = [q + u * t for t in roots]
    # sin(beta + alpha) = cross(n, CD)/l4 with n = (cos a, -sin a): the cross product's sign.
    pick = [np.sign((n[0] * (d[1] - c[1]) - n[1] * (d[0] - c[0]))) == p.branch for d in cands]
    d = np.where(pick[0], cands[0], cands[1])
    t = np.where(pick[0], roots[0], roots[1])
    # Velocities: D = Q + t u, C' = (dx, 0); (D - C).(D' - C') = 0 -> t' = (D - C).C' / (D - C).u.
    cd = d - c
    dc = np.stack([dx, np.zeros_like(dx)])
    dt = np.sum(cd * dc, axis=0) / np.sum(cd * u, axis=0)
    dd = u * dt
    s = c + p.lS * cd
    ds = dc + p.lS * (dd - dc)
    beta = np.arctan2(cd[1], cd[0])
    return {
        "slider.x": x, "slider.v": dx * w,
        "holder.beta": beta,
        "support.x": d[0], "support.y": d[1],
        "knife.x": s[0], "knife.y": s[1],
        "knife.vx": ds[0] * w, "knife.vy": ds[1] * w,
    }


def mismatches(result, p: Params = Params(), names=None, rtol: float = 1e-9) -> list[str]:
    """Columns of an FMPy result (with the shaft inputs it held) that differ from evaluate(),
    relative to each column's magnitude."""
    out = evaluate(result["shaft.phi"], result["shaft.w"], p)
    problems = []
    for name in names or [n for n in out if n in result.dtype.names]:
        actual, expected = np.asarray(result[name], float), out[name]
        scale = max(float(np.max(np.abs(expected))), 1e-300)
        err = np.abs(actual - expected)
        if np.any(err > rtol * scale):
            i = int(np.argmax(err))
            problems.append(f"{name}: row {i} (phi = {result['shaft.phi'][i]}): FMU {actual[i]!r}, "
                            f"closed form {expected[i]!r}, max error {err[i]:.3g} > {rtol * scale:.3g}")
    return problems
