//! The legacy needle drive of the NSh-6 thread-sewing automat (paper 002, Fig. 1, eqs. 1-8;
//! `legacy-needle-drive.md`): a disc cam on the main shaft O1 moves the roller K of the rocker
//! O2K (the cam-rocker pair, KMK); the rocker is one bell crank with the crank O2A of a four-bar
//! O2A-AB-BO3 (ChShRM); the rocker O3B is one bell crank with the arm O3C of a rocker-slider
//! O3C-CD (KPM) whose rod drives the needle bar D along its guide.
//!
//! The bar displacement `s` is the independent variable: the cam is synthesized for the needle
//! law `s(φ)`, and the chain is closed from the bar back to the roller by two circle
//! intersections ([`crate::mechanics::circles`]). The chain runs on second-order dual numbers
//! seeded with `(s, s', s'')`, so the rocker angle ψ1 comes with its exact φ-derivatives.
//!
//! Sign conventions (the spec's): frame origin O1, x right, y up; the cam turns counter-clockwise
//! as φ grows; ψ1 is the rocker's angle from the centre line O2→O1, counter-clockwise; the needles
//! rise along `+u_g`; forces are positive when the cam drives (`roller.F` > 0: the cam pushes on
//! the flank that raises the needles).

// `!(x > 0.0)` is deliberate throughout: a NaN parameter fails the check too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::mechanics::circles::intersect;
use crate::mechanics::cyclogram::{Cyclogram, Phase};
use crate::mechanics::hertz::Roller;
use crate::mechanics::hertz::Surface;
use crate::mechanics::motion_laws::MotionLaw;
use crate::mechanics::{
    ParamError, STANDARD_GRAVITY, Scalar, check_finite, check_non_negative, check_positive, cross,
    dot, hypot, max_of, sgn,
};
use crate::mechanisms::perforators::physics::{Drive as NeedleCurve, Params as NeedleParams};
use num_dual::{Dual, Dual2, Dual64, DualNum};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

crate::fmi_enum! {
    /// Which needle law the cam is made for (`needle.timing`).
    pub enum Timing ("NeedleTiming", "Which needle law the legacy cam is synthesized for") {
        Perforators = 1 ("perforators", "the Perforators FMU's needle curve over the table's forward travel, at rest for the rest of the turn"),
        Own = 2 ("own", "cycloidal rise, top dwell and harmonic fall at the needle.* angles (paper 002's 'Co' work and 'K' idle)"),
    }
}

crate::fmi_enum! {
    /// How the roller is held on the cam (`cam.closure`).
    pub enum Closure ("CamClosure", "How the roller is held on the cam") {
        Groove = 1 ("groove", "a groove cam: either flank pushes, the roller never leaves it"),
        Spring = 2 ("spring", "a spring holds the roller on the flank that raises the needles: it can only push, a pull lifts the roller off"),
    }
}

/// Samples per shaft turn of the checks at initialization (0.25°).
pub const SAMPLES: usize = 1440;

