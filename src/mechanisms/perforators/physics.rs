//! Pure mechanics of the perforator (needle) drive riding on the translating sewing table
//! (papers 000 and 002, `perforators.md`).
//!
//! Fixed ramp 7 → roller 8 on two-arm lever 9 (pivot O1 on the table) → rod 10 → carriage 11 with
//! the perforators 12, sliding on the table along a line at α from the vertical; tension spring 13
//! keeps the roller on the ramp. Lever frame: origin O1, y up, relative sizes × `synth.unit`.
//! Lever rotation Δγ ≥ 0 from the lowest position raises the perforators.
//!
//! The table moves along −x of the lever frame on its forward travel; `x_t` is its position
//! (0 at loading, `table.stroke` at sewing) from [`crate::mechanics::cyclogram`]. The ramp is
//! synthesized so that the perforators follow a motion law of `x_t` (rise over `ρ·h`, fall over
//! the rest); the same function holds on the return travel.
//!
//! Forces (level `kinetostatic`), in the table frame with the table's inertial force: carriage
//! along its line (rod force P, compression positive, weight, piercing load, guide friction μ,
//! inertia of its own and of the table's acceleration), lever moment balance about O1 (rod, spring
//! moment `−(M0 + kt·Δγ)`, ramp contact force along the ramp normal, lever inertia, hinge
//! friction `f·r·|F|` of seed 002 in O1, A and B reduced to the lever by their relative rates).
//! `table.F` is the force of the whole drive on the table along +x_t. The balance is in
//! [`forces`].

// `!(x > 0.0)` is deliberate throughout: a NaN parameter fails the check too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::mechanics::cyclogram::{CyclePoint, Cyclogram, Phase};
use crate::mechanics::hertz::Roller;
use crate::mechanics::motion_laws::MotionLaw;
use crate::mechanics::slider_line::{SliderLine, SliderPose};
use crate::mechanics::{ParamError, STANDARD_GRAVITY, Scalar, cross, dot};
use crate::mechanisms::sewing_table::physics::Params as TableParams;
use std::f64::consts::{FRAC_PI_2, TAU};

pub mod forces;
pub use forces::Forces;

crate::fmi_enum! {
    /// Which lever swing the ramp is built for (`synth.mode`).
    pub enum Mode ("SynthMode", "Which lever swing the ramp is built for") {
        Paper = 1 ("paper", "paper 000's gamma_sum of eq. (3); the carriage then travels 2.3 % more than lambda_S"),
        Exact = 2 ("exact", "the swing that gives exactly lambda_S"),
    }
}

/// Parameters, SI units (angles rad); field docs name the FMI variable.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// `synth.lambda_S` (1.0), `synth.lambda1` (1.07), `synth.lambda2` (2.0),
    /// `synth.lambda3` (2.03), `synth.lambda4` (1.6): relative sizes (paper 000).
    pub lambda_s: f64,
    pub lambda1: f64,
    pub lambda2: f64,
    pub lambda3: f64,
    pub lambda4: f64,
    /// `synth.gamma0` (6°), `synth.gamma1` (47°), `synth.alpha` (37°) (paper 000).
    pub gamma0: f64,
    pub gamma1: f64,
    pub alpha: f64,
    /// `synth.unit`, m (0.030: λS = 30 mm).
    pub unit: f64,
    /// `synth.mode`.
    pub mode: Mode,
    /// The table: its synthesis (`synth.l1`, `synth.R`, `synth.alpha2`) and cyclogram.
    pub table: TableParams,
    /// `travel.rise_fraction` ρ (0.5, paper 000: top at half the travel).
    pub rise_fraction: f64,
    /// `law.rise`, `law.fall` of the needles over the table travel.
    pub law_rise: MotionLaw,
    pub law_fall: MotionLaw,
    /// `pierce.Q` (215.75 N = 22 kgf, paper 002), `pierce.s_in` (0.55), `pierce.s_out` (0.75),
    /// `pierce.k_f` (0.15).
    pub pierce_q: f64,
    pub pierce_s_in: f64,
    pub pierce_s_out: f64,
    pub pierce_k_f: f64,
    /// `perf.m`: carriage and perforators, kg (0.6, assumption).
    pub perf_m: f64,
    /// `guide.mu`: carriage guide friction (0.1, assumption).
    pub guide_mu: f64,
    /// `lever.J` about O1, kg·m² (0.002, assumption).
    pub lever_j: f64,
    /// `spring.M0` N·m (6), `spring.kt` N·m/rad (20) (assumption).
    pub spring_m0: f64,
    pub spring_kt: f64,
    /// `joint.f` (0.05), `joint.r` m (0.006) (seed 002's hinge friction).
    pub joint_f: f64,
    pub joint_r: f64,
    /// `roller.r`, `roller.b` m (0.010, assumption), `ramp.E`, `roller.E` Pa (2.1e11).
    pub roller: Roller,
    /// The linkage as made: how far its links are from the design the ramp is built for.
    pub made: Made,
}

