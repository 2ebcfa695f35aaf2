"""Independent NumPy/Python model of the MainShaft FMU, written from its documentation (Kloss's
formula, gear, flywheel, bearing friction) and not from the Rust sources: a fine fixed-step RK4 of

    (fly.J + i^2*motor.J + sum J_red)*eps = i*M(i*w) - tau_c*tanh(w/w_s) - c*w - load.tau - sum tau0
    M(w_m) = 2*M_k*s*s_k/(s^2 + s_k^2),  s = (w0 - w_m)/w0,  w0 = n_rated/(1 - s_rated)
    M_k = lambda*P_rated/n_rated,  s_k = s_rated*(lambda + sqrt(lambda^2 - 1))

with the defaults of the FMU (the 1.1 kW, 1400 rpm motor; gear 15; fly.J 2 kg.m2).
"""

from __future__ import annotations

import math

import numpy as np

DEFAULTS = dict(P=1100.0, n=1400.0 * math.pi / 30.0, s_n=1.0 / 15.0, lam=2.2, J_m=0.0035, i=15.0, J_fly=2.0,
                tau_c=2.0, c=0.05, w_s=0.01)

# the cross-check set-up: constant loads from rest
LOAD = {"load.tau": 40.0, "load1.tau0": 20.0, "load1.J_red": 1.5,
        "load2.J_red": 0.0, "load2.tau0": 0.0, "load3.J_red": 0.0, "load3.tau0": 0.0}


def eps(w: float, p=DEFAULTS, load=LOAD) -> float:
    w0 = p["n"] / (1.0 - p["s_n"])
    mk = p["lam"] * p["P"] / p["n"]
    sk = p["s_n"] * (p["lam"] + math.sqrt(p["lam"] ** 2 - 1.0))
    s = (w0 - p["i"] * w) / w0
    motor = 2.0 * mk * s * sk / (s * s + sk * sk)
    friction = p["tau_c"] * math.tanh(w / p["w_s"]) + p["c"] * w
    j = p["J_fly"] + p["i"] ** 2 * p["J_m"] + load["load1.J_red"]
    return (p["i"] * motor - friction - load["load.tau"] - load["load1.tau0"]) / j


def startup(times: np.ndarray, h: float = 1e-5) -> tuple[np.ndarray, np.ndarray]:
    """(phi, w) at `times` (increasing, from 0) from rest."""
    phi, w, t = 0.0, 0.0, 0.0
    out_phi, out_w = [], []
    for target in times:
        while t < target - 1e-12:
            dt = min(h, target - t)
            k1 = (w, eps(w))
            k2 = (w + 0.5 * dt * k1[1], eps(w + 0.5 * dt * k1[1]))
            k3 = (w + 0.5 * dt * k2[1], eps(w + 0.5 * dt * k2[1]))
            k4 = (w + dt * k3[1], eps(w + dt * k3[1]))
            phi += dt / 6.0 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            w += dt / 6.0 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
            t += dt
        out_phi.append(phi)
        out_w.append(w)
    return np.array(out_phi), np.array(out_w)


def mismatches(result, rtol: float = 1e-6) -> list[str]:
    phi, w = startup(result["time"])
    problems = []
    for name, ref in (("shaft.phi", phi), ("shaft.w", w)):
        scale = max(float(np.max(np.abs(ref))), 1e-300)
        err = np.abs(result[name] - ref)
        k = int(np.argmax(err))
        if err[k] > rtol * scale:
            problems.append(f"{name}: row {k} (t = {result['time'][k]}): FMU {result[name][k]!r}, RK4 {ref[k]!r}")
    a = np.array([eps(x) for x in result["shaft.w"]])
    err = np.abs(result["shaft.a"] - a)
    if np.max(err) > 1e-9 * max(float(np.max(np.abs(a))), 1e-300):
        problems.append(f"shaft.a: not the equation of motion at the recorded speed (max error {np.max(err)})")
    return problems