/// Parameters, SI units (angles rad); field docs name the FMI variable.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// `kmk.lk` l_k = O1O2 (0.150), `kmk.beta` β = L_kor/l_k (paper 002: 0.48 for the NSh-6).
    pub l_k: f64,
    pub beta: f64,
    /// `kmk.theta` direction O1→O2 (180°), `kmk.kappa` κ, arm O2K to arm O2A, CCW (120°).
    pub theta12: f64,
    pub kappa: f64,
    /// `fb.R` O2A (0.100), `fb.c` AB (0.300), `fb.b` O3B (0.070); `fb.O3x`, `fb.O3y` (−0.180, 0.300).
    pub r: f64,
    pub c: f64,
    pub b: f64,
    pub o3: [f64; 2],
    /// `kpm.chi` χ, O3B to O3C, CCW (180°); `kpm.Rk` O3C (0.060); `kpm.l` rod CD (0.100).
    pub chi: f64,
    pub r_k: f64,
    pub l_rod: f64,
    /// `bar.dir` guide direction u_g (90°); `bar.D0x`, `bar.D0y`: D at s = 0 (−0.120, 0.385).
    pub bar_dir: f64,
    pub d0: [f64; 2],
    /// `fb.branch` (+1), `kpm.branch` (−1): the assembly branches.
    pub fb_branch: f64,
    pub kpm_branch: f64,
    /// `legacy.branches` n (2): cams and lever branches sharing the load equally.
    pub n: f64,
    /// `load.Kd` K_d (1), `load.F` (0 N), `load.P_spring` (0 N): eq. (1)'s dynamic factor,
    /// friction and spring loads.
    pub k_d: f64,
    pub load_f: f64,
    pub p_spring: f64,
    /// `cam.closure`.
    pub closure: Closure,
    /// `roller.r` r_r (0.015), `roller.b` B (0.015), `cam.E`, `roller.E` (2.1e11 Pa).
    pub roller: Roller,
    /// `cam.J` (0 kg·m²).
    pub cam_j: f64,
    /// `needle.timing`.
    pub timing: Timing,
    /// `needle.phi_start` (61°), `needle.Phi_rise` (41°), `needle.Phi_top` (0°),
    /// `needle.Phi_fall` (41°), `needle.law_rise` (cycloidal), `needle.law_fall` (harmonic):
    /// the `own` timing, angles from `cycle.phi0`.
    pub phi_start: f64,
    pub phi_rise: f64,
    pub phi_top: f64,
    pub phi_fall: f64,
    pub law_rise: MotionLaw,
    pub law_fall: MotionLaw,
    /// What the needles share with the Perforators (same names, meanings and defaults): the
    /// table's cyclogram `cycle.*`, `travel.rise_fraction`, `law.rise`, `law.fall`, `pierce.*`,
    /// `perf.m`, `guide.mu`, `joint.f`, `joint.r`; the stroke S is the Perforators' stroke.
    pub needles: NeedleParams,
}

impl Default for Params {
    fn default() -> Self {
        Self {
            l_k: 0.150,
            beta: 0.48,
            theta12: PI,
            kappa: 120f64.to_radians(),
            r: 0.100,
            c: 0.300,
            b: 0.070,
            o3: [-0.180, 0.300],
            chi: PI,
            r_k: 0.060,
            l_rod: 0.100,
            bar_dir: FRAC_PI_2,
            d0: [-0.120, 0.385],
            fb_branch: 1.0,
            kpm_branch: -1.0,
            n: 2.0,
            k_d: 1.0,
            load_f: 0.0,
            p_spring: 0.0,
            closure: Closure::Groove,
            roller: Roller::steel(0.015, 0.015),
            cam_j: 0.0,
            timing: Timing::Perforators,
            phi_start: 61f64.to_radians(),
            phi_rise: 41f64.to_radians(),
            phi_top: 0.0,
            phi_fall: 41f64.to_radians(),
            law_rise: MotionLaw::Cycloidal,
            law_fall: MotionLaw::Harmonic,
            needles: NeedleParams::default(),
        }
    }
}

/// The chain at one bar position, on any dual number: the points of Fig. 1 and ψ1.
#[derive(Clone, Copy, Debug)]
pub struct Pose<T> {
    pub d: [T; 2],
    pub c: [T; 2],
    pub b: [T; 2],
    pub a: [T; 2],
    pub k: [T; 2],
    /// ψ1, the rocker's angle from the centre line O2→O1, CCW, in (−π, π].
    pub psi1: T,
}

