"""Independent NumPy geometry of the legacy needle drive (legacy-needle-drive.md, "Closure
equations"), written from the spec alone, for the cross-check files: the needle law of the
`perforators` timing, the chain closed from the bar back to the roller, and the shaft torque as
the roller's moment on the rocker. Default parameters; angles in rad, lengths in m."""

from __future__ import annotations

import math

import numpy as np

from closed_form_sewing import compare, perforator_s, table_motion

LK, BETA, THETA12, KAPPA = 0.150, 0.48, math.pi, 120 * math.pi / 180
R, C, B, O3 = 0.100, 0.300, 0.070, np.array([-0.180, 0.300])
CHI, RK, LROD = math.pi, 0.060, 0.100
UG, D0 = np.array([0.0, 1.0]), np.array([-0.120, 0.385])
FB_BRANCH, KPM_BRANCH, N_BRANCHES = 1.0, -1.0, 2.0


def intersect(p, q, r1, r2, sigma):
    """X with |X - p| = r1, |X - q| = r2, on the side sigma of p -> q (arrays of points, rows)."""
    d = q - p
    dist = np.hypot(d[:, 0], d[:, 1])
    e = d / dist[:, None]
    a = (r1 ** 2 - r2 ** 2 + dist ** 2) / (2 * dist)
    h = np.sqrt(r1 ** 2 - a ** 2)
    perp = np.stack([-e[:, 1], e[:, 0]], axis=1)
    return p + a[:, None] * e + sigma * h[:, None] * perp


def chain(s):
    """theta_C and psi1 at bar positions s."""
    n = len(s)
    d = D0 + s[:, None] * UG
    o3 = np.tile(O3, (n, 1))
    c = intersect(o3, d, RK, LROD, KPM_BRANCH)
    theta_c = np.arctan2(c[:, 1] - O3[1], c[:, 0] - O3[0])
    theta_b = theta_c - CHI
    b = O3 + B * np.stack([np.cos(theta_b), np.sin(theta_b)], axis=1)
    o2 = np.array([LK * math.cos(THETA12), LK * math.sin(THETA12)])
    a = intersect(np.tile(o2, (n, 1)), b, R, C, FB_BRANCH)
    theta_k = np.arctan2(a[:, 1] - o2[1], a[:, 0] - o2[0]) - KAPPA
    psi1 = theta_k - math.atan2(-o2[1], -o2[0])
    psi1 = np.mod(psi1 + math.pi, 2 * math.pi) - math.pi
    return theta_c, psi1


def mismatches(result, rtol=1e-9):
    phi = result["shaft.phi"]
    x, _, _, _ = table_motion(phi, result["shaft.w"], result["shaft.a"])
    forward = np.mod(phi, 2 * np.pi) < 82 * math.pi / 180
    s = np.where(forward, perforator_s(x), 0.0)
    theta_c, psi1 = chain(s)
    # the roller's moment on the rocker, every branch: tau = n*P_kr*L*cos(alpha)*dpsi1/dphi
    tau = (N_BRANCHES * result["roller.F"] * BETA * LK * np.cos(result["cam.theta"])
           * result["rocker.w"] / result["shaft.w"])
    return compare(result, (("perforators.s", s), ("lever3.theta", theta_c), ("rocker.psi", psi1),
                            ("shaft.tau", tau)), rtol)