/// Manufacturing deviations of the linkage from its design, m (`made.d_rod`, `made.d_arm`,
/// `made.d_line`; all 0 by default): the ramp is cut for the design ([`Params::synthesis`], the
/// needle law), the lever and the carriage move as made. The roller arm λ4 is as designed, so
/// the ramp still sets the lever angle; the rod, the lever arm to the rod and the carriage
/// line's distance from the pivot change the needles' travel for that angle.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Made {
    /// Rod length minus λ1·unit.
    pub d_rod: f64,
    /// Lever arm to the rod minus λ3·unit.
    pub d_arm: f64,
    /// Distance of the carriage line from the pivot minus λ2·unit.
    pub d_line: f64,
}

impl Made {
    /// Is the linkage made exactly as designed?
    pub fn exact(&self) -> bool {
        *self == Made::default()
    }
}

impl Default for Params {
    fn default() -> Self {
        Self {
            lambda_s: 1.0,
            lambda1: 1.07,
            lambda2: 2.0,
            lambda3: 2.03,
            lambda4: 1.6,
            gamma0: 6f64.to_radians(),
            gamma1: 47f64.to_radians(),
            alpha: 37f64.to_radians(),
            unit: 0.030,
            mode: Mode::Exact,
            table: TableParams::default(),
            rise_fraction: 0.5,
            law_rise: MotionLaw::Cycloidal,
            law_fall: MotionLaw::Cycloidal,
            pierce_q: 22.0 * STANDARD_GRAVITY,
            pierce_s_in: 0.55,
            pierce_s_out: 0.75,
            pierce_k_f: 0.15,
            perf_m: 0.6,
            guide_mu: 0.1,
            lever_j: 0.002,
            spring_m0: 6.0,
            spring_kt: 20.0,
            joint_f: 0.05,
            joint_r: 0.006,
            roller: Roller::steel(0.010, 0.010),
            made: Made::default(),
        }
    }
}

/// The paper's synthesis, eqs. (2)-(4), relative units and rad.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Synthesis {
    /// ν, eq. (2) (28.79°).
    pub nu: f64,
    /// γΣ, eq. (3) (28.93°).
    pub gamma_sum: f64,
    /// SΣ, eq. (4) (0.7023).
    pub s_sum: f64,
}