/// Kinematics at one shaft state (any [`Scalar`]: `f64`, or dual numbers along the inputs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Kinematics<T = f64> {
    /// `perforators.s` (0 = lowest), `ds/dφ`, `d²s/dφ²`, `perforators.v`, `perforators.a`.
    pub s: T,
    pub s_d: T,
    pub s_dd: T,
    pub v: T,
    pub a: T,
    /// `rocker.psi` ψ1, ψ1' = dψ1/dφ, ψ1'', `rocker.w`, `rocker.a`, dψ1/ds (1/m).
    pub psi1: T,
    pub psi1_d: T,
    pub psi1_dd: T,
    pub psi1_w: T,
    pub psi1_a: T,
    pub psi1_s: T,
    /// `lever3.theta` θ_C, the direction of O3C.
    pub theta_c: T,
    /// `cam.theta` α, the cam's pressure angle (< 0 while the rocker turns with the cam).
    pub alpha: T,
    /// `cam.rho` ρ_p, the pitch curve's curvature radius (> 0 convex).
    pub rho_p: T,
    /// The paper's angles as the sines and cosines of the vector form (every factor ≥ 0):
    /// cos α_sh = |e_CD·u_g|, sin(γ + α_sh) = |e_O3C × e_CD|, sin μ = |e_AB × e_O3B|,
    /// sin(δ − ψ) = |e_O2A × e_AB|.
    pub cos_alpha_sh: T,
    pub sin_gamma: T,
    pub sin_mu: T,
    pub sin_delta_psi: T,
}

/// Forces at one shaft state (kinetostatic level, one branch unless said).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Forces<T = f64> {
    /// `pierce.Q_T`: the piercing load Q_T (while the needles rise), ≥ 0.
    pub q_t: T,
    /// `perforators.F_inertia`: −K_d·m·a, the bar's inertia force along u_g.
    pub f_inertia: T,
    /// `load.Q` Q_b: the load one branch carries along −u_g (eq. 1 over n).
    pub q_b: T,
    /// `rod.F` P_sh1 (eq. 2), `lever3.P_C` (3), `lever3.P_B` (4), `fb.F` P_sh2 (5),
    /// `rocker.P_A` (6), `roller.F` P_kr (7).
    pub p_sh1: T,
    pub p_c: T,
    pub p_b: T,
    pub p_sh2: T,
    pub p_a: T,
    pub p_kr: T,
    /// `roller.sigma_H` (eq. 8), Pa; `cam.rho_red` ρ_red, m; `cam.flank` (+1 the flank that
    /// raises the needles, −1 the other).
    pub sigma_h: T,
    pub rho_red: T,
    pub flank: i32,
    /// The spring cannot hold the roller: it would have to pull (`cam.closure = spring`).
    pub lost_contact: bool,
    /// `shaft.tau`: the torque on the cam shaft, all branches, N·m.
    pub tau: T,
}

/// Everything fixed for a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drive {
    pub p: Params,
    /// The Perforators' needle curve (table cyclogram, rise fraction, laws, stroke, piercing).
    pub curve: NeedleCurve,
    /// The `own` timing as a cyclogram of the needles.
    pub own: Cyclogram,
    /// `perforators.stroke` S, m.
    pub stroke: f64,
    /// `kmk.L` L = β·l_k, m; O2; the guide's direction u_g.
    pub l: f64,
    pub o2: [f64; 2],
    pub u_g: [f64; 2],
    /// atan2(O1 − O2): the centre line's direction from O2.
    pub base: f64,
    /// `kmk.psi_low`, `kmk.psi_high`: ψ1 at s = 0 and s = S; `cam.r0` |O1K| at s = 0.
    pub psi_low: f64,
    pub psi_high: f64,
    pub r0: f64,
    /// The sense the rocker turns in to raise the needles: the sign of dψ1/ds, the same over
    /// the whole stroke (checked). The force chain's factors are magnitudes (the vector form),
    /// so the raising flank's moment about O2 is `psi_sense·P_kr·L·cos α`.
    pub psi_sense: f64,
    /// The hinges' relative friction arms ε_j = f·r/ℓ_j: C and O3 (ℓ = R_k), B (ℓ = b), A and
    /// O2 (ℓ = R).
    pub eps_c: f64,
    pub eps_b: f64,
    pub eps_a: f64,
}

