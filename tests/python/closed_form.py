"""Independent NumPy implementation of GenevaKnifeDrive's closed form.

Written from `shared/spec/geneva-knife-drive.md` alone (not from the Rust sources), so that the
FMU can be checked against it. Every function is vectorized over the shaft inputs.

Kinematics (spec, section "Kinematics"):
    psi = phi mod 2*pi, phi_e = pi/2 - pi/Z, lambda = 1/sin(pi/Z), u = phi_e - psi
    engaged (roller in a slot) for psi in [0, 2*phi_e]:
        gamma   = pi/Z - atan(sin u / (lambda - cos u))
        gamma'  = (lambda*cos u - 1) / (1 + lambda^2 - 2*lambda*cos u)
        gamma'' = lambda*(lambda^2 - 1)*sin u / (1 + lambda^2 - 2*lambda*cos u)^2
    dwell: gamma = 2*pi/Z, gamma' = gamma'' = 0
    theta = i*gamma, sin(nu) = sin(theta)/lambda2, lambda2 = l/r2
    s = r2*(1 + lambda2 - cos(theta) - sqrt(lambda2^2 - sin(theta)^2))
    v = s_theta*theta_dot, a = s_thetatheta*theta_dot^2 + s_theta*theta_ddot,
    theta_dot = i*gamma'*w, theta_ddot = i*(gamma''*w^2 + gamma'*eps)

Kinetostatics (spec, section "Kinetostatics"), solved for the rod force P (compression > 0):
    P*cos(nu) - mu*|P*sin(nu)|*sgn(v) + m_s*g - F_cut = m_s*a
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

G = 9.80665  # standard gravity, m/s2


@dataclass(frozen=True)
class Params:
    """The parameters of geneva-knife-drive.md with the spec's defaults."""

    Z: int = 4
    r1: float = 0.08
    i: int = 4
    eta: float = 0.98
    r2: float = 0.07
    l: float = 0.35
    m_knife: float = 12.0
    m_rod: float = 3.0
    J_crank: float = 0.05
    J_cross: float = 0.08
    J_driver: float = 0.03
    mu: float = 0.1
    F_max: float = 15000.0
    s_start: float = 0.070
    s_full: float = 0.075
    s_end: float = 0.135
    n: float = math.pi  # drive.n, rad/s (30 rpm)

    # FMI variable names of the fields (for start_values)
    NAMES = {
        "Z": "geneva.Z", "r1": "geneva.r1", "i": "gear.i", "eta": "gear.eta", "r2": "crank.r",
        "l": "rod.l", "m_knife": "knife.m", "m_rod": "rod.m", "J_crank": "crank.J",
        "J_cross": "cross.J", "J_driver": "driver.J", "mu": "guide.mu", "F_max": "cut.F_max",
        "s_start": "cut.s_start", "s_full": "cut.s_full", "s_end": "cut.s_end", "n": "drive.n",
    }

    def with_(self, **changes) -> "Params":
        return replace(self, **changes)

    def start_values(self) -> dict:
        """Every parameter as an FMPy start_values dict (FMI names)."""
        return {fmi: getattr(self, field) for field, fmi in self.NAMES.items()}

    @property
    def m_s(self) -> float:
        """Translating mass: slider + knife + half the rod."""
        return self.m_knife + self.m_rod / 2.0


def geneva(phi, p: Params = Params()):
    """gamma, gamma', gamma'' and the engagement flag at driver angle(s) phi."""
    phi = np.asarray(phi, dtype=float)
    half_index = math.pi / p.Z
    lam = 1.0 / math.sin(half_index)
    phi_e = math.pi / 2.0 - half_index
    psi = np.mod(phi, 2.0 * math.pi)
    psi = np.where(psi >= 2.0 * math.pi, 0.0, psi)
    u = phi_e - psi
    su, cu = np.sin(u), np.cos(u)
    d = 1.0 + lam * lam - 2.0 * lam * cu
    engaged = psi <= 2.0 * phi_e
    gamma = np.where(engaged, half_index - np.arctan(su / (lam - cu)), 2.0 * half_index)
    gamma_d = np.where(engaged, (lam * cu - 1.0) / d, 0.0)
    gamma_dd = np.where(engaged, lam * (lam * lam - 1.0) * su / (d * d), 0.0)
    rho = p.r1 * np.sqrt(d)
    return gamma, gamma_d, gamma_dd, engaged, rho


def evaluate(phi, w, eps, p: Params = Params()) -> dict:
    """Every output of the spec, as NumPy arrays, at shaft angle/speed/acceleration (phi, w, eps)."""
    return evaluate_with_alternatives(phi, w, eps, p)[0]