/// Everything fixed for a run: geometry in metres, the swing, the stroke.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drive {
    pub p: Params,
    pub line: SliderLine,
    /// `s(0)`, m.
    pub s0: f64,
    /// Branch of the inverse (see [`SliderLine::joint_on_circle`]).
    pub branch: f64,
    /// The paper's swing γΣ and the exact swing, rad.
    pub gamma_paper: f64,
    pub gamma_exact: f64,
    /// The swing the ramp is built for, rad.
    pub gamma_sw: f64,
    /// `perforators.stroke` S = s(γ_sw) − s(0), m.
    pub stroke: f64,
    /// Table stroke h, m, and cyclogram.
    pub cyc: Cyclogram,
    /// The linkage as made ([`Made`]): `p` with the made link lengths; equal to `p` when made
    /// exactly. The needles' travel, the rod and the carriage's inertia follow it.
    pub made: Params,
    /// Its carriage line and `s(0)`.
    pub made_line: SliderLine,
    pub made_s0: f64,
    /// `sin α`, `cos α` of the carriage line's incline α (`synth.alpha`, as made as designed).
    pub alpha_sin_cos: (f64, f64),
}

/// Kinematics at one shaft state (any [`Scalar`]: `f64`, or dual numbers for the exact partial
/// derivatives in the inputs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Kinematics<T = f64> {
    pub phase: i32,
    /// Table position x_t, `dx_t/dφ`, velocity, acceleration.
    pub x_t: T,
    pub x_t_d: T,
    pub v_t: T,
    pub a_t: T,
    /// `perforators.s`, `.v`, `.a`.
    pub s: T,
    pub v: T,
    pub a: T,
    /// `lever.gamma` Δγ, `lever.w`, `lever.a`; `dΔγ/dx_t`, `d²Δγ/dx_t²`.
    pub gamma: T,
    pub gamma_w: T,
    pub gamma_a: T,
    pub gamma_x: T,
    pub gamma_xx: T,
    /// `sin ν` of the rod to the carriage line (`rod.nu`, with `roller.rise` and `ramp.theta`
    /// outputs only: [`Drive::output_angles`] makes them where they are written, not in every
    /// right-hand side of the elastodynamic level).
    pub sin_nu: T,
    /// Ramp: upward unit normal (ground frame), `ramp.rho` (profile, + convex).
    pub normal: (T, T),
    /// `dn/dx_t` of that normal, 1/m (the elastodynamic level's penetration rate).
    pub normal_x: (T, T),
    pub rho: T,
}

const SAMPLES: usize = 2000;

/// A point of a plane curve with its first and second derivatives.
pub type Vec3<T = f64> = ((T, T), (T, T), (T, T));

/// The linkage at one lever angle Δγ: joint A ([`Params::joint_a`]), the carriage's pose
/// ([`Params::carriage`]) and the roller centre ([`Params::roller`]), each with its derivatives
/// in Δγ: what the forces take from the angle alone. The elastic lever's balance iterates on
/// the lever's acceleration at one angle, so it computes them once.
#[derive(Clone, Copy, Debug)]
pub struct Linkage<T = f64> {
    pub a: Vec3<T>,
    pub pose: SliderPose<T>,
    pub r: Vec3<T>,
}

impl Params {
    /// Paper 000, eqs. (2)-(4).
    pub fn synthesis(&self) -> Synthesis {
        let nu = ((self.lambda2 - self.lambda3 * (self.alpha + self.gamma0).cos()) / self.lambda1)
            .asin();
        let gamma_sum = ((self.lambda_s * self.alpha.cos()
            + self.lambda1 * (self.alpha - nu).cos()
            - self.lambda3 * self.gamma0.sin()
            - self.lambda1 * self.alpha.cos())
            / self.lambda3)
            .asin()
            + self.gamma0;
        let s_sum =
            self.lambda4 * self.gamma1.cos() - self.lambda4 * (gamma_sum + self.gamma1).cos();
        Synthesis {
            nu,
            gamma_sum,
            s_sum,
        }
    }

    /// The linkage as made: the design with the deviations of [`Params::made`] in λ1, λ2, λ3.
    pub fn as_made(&self) -> Params {
        let u = self.unit;
        Params {
            lambda1: self.lambda1 + self.made.d_rod / u,
            lambda2: self.lambda2 + self.made.d_line / u,
            lambda3: self.lambda3 + self.made.d_arm / u,
            made: Made::default(),
            ..*self
        }
    }