/// Unit vector from `p` to `q`.
fn unit<T: Scalar>(p: [T; 2], q: [T; 2]) -> (T, T) {
    let d = [q[0] - p[0], q[1] - p[1]];
    let n = hypot(d[0], d[1]);
    (d[0] / n, d[1] / n)
}

/// A point of a [`Pose`] on second-order dual numbers without its φ-derivatives.
fn re<T: Scalar>(x: &[Dual2<T>; 2]) -> [T; 2] {
    [x[0].re, x[1].re]
}

/// A fixed point as any [`Scalar`].
fn lift<T: Scalar>(x: [f64; 2]) -> [T; 2] {
    [T::from(x[0]), T::from(x[1])]
}

impl Params {
    /// Checks the parameters and derives the run's constants; a loop that does not assemble,
    /// an undercut cam or a rocker at 0 or π is refused naming the loop, the bar position or
    /// the shaft angle.
    pub fn drive(&self) -> Result<Drive, ParamError> {
        for (name, x) in [
            ("kmk.lk", self.l_k),
            ("fb.R", self.r),
            ("fb.c", self.c),
            ("fb.b", self.b),
            ("kpm.Rk", self.r_k),
            ("kpm.l", self.l_rod),
            ("roller.r", self.roller.r),
            ("roller.b", self.roller.b),
            ("cam.E", self.roller.e_track),
            ("roller.E", self.roller.e),
        ] {
            check_positive(name, x, "must be a finite length or modulus > 0")?;
        }
        check_positive("kmk.beta", self.beta, "beta = L_rocker/l_k must be > 0")?;
        for (name, x) in [
            ("fb.branch", self.fb_branch),
            ("kpm.branch", self.kpm_branch),
        ] {
            crate::require!(
                x.abs() == 1.0,
                name,
                x,
                "an assembly branch is +1 or -1 (the side of the loop's second joint)"
            );
        }
        crate::require!(
            self.n >= 1.0,
            "legacy.branches",
            self.n,
            "at least one branch must carry the needle bar"
        );
        check_non_negative(&[("load.Kd", self.k_d), ("cam.J", self.cam_j)])?;
        check_finite(&[
            ("kmk.theta", self.theta12),
            ("kmk.kappa", self.kappa),
            ("kpm.chi", self.chi),
            ("bar.dir", self.bar_dir),
            ("fb.O3x", self.o3[0]),
            ("fb.O3y", self.o3[1]),
            ("bar.D0x", self.d0[0]),
            ("bar.D0y", self.d0[1]),
            ("load.F", self.load_f),
            ("load.P_spring", self.p_spring),
        ])?;
        if self.timing == Timing::Own {
            for (name, x) in [
                ("needle.Phi_rise", self.phi_rise),
                ("needle.Phi_fall", self.phi_fall),
            ] {
                check_positive(name, x, "a needle rise or fall needs a phase angle > 0")?;
            }
            crate::require!(
                self.phi_top >= 0.0 && self.phi_rise + self.phi_top + self.phi_fall < TAU,
                "needle.Phi_top",
                self.phi_top,
                "rise, top dwell and fall must fit in one turn"
            );
        }
        let curve = self.needles.drive()?;
        let stroke = curve.stroke;
        let own = Cyclogram {
            h: stroke,
            forward: self.phi_rise,
            dwell_far: self.phi_top,
            ret: self.phi_fall,
            phi0: self.needles.table.phi0 + self.phi_start,
            law_forward: self.law_rise,
            law_return: self.law_fall,
        };
        let o2 = [self.l_k * self.theta12.cos(), self.l_k * self.theta12.sin()];
        let jr = self.needles.joint_f * self.needles.joint_r;
        let mut d = Drive {
            p: *self,
            curve,
            own,
            stroke,
            l: self.beta * self.l_k,
            o2,
            u_g: [self.bar_dir.cos(), self.bar_dir.sin()],
            base: (-o2[1]).atan2(-o2[0]),
            psi_low: f64::NAN,
            psi_high: f64::NAN,
            r0: f64::NAN,
            psi_sense: f64::NAN,
            eps_c: jr / self.r_k,
            eps_b: jr / self.b,
            eps_a: jr / self.r,
        };
        // every bar position of the stroke assembles, and the rocker turns one way over it (a
        // chain through a dead point cannot be driven from the cam)
        let rate = |d: &Drive, s: f64| {
            d.pose(Dual64::new(s, 1.0))
                .map(|p| p.psi1.eps)
                .map_err(|e| d.assembly_error(e, s))
        };
        let sense = sgn(rate(&d, 0.5 * stroke)?);
        for k in 0..=SAMPLES {
            let s = stroke * k as f64 / SAMPLES as f64;
            let r = rate(&d, s)?;
            if !(r * sense > 0.0) {
                return Err(d.dead_point(s, r));
            }
        }
        d.psi_sense = sense;
        let low = d.pose(0.0).map_err(|e| d.assembly_error(e, 0.0))?;
        let high = d.pose(stroke).map_err(|e| d.assembly_error(e, stroke))?;
        d.psi_low = low.psi1;
        d.psi_high = high.psi1;
        d.r0 = low.k[0].hypot(low.k[1]);
        d.check_turn()?;
        Ok(d)
    }
}

