"""The Geneva knife drive (paper 003) as a PythonFMU slave: the benchmark's Python peer.

Plain Python, the same equations as src/mechanisms/geneva_knife_drive/physics.rs and
../shared/spec/geneva-knife-drive.md (kinematic and kinetostatic levels, default parameters),
with the FMU's variable names. Built into an FMU by bench/run with `pythonfmu build`; never
committed as an .fmu. What a user would write who picks PythonFMU instead of bindery-fmu.
"""
import math

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real

TAU = 2.0 * math.pi
G = 9.80665

# (name, attribute) of every Real output, in the order of the Rust FMU's table.
OUTPUTS = [
    ("shaft.tau", "shaft_tau"), ("shaft.P", "shaft_P"),
    ("shaft.J_red", "shaft_J_red"), ("shaft.tau0", "shaft_tau0"),
    ("cross.gamma", "cross_gamma"), ("cross.w", "cross_w"), ("cross.a", "cross_a"),
    ("crank.theta", "crank_theta"), ("crank.w", "crank_w"), ("crank.a", "crank_a"),
    ("rod.nu", "rod_nu"), ("knife.s", "knife_s"), ("knife.v", "knife_v"), ("knife.a", "knife_a"),
    ("knife.F_cut", "knife_F_cut"), ("knife.F_inertia", "knife_F_inertia"), ("rod.F", "rod_F"),
    ("guide.N", "guide_N"), ("crank.tau", "crank_tau"), ("cross.tau", "cross_tau"),
    ("geneva.F", "geneva_F"),
]


def wrap_angle(phi):
    psi = math.fmod(phi, TAU)
    if psi < 0.0:
        psi += TAU
    return 0.0 if psi >= TAU else psi