    fn slider_line(&self) -> SliderLine {
        SliderLine::new(
            self.lambda1 * self.unit,
            self.lambda2 * self.unit,
            self.alpha,
        )
    }

    /// Rod joint A, `dA/dΔγ`, `d²A/dΔγ²`, m (any [`Scalar`]).
    pub fn joint_a<T: Scalar>(&self, g: T) -> Vec3<T> {
        let r = self.lambda3 * self.unit;
        let (s, c) = (g - self.gamma0).sin_cos();
        ((c * r, s * r), (s * -r, c * r), (c * -r, s * -r))
    }

    /// Roller centre R, `dR/dΔγ`, `d²R/dΔγ²` in the lever frame, m (any [`Scalar`]).
    pub fn roller<T: Scalar>(&self, g: T) -> Vec3<T> {
        let r = self.lambda4 * self.unit;
        let (s, c) = (g + self.gamma1).sin_cos();
        ((s * r, c * -r), (c * r, s * r), (s * -r, c * r))
    }

    /// Carriage position `s(Δγ)` along `u` and its derivatives, m (any [`Scalar`]).
    pub fn carriage<T: Scalar>(&self, g: T) -> SliderPose<T> {
        self.carriage_on(&self.slider_line(), g)
    }

    /// [`Params::carriage`] on `line`, this linkage's line made once ([`Drive`] keeps it).
    fn carriage_on<T: Scalar>(&self, line: &SliderLine, g: T) -> SliderPose<T> {
        let (a, a1, a2) = self.joint_a(g);
        line.pose(a, a1, a2)
    }

    /// The linkage at lever angle Δγ on `line`, this linkage's line made once ([`Linkage`];
    /// any [`Scalar`]).
    fn linkage_on<T: Scalar>(&self, line: &SliderLine, g: T) -> Linkage<T> {
        let a = self.joint_a(g);
        Linkage {
            a,
            pose: line.pose(a.0, a.1, a.2),
            r: self.roller(g),
        }
    }