impl Drive {
    /// The drive of the default parameters with the needle timing `timing` (the figures' and
    /// the tests' drives).
    pub fn default_with(timing: Timing) -> Drive {
        Params {
            timing,
            ..Params::default()
        }
        .drive()
        .expect("the defaults assemble")
    }

    /// The chain at bar position `s` (any dual number): `Err((loop, h²))` where a loop does not
    /// assemble.
    pub fn pose<T: DualNum<Primitive = f64> + Copy>(
        &self,
        s: T,
    ) -> Result<Pose<T>, (&'static str, f64)> {
        let p = &self.p;
        let c0 = |x: f64| T::from(x);
        let o3 = [c0(p.o3[0]), c0(p.o3[1])];
        // 1. KPM: D on the guide, C where arm O3C meets rod CD
        let d = [s * self.u_g[0] + p.d0[0], s * self.u_g[1] + p.d0[1]];
        let c = intersect(o3, d, p.r_k, p.l_rod, p.kpm_branch)
            .map_err(|h2| ("rocker-slider O3C-CD (kpm.Rk, kpm.l)", h2))?;
        // 2. bell crank O3: B at χ behind C
        let theta_b = (c[1] - o3[1]).atan2(c[0] - o3[0]) - p.chi;
        let (sb, cb) = theta_b.sin_cos();
        let b = [o3[0] + cb * p.b, o3[1] + sb * p.b];
        // 3. four-bar: A where crank O2A meets coupler AB
        let o2 = [c0(self.o2[0]), c0(self.o2[1])];
        let a = intersect(o2, b, p.r, p.c, p.fb_branch)
            .map_err(|h2| ("four-bar O2A-AB (fb.R, fb.c, fb.b)", h2))?;
        // 4. bell crank O2: K at κ behind A
        let theta_k = (a[1] - o2[1]).atan2(a[0] - o2[0]) - p.kappa;
        let (sk, ck) = theta_k.sin_cos();
        let k = [o2[0] + ck * self.l, o2[1] + sk * self.l];
        // 5. ψ1 from the centre line O2→O1, in (−π, π]
        let psi = theta_k - self.base;
        let turns = ((psi.re() + PI) / TAU).ceil() - 1.0;
        Ok(Pose {
            d,
            c,
            b,
            a,
            k,
            psi1: psi - turns * TAU,
        })
    }