class GenevaKnifeDrivePy(Fmi2Slave):
    author = "bindery-fmu benchmark"
    description = "Geneva knife drive (paper 003), kinematic and kinetostatic, plain Python"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        # inputs
        self.shaft_phi = 0.0
        self.shaft_w = math.pi
        self.shaft_a = 0.0
        # parameters (the spec's defaults)
        self.model_fidelity = 2  # 1 kinematic, 2 kinetostatic
        self.geneva_Z = 4
        self.geneva_r1 = 0.08
        self.gear_i = 4
        self.gear_eta = 0.98
        self.crank_r = 0.07
        self.rod_l = 0.35
        self.knife_m = 12.0
        self.rod_m = 3.0
        self.crank_J = 0.05
        self.cross_J = 0.08
        self.driver_J = 0.03
        self.guide_mu = 0.1
        self.cut_F_max = 15000.0
        self.cut_s_start = 0.070
        self.cut_s_full = 0.075
        self.cut_s_end = 0.135
        for _, attr in OUTPUTS:
            setattr(self, attr, 0.0)
        self.knife_dwell = False

        def reg(var, attr):
            var.getter = lambda: getattr(self, attr)
            if var.variability != Fmi2Variability.constant:
                var.setter = lambda v: setattr(self, attr, v)
            self.register_variable(var, nested=False)

        reg(Real("shaft.phi", causality=Fmi2Causality.input), "shaft_phi")
        reg(Real("shaft.w", causality=Fmi2Causality.input), "shaft_w")
        reg(Real("shaft.a", causality=Fmi2Causality.input), "shaft_a")
        reg(Integer("model.fidelity", causality=Fmi2Causality.parameter,
                    variability=Fmi2Variability.fixed), "model_fidelity")
        for name in ["geneva.r1", "gear.eta", "crank.r", "rod.l", "knife.m", "rod.m", "crank.J",
                     "cross.J", "driver.J", "guide.mu", "cut.F_max", "cut.s_start", "cut.s_full",
                     "cut.s_end"]:
            reg(Real(name, causality=Fmi2Causality.parameter, variability=Fmi2Variability.fixed),
                name.replace(".", "_"))
        for name in ["geneva.Z", "gear.i"]:
            reg(Integer(name, causality=Fmi2Causality.parameter,
                        variability=Fmi2Variability.fixed), name.replace(".", "_"))
        for name, attr in OUTPUTS:
            reg(Real(name, causality=Fmi2Causality.output), attr)

    def do_step(self, current_time, step_size):
        self.evaluate(self.shaft_phi, self.shaft_w, self.shaft_a)
        return True

    def evaluate(self, phi, w, eps):
        # ---- Geneva pair (src/mechanics/geneva.rs)
        z = self.geneva_Z
        half_index = math.pi / z
        lam = 1.0 / math.sin(half_index)
        phi_e = 0.5 * math.pi - half_index
        psi = wrap_angle(phi)
        u = phi_e - psi
        su, cu = math.sin(u), math.cos(u)
        d = 1.0 + lam * lam - 2.0 * lam * cu
        rho = self.geneva_r1 * math.sqrt(d)
        engaged = psi <= 2.0 * phi_e
        if engaged:
            gamma = half_index - math.atan2(su, lam - cu)
            gamma_d = (lam * cu - 1.0) / d
            gamma_dd = lam * (lam * lam - 1.0) * su / (d * d)
        else:
            gamma, gamma_d, gamma_dd = 2.0 * half_index, 0.0, 0.0
        # ---- gear pair and crank: theta = i*gamma
        i = float(self.gear_i)
        theta = wrap_angle(i * gamma) if engaged else 0.0
        cross_w = gamma_d * w
        crank_w = i * cross_w
        # ---- central slider-crank (src/mechanics/slider_crank.rs)
        r, l = self.crank_r, self.rod_l
        st, ct = math.sin(theta), math.cos(theta)
        rs = r * st
        y = rs
        wl = math.sqrt(l * l - y * y)  # l*cos(nu)
        dy = r * ct
        ddy = -rs
        inv_w = 1.0 / wl
        inv_w3 = inv_w * inv_w * inv_w
        dx = -rs - y * dy * inv_w
        ddx = -r * ct - (dy * dy + y * ddy) * inv_w - y * y * dy * dy * inv_w3
        one_minus_cos = st * st / (1.0 + ct) if ct >= 0.0 else 1.0 - ct
        s = r * one_minus_cos + rs * rs / (l + wl)
        ds, dds = -dx, -ddx
        nu = math.atan2(y, wl)
        sin_nu, cos_nu = y / l, wl / l
        v = ds * crank_w

        def accelerations(eps):
            cross_a = gamma_dd * w * w + gamma_d * eps
            crank_a = i * cross_a
            return cross_a, crank_a, dds * crank_w * crank_w + ds * crank_a

        cross_a, crank_a, a = accelerations(eps)
        self.cross_gamma, self.cross_w, self.cross_a = gamma, cross_w, cross_a
        self.crank_theta, self.crank_w, self.crank_a = theta, crank_w, crank_a
        self.rod_nu, self.knife_s, self.knife_v, self.knife_a = nu, s, v, a
        self.knife_dwell = not engaged
        if self.model_fidelity != 2:
            self.shaft_tau = 0.0
            self.shaft_P = 0.0
            self.shaft_J_red = 0.0
            self.shaft_tau0 = 0.0
            return
        # ---- kinetostatics (physics.rs, Params::kinetostatics)
        m_s = self.knife_m + 0.5 * self.rod_m
        if v > 0.0 and self.cut_s_start <= s <= self.cut_s_end:
            if s >= self.cut_s_full:
                f_cut = self.cut_F_max
            else:
                f_cut = self.cut_F_max * (s - self.cut_s_start) / (self.cut_s_full - self.cut_s_start)
        else:
            f_cut = 0.0
        sgn_v = 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)
        kf = self.guide_mu * abs(sin_nu) * sgn_v
        crank_inertia = self.crank_J + 0.5 * self.rod_m * r * r

        def forces(eps):
            cross_a, crank_a, a = accelerations(eps)
            rhs = m_s * (a - G) + f_cut
            p = rhs / (cos_nu - kf) if rhs >= 0.0 else rhs / (cos_nu + kf)
            crank_tau = p * ds * cos_nu + crank_inertia * crank_a
            if crank_tau * crank_w >= 0.0:
                gear = i * crank_tau / self.gear_eta
            else:
                gear = i * crank_tau * self.gear_eta
            if engaged:
                cross_tau = gear + self.cross_J * cross_a
                return p, crank_tau, cross_tau, cross_tau / rho, cross_tau * gamma_d + self.driver_J * eps
            return p, crank_tau, 0.0, 0.0, self.driver_J * eps

        p, crank_tau, cross_tau, geneva_f, shaft_tau = forces(eps)
        # shaft.tau = shaft.tau0 + shaft.J_red*shaft.a (src/model.rs, shaft::reduce_at)
        if abs(eps) >= 1.0:
            tau0 = forces(0.0)[4]
            j_red = (shaft_tau - tau0) / eps
        elif eps == 0.0:
            tau0 = shaft_tau
            j_red = forces(1.0)[4] - shaft_tau
        else:
            tau0 = forces(0.0)[4]
            j_red = forces(1.0)[4] - tau0
        self.shaft_J_red = j_red
        self.shaft_tau0 = tau0
        self.knife_F_cut = f_cut
        self.knife_F_inertia = -m_s * a
        self.rod_F = p
        self.guide_N = p * sin_nu
        self.crank_tau = crank_tau
        self.cross_tau = cross_tau
        self.geneva_F = geneva_f
        self.shaft_tau = shaft_tau
        self.shaft_P = shaft_tau * w