    /// Checks the parameters and derives the run's constants.
    pub fn drive(&self) -> Result<Drive, ParamError> {
        self.table.validate()?;
        let arg2 = (self.lambda2 - self.lambda3 * (self.alpha + self.gamma0).cos()) / self.lambda1;
        crate::require!(
            arg2.abs() <= 1.0,
            "synth.lambda1",
            self.lambda1,
            "eq. (2): (lambda2 - lambda3*cos(alpha + gamma0))/lambda1 = {arg2:.4} is outside [-1, 1]"
        );
        let syn = self.synthesis();
        crate::require!(
            syn.gamma_sum.is_finite(),
            "synth.lambda_S",
            self.lambda_s,
            "eq. (3): the arcsine argument is outside [-1, 1]: the lever cannot swing far enough for this stroke"
        );
        crate::require!(
            self.rise_fraction > 0.0 && self.rise_fraction < 1.0,
            "travel.rise_fraction",
            self.rise_fraction,
            "must lie strictly between 0 and 1"
        );
        crate::require!(
            self.pierce_s_in < self.pierce_s_out && self.pierce_s_out <= 1.0,
            "pierce.s_out",
            self.pierce_s_out,
            "must lie in (pierce.s_in = {}, 1]",
            self.pierce_s_in
        );
        let line = self.slider_line();
        let (a0, _, _) = self.joint_a(0.0);
        let s0 = self.carriage(0.0).s;
        let target = self.lambda_s * self.unit;
        // exact swing: s rises monotonically from s(0) until it reaches s0 + λS
        let (mut lo, mut hi) = (0.0f64, 0.0f64);
        let step = 1e-3;
        loop {
            let g = hi + step;
            let c = self.carriage(g);
            if !(c.s.is_finite() && c.ds > 0.0) || g > FRAC_PI_2 {
                return Err(ParamError::new(
                    "synth.lambda_S",
                    self.lambda_s,
                    format!(
                        "the linkage cannot raise the perforators that far (it reaches {:.4} before the rod or lever turns back)",
                        (self.carriage(hi).s - s0) / self.unit
                    ),
                ));
            }
            if c.s - s0 >= target {
                hi = g;
                break;
            }
            lo = g;
            hi = g;
        }
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if self.carriage(mid).s - s0 < target {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let gamma_exact = 0.5 * (lo + hi);
        let gamma_paper = syn.gamma_sum;
        let gamma_sw = match self.mode {
            Mode::Paper => gamma_paper,
            Mode::Exact => gamma_exact,
        };
        let mut g = 0.0;
        while g < gamma_sw {
            crate::require!(
                self.carriage(g).ds > 0.0,
                "synth.gamma0",
                self.gamma0,
                "the perforators do not rise monotonically over the swing (at lever angle {:.2} deg)",
                g.to_degrees()
            );
            g += 1e-3;
        }
        let stroke = self.carriage(gamma_sw).s - s0;
        let made = if self.made.exact() {
            *self
        } else {
            self.as_made()
        };
        // the linkage as made must follow the ramp's whole swing, the needles rising
        let mut g = 0.0;
        while g <= gamma_sw + 1e-3 {
            let c = made.carriage(g.min(gamma_sw));
            if !(c.s.is_finite() && c.ds > 0.0) {
                let (name, value) = if self.made.d_rod != 0.0 {
                    ("made.d_rod", self.made.d_rod)
                } else if self.made.d_arm != 0.0 {
                    ("made.d_arm", self.made.d_arm)
                } else {
                    ("made.d_line", self.made.d_line)
                };
                return Err(ParamError::new(
                    name,
                    value,
                    format!(
                        "the linkage as made cannot follow the ramp: at lever angle {:.2} deg the rod no longer moves the carriage up",
                        g.to_degrees()
                    ),
                ));
            }
            g += 1e-3;
        }
        let d = Drive {
            p: *self,
            line,
            s0,
            branch: line.branch_of(a0),
            gamma_paper,
            gamma_exact,
            gamma_sw,
            stroke,
            cyc: self.table.cyclogram(),
            made,
            made_line: made.slider_line(),
            made_s0: made.carriage(0.0).s,
            alpha_sin_cos: made.alpha.sin_cos(),
        };
        d.check_ramp()?;
        Ok(d)
    }
}

impl Drive {
    /// [`Params::carriage`] of the linkage as made, on its line made once (the same values).
    pub fn carriage<T: Scalar>(&self, g: T) -> SliderPose<T> {
        self.made.carriage_on(&self.made_line, g)
    }

    /// The linkage as made at lever angle Δγ, on its line made once ([`Linkage`]).
    pub fn linkage<T: Scalar>(&self, g: T) -> Linkage<T> {
        self.made.linkage_on(&self.made_line, g)
    }

    /// `synth.stroke_error`: the paper's stroke over the exact one, minus 1.
    pub fn stroke_error(&self) -> f64 {
        (self.p.carriage(self.gamma_paper).s - self.s0) / (self.p.lambda_s * self.p.unit) - 1.0
    }

    /// Lever angle for a perforator displacement `s_p` (the inverse of `perforators.md`; any
    /// [`Scalar`]).
    pub fn gamma_of<T: Scalar>(&self, s_p: T) -> T {
        let a = self
            .line
            .joint_on_circle(self.p.lambda3 * self.p.unit, s_p + self.s0, self.branch)
            .unwrap_or((T::from(f64::NAN), T::from(f64::NAN)));
        let g = a.1.atan2(a.0) + self.p.gamma0;
        // keep Δγ continuous through ±π
        if g.re() > std::f64::consts::PI {
            g - TAU
        } else {
            g
        }
    }