def evaluate_with_alternatives(phi, w, eps, p: Params = Params()) -> tuple[dict, dict]:
    """`evaluate`, and the values some outputs may equally take where the spec leaves a tie open."""
    phi, w, eps = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (phi, w, eps)))
    gamma, gd, gdd, engaged, rho = geneva(phi, p)
    lam2 = p.l / p.r2

    gamma_w = gd * w
    gamma_a = gdd * w * w + gd * eps

    theta_raw = p.i * gamma
    theta = np.mod(theta_raw, 2.0 * math.pi)
    theta_w = p.i * gamma_w
    theta_a = p.i * gamma_a

    st, ct = np.sin(theta_raw), np.cos(theta_raw)
    R = np.sqrt(lam2 * lam2 - st * st)
    s = p.r2 * (1.0 + lam2 - ct - R)
    s_t = p.r2 * st * (1.0 + ct / R)
    s_tt = p.r2 * (ct + np.cos(2.0 * theta_raw) / R + (st * ct) ** 2 / R ** 3)
    v = s_t * theta_w
    a = s_tt * theta_w ** 2 + s_t * theta_a
    nu = np.arcsin(st / lam2)

    # kinetostatics
    m_s = p.m_s
    ramp = np.clip((s - p.s_start) / (p.s_full - p.s_start), 0.0, 1.0)
    F_cut = np.where((v > 0) & (s >= p.s_start) & (s <= p.s_end), p.F_max * ramp, 0.0)
    F_inertia = -m_s * a
    rhs = m_s * a - m_s * G + F_cut
    P = rhs / (np.cos(nu) - p.mu * np.abs(np.sin(nu)) * np.sign(v) * np.sign(rhs))
    N = P * np.sin(nu)
    J_c = p.J_crank + p.m_rod / 2.0 * p.r2 ** 2
    tau_crank = P * p.r2 * np.sin(theta_raw + nu) + J_c * theta_a
    to_crank = tau_crank * theta_w > 0
    tau_cross = np.where(to_crank, p.i * tau_crank / p.eta, p.i * tau_crank * p.eta) + p.J_cross * gamma_a
    F_geneva = tau_cross / rho
    # Where the crank stands still (entry and exit of the roller, theta_dot = 0 up to round-off) no
    # power flows through the mesh and the spec does not say which efficiency branch applies:
    # either is accepted there (see `mismatches`).
    tie = np.abs(theta_w) <= 1e-9 * p.i * np.abs(w)
    tau_cross_alt = np.where(to_crank, p.i * tau_crank * p.eta, p.i * tau_crank / p.eta) + p.J_cross * gamma_a
    tau = np.where(engaged, tau_cross * gd, 0.0) + p.J_driver * eps

    return {
        "cross.gamma": gamma, "cross.w": gamma_w, "cross.a": gamma_a,
        "crank.theta": theta, "crank.w": theta_w, "crank.a": theta_a,
        "rod.nu": nu,
        "knife.s": s, "knife.v": v, "knife.a": a, "knife.dwell": ~engaged,
        "knife.F_cut": F_cut, "knife.F_inertia": F_inertia,
        "rod.F": P, "guide.N": N,
        "crank.tau": tau_crank, "cross.tau": tau_cross, "geneva.F": F_geneva,
        "shaft.tau": tau, "shaft.P": tau * w,
    }, {
        "cross.tau": np.where(tie, tau_cross_alt, tau_cross),
        "geneva.F": np.where(tie, tau_cross_alt / rho, F_geneva),
    }


def kinetic_energy(out: dict, p: Params = Params(), w=None) -> np.ndarray:
    """Kinetic energy of the moving members from the FMU's (or this module's) outputs.

    Slider mass m_s on knife.v; crank J plus half the rod (at the pin) on crank.w; cross J on
    cross.w; driver J on the shaft speed w (omit it at constant speed: it does not change).
    """
    J_c = p.J_crank + p.m_rod / 2.0 * p.r2 ** 2
    ke = 0.5 * p.m_s * out["knife.v"] ** 2 + 0.5 * J_c * out["crank.w"] ** 2 \
        + 0.5 * p.J_cross * out["cross.w"] ** 2
    if w is not None:
        ke = ke + 0.5 * p.J_driver * np.asarray(w) ** 2
    return ke


ANGLE_PERIODS = {"cross.gamma": lambda p: 2.0 * math.pi / p.Z, "crank.theta": lambda p: 2.0 * math.pi}


def mismatches(result, p: Params = Params(), names=None, rtol: float = 1e-9, inputs=None) -> list[str]:
    """Compares a simulation result (structured array that also holds the three shaft inputs the
    FMU held, see harness.py) with `evaluate` at those inputs. Returns one message per output
    that differs by more than rtol times the output's largest magnitude in the run;
    angles (cross.gamma, crank.theta) are compared modulo their period. Empty list: agreement.
    `inputs` = (phi, w, a) arrays replace the recorded shaft inputs (for drive.mode = constant_speed,
    where the FMU drives itself and ignores them)."""
    phi, w, a = inputs if inputs is not None else (result["shaft.phi"], result["shaft.w"], result["shaft.a"])
    phi, w, a = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (phi, w, a)))
    expected, alternatives = evaluate_with_alternatives(phi, w, a, p)
    names = [n for n in (names or expected) if n in result.dtype.names]
    problems = []
    for name in names:
        got = np.asarray(result[name])
        want = expected[name]
        if want.dtype == bool:
            bad = np.flatnonzero(got.astype(bool) != want)
            if bad.size:
                k = bad[0]
                problems.append(f"{name}: {bad.size} samples differ, first at t={float(result['time'][k])!r} "
                                f"(phi={float(phi[k])!r}): got {bool(got[k])}, "
                                f"expected {bool(want[k])}")
            continue
        diff = got - want
        if name in alternatives:
            diff_alt = got - alternatives[name]
            diff = np.where(np.abs(diff_alt) < np.abs(diff), diff_alt, diff)
        if name in ANGLE_PERIODS:
            period = ANGLE_PERIODS[name](p)
            diff = diff - period * np.round(diff / period)
        scale = max(float(np.max(np.abs(want))), 1e-300)
        tol = rtol * scale
        bad = np.flatnonzero(~(np.abs(diff) <= tol))
        if bad.size:
            k = bad[np.argmax(np.abs(diff[bad]))]
            problems.append(f"{name}: {bad.size} of {got.size} samples off by more than rtol={rtol:g} "
                            f"(scale {scale:.6g}); worst at t={float(result['time'][k])!r} "
                            f"(phi={float(phi[k])!r}, w={float(w[k])!r}, a={float(a[k])!r}): got {float(got[k])!r}, "
                            f"expected {float(want[k])!r}")
    return problems