    fn assembly_error(&self, (what, h2): (&'static str, f64), s: f64) -> ParamError {
        let param = if what.starts_with("four-bar") {
            "fb.c"
        } else {
            "kpm.l"
        };
        let value = if param == "fb.c" {
            self.p.c
        } else {
            self.p.l_rod
        };
        ParamError::new(
            param,
            value,
            format!(
                "the {what} does not assemble at bar position s = {:.3} mm (the circles miss each other by h^2 = {h2:.3e} m^2)",
                1000.0 * s
            ),
        )
    }

    /// The refusal of a chain that passes a dead point at bar position `s` (dψ1/ds = `rate`
    /// changes sign): ds/dψ1 is unbounded where the four-bar's coupler AB comes in line with
    /// its rocker O3B (sin μ = 0) or the rod CD stands across the guide (cos α_sh = 0); the
    /// loop nearer to it is named.
    fn dead_point(&self, s: f64, rate: f64) -> ParamError {
        let q = self.pose(s).expect("assembles (checked before)");
        let sin_mu = cross(unit(q.a, q.b), unit(self.p.o3, q.b)).abs();
        let cos_sh = { dot(unit(q.c, q.d), (self.u_g[0], self.u_g[1])).abs() };
        let (param, value, what) = if sin_mu <= cos_sh {
            (
                "fb.b",
                self.p.b,
                format!(
                    "the four-bar's coupler AB comes in line with its rocker O3B (sin mu = {sin_mu:.4})"
                ),
            )
        } else {
            (
                "kpm.l",
                self.p.l_rod,
                format!(
                    "the rocker-slider's rod CD stands across the guide (cos alpha_sh = {cos_sh:.4})"
                ),
            )
        };
        ParamError::new(
            param,
            value,
            format!(
                "the chain passes a dead point at bar position s = {:.3} mm, where {what}: the rocker turns back within the stroke (dpsi1/ds = {rate:.4} rad/m)",
                1000.0 * s
            ),
        )
    }

    /// The needle law: `(s, ds/dφ, d²s/dφ²)` at shaft angle `phi` (any [`Scalar`]).
    pub fn needle<T: Scalar>(&self, phi: T) -> (T, T, T) {
        match self.p.timing {
            Timing::Perforators => {
                let c = self.curve.cyc.at(phi);
                if c.phase != Phase::Forward {
                    return (T::zero(), T::zero(), T::zero());
                }
                let (s, sx, sxx) = self.curve.needle_law(c.x);
                (s, sx * c.dx, sxx * c.dx * c.dx + sx * c.ddx)
            }
            Timing::Own => {
                let c = self.own.at(phi);
                (c.x, c.dx, c.ddx)
            }
        }
    }

    /// Kinematics at shaft angle `phi`, speed `w`, acceleration `eps` (any [`Scalar`]: the
    /// same operations for `f64` and for the dual numbers of the partial derivatives). The
    /// chain runs on second-order dual numbers over `T` seeded with `(s, s', s'')`.
    pub fn kinematics<T: Scalar>(&self, phi: T, w: T, eps: T) -> Kinematics<T> {
        let (s, s_d, s_dd) = self.needle(phi);
        let pose = self
            .pose(Dual2::new(s, s_d, s_dd))
            .expect("every bar position of the stroke assembles (checked at initialization)");
        let psi_s = self
            .pose(Dual::new(s, T::one()))
            .expect("checked at initialization")
            .psi1
            .eps;
        let (psi1, psi1_d, psi1_dd) = (pose.psi1.re, pose.psi1.v1, pose.psi1.v2);
        let beta = self.p.beta;
        let (sp, cp) = psi1.sin_cos();
        // pressure angle (instant centre on O1O2), and the pitch curve's curvature radius
        let u = (T::one() - psi1_d) * beta;
        let alpha = ((u - cp) / sp).atan();
        let n = T::one() - u * 2.0 * cp + u * u;
        let rho_p = n * self.p.l_k * n.sqrt()
            / (n - u * u * psi1_d + u * psi1_d * cp - psi1_dd * beta * sp);
        let [d, c, b, a] = [re(&pose.d), re(&pose.c), re(&pose.b), re(&pose.a)];
        let (o3, o2) = (lift(self.p.o3), lift(self.o2));
        let (e_cd, e_o3c) = (unit(c, d), unit(o3, c));
        let (e_ab, e_o3b, e_o2a) = (unit(a, b), unit(o3, b), unit(o2, a));
        let o3c = [c[0] - self.p.o3[0], c[1] - self.p.o3[1]];
        let u_g = (T::from(self.u_g[0]), T::from(self.u_g[1]));
        Kinematics {
            s,
            s_d,
            s_dd,
            v: s_d * w,
            a: s_dd * w * w + s_d * eps,
            psi1,
            psi1_d,
            psi1_dd,
            psi1_w: psi1_d * w,
            psi1_a: psi1_dd * w * w + psi1_d * eps,
            psi1_s: psi_s,
            theta_c: o3c[1].atan2(o3c[0]),
            alpha,
            rho_p,
            cos_alpha_sh: dot(e_cd, u_g).abs(),
            sin_gamma: cross(e_o3c, e_cd).abs(),
            sin_mu: cross(e_ab, e_o3b).abs(),
            sin_delta_psi: cross(e_o2a, e_ab).abs(),
        }
    }

    /// The piercing load Q_T: the Perforators' profile while the needles rise, 0 otherwise.
    pub fn pierce_load<T: Scalar>(&self, k: &Kinematics<T>) -> T {
        if k.v.re() > 0.0 {
            self.curve.pierce_load(k.s, k.v, Phase::Forward as i32)
        } else {
            T::zero()
        }
    }

    /// Forces, eqs. (1)-(8), for kinematics `k` at shaft acceleration `eps` (any [`Scalar`]);
    /// with `hertz` false the contact stress is not computed (0).
    pub fn forces<T: Scalar>(&self, k: &Kinematics<T>, eps: T, hertz: bool) -> Forces<T> {
        let p = &self.p;
        let np = &p.needles;
        let q_t = self.pierce_load(k);
        let f_inertia = k.a * (-p.k_d * np.perf_m);
        // eq. (1), one branch's share, along −u_g
        let q_b = (q_t + p.load_f + np.perf_m * STANDARD_GRAVITY * self.u_g[1] - f_inertia
            + p.p_spring)
            / p.n;
        // friction against the motion: +1 the cam drives, −1 the load drives
        let sigma = sgn(q_b.re() * k.v.re());
        let sin_alpha_sh = max_of(T::one() - k.cos_alpha_sh * k.cos_alpha_sh, 0.0).sqrt();
        let guide = k.cos_alpha_sh - sin_alpha_sh * (sigma * np.guide_mu);
        let (e_c, e_o3, e_b, e_a, e_o2) =
            (self.eps_c, self.eps_c, self.eps_b, self.eps_a, self.eps_a);
        let (cos_alpha, g, sdp) = (k.alpha.cos(), k.sin_gamma, k.sin_delta_psi);
        let p_sh1 = q_b / guide;
        let p_c = q_b * g / (guide - sigma * (e_c + e_o3));
        let p_b = q_b * p.r_k * g / ((guide - sigma * (e_c + e_o3 + e_b)) * p.b);
        let p_sh2 = q_b * p.r_k * g / ((guide * k.sin_mu - sigma * (e_o3 + e_b + e_c)) * p.b);
        let p_a = p_sh2 * sdp;
        let f_pr = e_o3 + e_b + e_o2 + e_c + e_a;
        let p_kr = q_b * p.r * p.r_k * g * sdp
            / ((guide * k.sin_mu * cos_alpha - sigma * f_pr) * (p.b * self.l));
        // eq. (8) on the loaded flank: the working one at ρ_p − r, the other at ρ_p + r
        let flank = if p_kr.re() < 0.0 { -1.0 } else { 1.0 };
        let lost_contact = p.closure == Closure::Spring && p_kr.re() < 0.0;
        let rho_flank = (k.rho_p - flank * p.roller.r) * flank;
        let surface = if rho_flank.re() > 0.0 {
            Surface::Convex
        } else {
            Surface::Concave
        };
        let inv_rho = T::one() / rho_flank + 1.0 / p.roller.r;
        let sigma_h = if hertz && p_kr.re() != 0.0 && !lost_contact {
            p.roller.stress(p_kr, rho_flank.abs(), surface)
        } else {
            T::zero()
        };
        Forces {
            q_t,
            f_inertia,
            q_b,
            p_sh1,
            p_c,
            p_b,
            p_sh2,
            p_a,
            p_kr,
            sigma_h,
            rho_red: T::one() / inv_rho,
            flank: flank as i32,
            lost_contact,
            tau: p_kr * p.n * self.l * cos_alpha * k.psi1_d * self.psi_sense + eps * p.cam_j,
        }
    }

    /// The cam force the contact watch follows (`roller.F_margin`), any [`Scalar`]: one
    /// branch's P_kr (eq. 7); with a groove the loaded flank's, `|P_kr|`, which never pulls.
    pub fn contact_force<T: Scalar>(&self, phi: T, w: T, a: T) -> T {
        let f = self.forces(&self.kinematics(phi, w, a), a, false).p_kr;
        match self.p.closure {
            Closure::Groove => f.abs(),
            Closure::Spring => f,
        }
    }

    /// Paper 002's quantity of the β study: the largest Hertz stress over the run-up of the
    /// needles' rise (where ψ1'' > 0), at shaft speed `w`, sampled `samples` times over the
    /// rise (the `own` timing's rise; the `perforators` timing's forward travel), Pa.
    pub fn run_up_stress(&self, w: f64, samples: usize) -> f64 {
        let (start, span) = match self.p.timing {
            Timing::Own => (self.own.phi0, self.own.forward),
            Timing::Perforators => (self.curve.cyc.phi0, self.curve.cyc.forward),
        };
        (0..=samples)
            .map(|i| self.kinematics(start + span * i as f64 / samples as f64, w, 0.0))
            .filter(|k| k.psi1_dd > 0.0)
            .map(|k| self.forces(&k, 0.0, true).sigma_h)
            .fold(0.0, f64::max)
    }

    /// The roller centre on the cam (the pitch curve in the cam's frame) at `phi`:
    /// `K_cam(φ) = Rot(−φ)·K`.
    pub fn pitch_point(&self, phi: f64) -> [f64; 2] {
        let (s, ..) = self.needle(phi);
        let k = self.pose(s).expect("checked at initialization").k;
        let (sn, cs) = phi.sin_cos();
        [cs * k[0] + sn * k[1], -sn * k[0] + cs * k[1]]
    }

    /// Over a turn: the rocker stays away from 0 and π (the pressure angle is singular there)
    /// and the cam is not undercut.
    fn check_turn(&self) -> Result<(), ParamError> {
        let r = self.p.roller.r;
        for i in 0..SAMPLES {
            let phi = TAU * i as f64 / SAMPLES as f64;
            let k = self.kinematics(phi, 1.0, 0.0);
            crate::require!(
                k.psi1.sin().abs() > 1e-6,
                "kmk.kappa",
                self.p.kappa,
                "the rocker reaches psi1 = {:.2} deg at shaft angle {:.2} deg, in line with O1O2: the pressure angle is singular there",
                k.psi1.to_degrees(),
                phi.to_degrees()
            );
            let undercut = match self.p.closure {
                Closure::Groove => !(k.rho_p.abs() > r),
                Closure::Spring => k.rho_p > 0.0 && !(k.rho_p > r),
            };
            crate::require!(
                !undercut,
                "roller.r",
                r,
                "the cam is undercut at shaft angle {:.2} deg: the pitch curve's curvature radius {:.4} m is within the roller radius",
                phi.to_degrees(),
                k.rho_p
            );
        }
        Ok(())
    }
}

#[cfg(test)]
#[path = "physics_tests.rs"]
mod tests;