    /// The needles' law over the table travel: `(s_p, ds_p/dx_t, d²s_p/dx_t²)`.
    pub fn needle_law<T: Scalar>(&self, x_t: T) -> (T, T, T) {
        let h = self.cyc.h;
        let rh = self.p.rise_fraction * h;
        if x_t.re() <= rh {
            self.p.law_rise.rise(self.stroke, rh, x_t)
        } else {
            self.p.law_fall.fall(self.stroke, h - rh, x_t - rh)
        }
    }

    /// Lever angle as a function of the table position: `(Δγ, dΔγ/dx_t, d²Δγ/dx_t²)`, and the
    /// needle law's `(s_p, ds_p/dx_t, d²s_p/dx_t²)` (any [`Scalar`]).
    pub fn gamma_of_x<T: Scalar>(&self, x_t: T) -> (T, T, T, T, T, T) {
        let (s, sx, sxx) = self.needle_law(x_t);
        let g = self.gamma_of(s);
        let c = self.p.carriage_on(&self.line, g);
        let gs = T::one() / c.ds;
        let gss = -c.dds * gs * gs * gs;
        (g, gs * sx, gss * sx * sx + gs * sxx, s, sx, sxx)
    }

    /// Ramp pitch curve in the ground frame (lever frame at loading): `C(x_t) = (−x_t, 0) + R(Δγ)`,
    /// with `C'`, `C''` in x_t.
    pub fn ramp<T: Scalar>(&self, x_t: T) -> Vec3<T> {
        let (g, gx, gxx, ..) = self.gamma_of_x(x_t);
        self.ramp_at(x_t, self.p.roller(g), gx, gxx)
    }

    /// [`Drive::ramp`] at `x_t` from the roller centre there ([`Params::roller`] at the lever
    /// angle) and the angle's derivatives in `x_t` ([`Drive::gamma_of_x`]), which a caller that
    /// has them need not repeat.
    fn ramp_at<T: Scalar>(&self, x_t: T, roller: Vec3<T>, gx: T, gxx: T) -> Vec3<T> {
        let (r, r1, r2) = roller;
        (
            (r.0 - x_t, r.1),
            (r1.0 * gx - 1.0, r1.1 * gx),
            (r2.0 * gx * gx + r1.0 * gxx, r2.1 * gx * gx + r1.1 * gxx),
        )
    }

    /// Ramp at x_t: upward normal, signed profile curvature radius (+ convex hill, − concave
    /// valley), and whether the profile is convex.
    pub fn ramp_geometry(&self, x_t: f64) -> ((f64, f64), f64, bool) {
        let (n, rho, convex, _) = self.ramp_frame(x_t);
        (n, rho, convex)
    }

    /// As [`Drive::ramp_geometry`], with the normal's rate `dn/dx_t`: with the unit tangent
    /// `t = C'/|C'|`, `dt/dx = (C'' − t·(t·C''))/|C'|` and `n = (t_y, −t_x)`.
    pub fn ramp_frame(&self, x_t: f64) -> ((f64, f64), f64, bool, (f64, f64)) {
        let (_, c1, c2) = self.ramp(x_t);
        self.frame_of(c1, c2)
    }

    /// [`Drive::ramp_frame`] from the pitch curve's first and second derivatives (any
    /// [`Scalar`]; valley or hill decided on the real parts).
    #[allow(clippy::type_complexity)]
    fn frame_of<T: Scalar>(&self, c1: (T, T), c2: (T, T)) -> ((T, T), T, bool, (T, T)) {
        let len = dot(c1, c1).sqrt();
        let t = (c1.0 / len, c1.1 / len);
        let n = (t.1, -t.0);
        let tc = dot(t, c2);
        let dt = ((c2.0 - t.0 * tc) / len, (c2.1 - t.1 * tc) / len);
        let n_x = (dt.1, -dt.0);
        let bend = cross(c1, c2).abs();
        // a straight stretch (the table's dwells): the radius is infinite all along it, with
        // the derivative 0
        let rho_pitch = if bend.re() == 0.0 {
            T::from(len.re() * len.re() * len.re() / bend.re())
        } else {
            len * len * len / bend
        };
        let valley = dot(c2, n).re() > 0.0;
        if valley {
            (n, -(rho_pitch + self.p.roller.r), false, n_x)
        } else {
            (n, rho_pitch - self.p.roller.r, true, n_x)
        }
    }

    /// "A ramp the roller cannot follow" (`interface.md`): a pitch curve folding back, or an
    /// undercut convex profile.
    fn check_ramp(&self) -> Result<(), ParamError> {
        for k in 0..=SAMPLES {
            let x = self.cyc.h * k as f64 / SAMPLES as f64;
            let (_, c1, c2) = self.ramp(x);
            crate::require!(
                c1.0 < 0.0,
                "synth.lambda4",
                self.p.lambda4,
                "the ramp folds back at table position {:.2} mm: the roller cannot follow it",
                1000.0 * x
            );
            let (_, rho, convex, _) = self.frame_of(c1, c2);
            crate::require!(
                !convex || rho > 0.0,
                "roller.r",
                self.p.roller.r,
                "the ramp profile is undercut at table position {:.2} mm (pitch curvature radius {:.4} m <= roller.r)",
                1000.0 * x,
                rho + self.p.roller.r
            );
        }
        Ok(())
    }

    /// At rest in the loading dwell, 0.1 rad before the forward travel: the lowest position,
    /// where the spring's preload alone presses the roller on the ramp.
    pub fn at_loading(&self) -> Kinematics {
        self.kinematics(self.cyc.phi0 - 0.1, 0.0, 0.0)
    }

    /// The roller's force at rest in the loading dwell ([`Drive::at_loading`]), N.
    pub fn loading_force(&self) -> f64 {
        self.forces(&self.at_loading()).roller_f
    }

    /// Kinematics at shaft angle `phi`, speed `w`, acceleration `eps` (any [`Scalar`]).
    pub fn kinematics<T: Scalar>(&self, phi: T, w: T, eps: T) -> Kinematics<T> {
        let c: CyclePoint<T> = self.cyc.at(phi);
        let (v_t, a_t) = c.motion(w, eps);
        let (g, gx, gxx, s, sx, sxx) = self.gamma_of_x(c.x);
        let g_d = gx * c.dx;
        let g_dd = gxx * c.dx * c.dx + gx * c.ddx;
        let pose = self.carriage(g);
        // the needles follow their law exactly; as made, the linkage's travel for the lever angle
        let (s, s_d, s_dd) = if self.p.made.exact() {
            (s, sx * c.dx, sxx * c.dx * c.dx + sx * c.ddx)
        } else {
            (
                pose.s - self.made_s0,
                pose.ds * g_d,
                pose.dds * g_d * g_d + pose.ds * g_dd,
            )
        };
        let roller = self.p.roller(g);
        let (_, c1, c2) = self.ramp_at(c.x, roller, gx, gxx);
        let (n, rho, _, n_x) = self.frame_of(c1, c2);
        Kinematics {
            phase: c.phase as i32,
            x_t: c.x,
            x_t_d: c.dx,
            v_t,
            a_t,
            s,
            v: s_d * w,
            a: s_dd * w * w + s_d * eps,
            gamma: g,
            gamma_w: g_d * w,
            gamma_a: g_dd * w * w + g_d * eps,
            gamma_x: gx,
            gamma_xx: gxx,
            sin_nu: pose.sin_nu,
            normal: n,
            normal_x: n_x,
            rho,
        }
    }

    /// `rod.nu`, `roller.rise` (m) and `ramp.theta` (the pressure angle: the ramp's normal
    /// against the roller centre's direction of motion on the lever) of a [`Kinematics`] (any
    /// [`Scalar`]).
    pub fn output_angles<T: Scalar>(&self, k: &Kinematics<T>) -> (T, T, T) {
        let p = &self.p;
        let l4 = p.lambda4 * p.unit;
        let (_, r1, _) = p.roller(k.gamma);
        let tr = (r1.0 / l4, r1.1 / l4);
        let n = k.normal;
        (
            k.sin_nu.asin(),
            (T::from(p.gamma1.cos()) - (k.gamma + p.gamma1).cos()) * l4,
            cross(tr, n).atan2(dot(tr, n)),
        )
    }

    /// Piercing load magnitude (`perforators.md`): forward travel only; rising: 0 below s_in,
    /// linear to Q at the middle of [s_in, s_out], linear to k_f·Q at s_out, k_f·Q above; falling:
    /// k_f·Q while above s_in.
    pub fn pierce_load<T: Scalar>(&self, s: T, v: T, phase: i32) -> T {
        if phase != Phase::Forward as i32 || self.stroke <= 0.0 {
            return T::zero();
        }
        let p = &self.p;
        let q = s / self.stroke;
        let (si, so) = (p.pierce_s_in, p.pierce_s_out);
        let mid = 0.5 * (si + so);
        if v.re() > 0.0 {
            if q.re() <= si {
                T::zero()
            } else if q.re() <= mid {
                (q - si) * p.pierce_q / (mid - si)
            } else if q.re() <= so {
                (T::one() - (q - mid) * (1.0 - p.pierce_k_f) / (so - mid)) * p.pierce_q
            } else {
                T::from(p.pierce_k_f * p.pierce_q)
            }
        } else if v.re() < 0.0 && q.re() > si {
            T::from(p.pierce_k_f * p.pierce_q)
        } else {
            T::zero()
        }
    }

    /// Smallest contact force over one turn at constant speed `w` (and the shaft angle).
    pub fn min_contact_force(&self, w: f64, samples: usize) -> (f64, f64) {
        let mut worst = (f64::INFINITY, 0.0);
        for i in 0..samples {
            let phi = self.cyc.phi0 + TAU * i as f64 / samples as f64;
            let f = self.forces(&self.kinematics(phi, w, 0.0)).roller_f;
            if f < worst.0 {
                worst = (f, phi);
            }
        }
        worst
    }

    /// The lowest constant speed (rad/s) in `(lo, hi]` at which the roller lifts off somewhere in
    /// the turn, by bisection to `tol`; `None` if it does not lift off at `hi` or already does at
    /// `lo`.
    pub fn liftoff_speed(&self, lo: f64, hi: f64, tol: f64, samples: usize) -> Option<f64> {
        let lifts = |w: f64| self.min_contact_force(w, samples).0 < 0.0;
        if lifts(lo) || !lifts(hi) {
            return None;
        }
        let (mut lo, mut hi) = (lo, hi);
        while hi - lo > tol {
            let mid = 0.5 * (lo + hi);
            if lifts(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        Some(hi)
    }

    /// Mechanical energy of the drive (table frame plus table motion): carriage kinetic energy in
    /// the ground frame, lever kinetic energy, spring and carriage potential energy.
    /// Any [`Scalar`].
    pub fn energy<T: Scalar>(&self, k: &Kinematics<T>) -> T {
        let p = &self.p;
        let u = self.line.u();
        // carriage velocity in the ground frame: v_p·u − v_t·e_x
        let vc = (k.v * u.0 - k.v_t, k.v * u.1);
        dot(vc, vc) * (0.5 * p.perf_m)
            + k.gamma_w * (0.5 * p.lever_j) * k.gamma_w
            + k.gamma * p.spring_m0
            + k.gamma * (0.5 * p.spring_kt) * k.gamma
            + k.s * (p.perf_m * STANDARD_GRAVITY) * p.alpha.cos()
    }
}

#[cfg(test)]
mod tests;
