//! The SewingTable FMU: its variables, declared once, and the glue from them to
//! [`super::physics`] (`../shared/spec/sewing-table.md`).

use super::elastic::{TableMemory, TableOde};
use super::physics::{Forces, Kind, Kinematics, Params, Rocking};
use crate::mechanics::cyclogram::Phase;
use crate::mechanics::hertz::{Roller, Surface};
use crate::mechanics::motion_laws::MotionLaw;
use crate::mechanics::{SpringDamper, clamp_of};
use crate::model::partials::{Put, Scalar, Seeded, put_zero};
use crate::model::shaft::{self, Fidelity, ON_ALL, ON_PHI, ON_PHI_W, ShaftState};
use crate::model::{Dynamics, EnumType, Experiment, Log, Model, ParamError, Stage, Values, VarSet};
use crate::solver::ShaftPath;
use crate::solver::chain::ChainOde;
use crate::solver::chain::{self, Chain, ChainModel, LastAt, Peaks};
use std::cell::Cell;

/// `law.*` (`motion-laws.md`), shared by SewingTable and Perforators.
pub static MOTION_LAW: EnumType = EnumType {
    name: "MotionLaw",
    description: "Normalized cam motion law",
    items: &[
        ("cycloidal", "sine acceleration; paper 002's 'Co'"),
        (
            "harmonic",
            "cosine acceleration; paper 002's 'K'; acceleration jumps at the ends",
        ),
        ("poly345", "3-4-5 polynomial"),
    ],
};

/// The law of a `law.*` value (1-based item of [`MOTION_LAW`]).
pub fn motion_law(item: i32) -> MotionLaw {
    match item {
        2 => MotionLaw::Harmonic,
        3 => MotionLaw::Poly345,
        _ => MotionLaw::Cycloidal,
    }
}

/// The table's synthesis (`synth.l1`, `synth.R`, `synth.alpha2`, `synth.unit`) and cyclogram
/// (`cycle.*`, `law.forward`, `law.return`) from the variables of those names (read by name:
/// SewingTable and the Perforators riding on its table declare them, each in its own enum); the
/// rest at its defaults (the translating table).
pub fn table_params<V: VarSet>(v: &Values<V>) -> Params {
    let x = |name| v.named(name);
    Params {
        l1: x("synth.l1"),
        r: x("synth.R"),
        alpha2: x("synth.alpha2"),
        unit: x("synth.unit"),
        forward: x("cycle.forward"),
        dwell_sew: x("cycle.dwell_sew"),
        ret: x("cycle.return"),
        phi0: x("cycle.phi0"),
        law_forward: motion_law(x("law.forward") as i32),
        law_return: motion_law(x("law.return") as i32),
        ..Params::default()
    }
}

/// Dependencies of what the external force on the table acts on.
const ON_ALL_F: &[u32] = &[shaft::PHI, shaft::W, shaft::A, V::table_F_ext as u32];

crate::stages! {
    FLANK = Stage::new("flank", "Force solution for the loaded slot flank and its curvature radius (cam.rho)", Fidelity::ALL),
    FORCES = Stage::new("forces", "Kinetostatic force analysis: inertia, guide friction, cam force, shaft torque", Fidelity::WITH_FORCES),
    HERTZ = Stage::new("hertz", "Hertz contact stress at the loaded flank (paper 002 eq. 8)", Fidelity::WITH_FORCES).requires(stage::FLANK),
    ROCKING = Stage::new("rocking", "The BNSh-6A's rocking table, computed alongside for comparison (rocking.*)", Fidelity::ALL),
    SYNTHESIS = Stage::new("synthesis", "Paper 000's synthesis reported as calculated parameters (rewritten at every evaluation), and the smallest base radius without undercut (a search at initialization)", Fidelity::ALL),
    ELASTIC = Stage::new("elastic", "The ODE of the compliant cam-follower chain (with slot play), integrated inside fmi2DoStep", Fidelity::DYNAMIC).always();
    /// What the table's mass and guide friction feed.
    LOADS = FLANK.or(FORCES).or(HERTZ).or(ELASTIC),
}

crate::model_variables! {
    pub enum V (nominal_rpm = 100.0, torque_depends = ON_ALL_F, torque_needs = stage::FORCES) {
        // ---- synthesis (paper 000)
        synth_l1 = Var::parameter("synth.l1", 1.0, "", "l1: rocking axis to the table top in the sewing position, relative (paper 000: 1.0)").min(0.0),
        synth_R = Var::parameter("synth.R", 11.0, "", "R: diagonal OA from the rocking axis to the top, relative (paper 000: 11.0)").min(0.0),
        synth_alpha2 = Var::parameter("synth.alpha2", 20f64.to_radians(), "rad", "alpha2: swing of the rocking table (paper 000: 20 deg)").min(0.0).max(std::f64::consts::FRAC_PI_2),
        synth_unit = Var::parameter("synth.unit", 0.030, "m", "The relative unit (assumption: the perforators' lambda_S = 1 = 30 mm)").min(0.0),
        // ---- cyclogram
        cycle_forward = Var::parameter("cycle.forward", 82f64.to_radians(), "rad", "Shaft angle of the forward travel I -> III (paper 000: perforators rise over half of it, phi = 41 deg)").min(0.0),
        cycle_dwell_sew = Var::parameter("cycle.dwell_sew", 110f64.to_radians(), "rad", "Dwell at the sewing position (assumption)").min(0.0),
        cycle_return = Var::parameter("cycle.return", 90f64.to_radians(), "rad", "Shaft angle of the return travel (assumption)").min(0.0),
        cycle_phi0 = Var::parameter("cycle.phi0", 0.0, "rad", "Shaft angle where the forward travel starts"),
        law_forward = Var::enum_parameter("law.forward", &MOTION_LAW, "cycloidal", "Motion law of the forward travel (cycloidal: the smooth stop paper 000 asks for)"),
        law_return = Var::enum_parameter("law.return", &MOTION_LAW, "cycloidal", "Motion law of the return travel"),
        table_kind = Var::enum_parameter("table.kind", &Kind::FMI, "translating", "translating (paper 000) or rocking (the table it replaces; drives table.x, forces and shaft.tau)"),
        // ---- cam and forces
        cam_R0 = Var::parameter("cam.R0", 0.10, "m", "Base (pitch) radius of the slot cam (assumption; tune against the pressure angle)").min(0.0),
        cam_e = Var::parameter("cam.e", 0.0, "m", "Offset of the follower line from the cam axis (assumption)"),
        roller_r = Var::parameter("roller.r", 0.015, "m", "Cam roller radius (assumption)").min(0.0).feeds(stage::FLANK.or(stage::HERTZ).or(stage::SYNTHESIS)),
        roller_b = Var::parameter("roller.b", 0.015, "m", "Cam roller width (assumption)").min(0.0).feeds(stage::HERTZ),
        cam_E = crate::mechanisms::cam_e(stage::HERTZ),
        roller_E = crate::mechanisms::roller_e(stage::HERTZ),
        table_m = Var::parameter("table.m", 8.0, "kg", "Mass of table, saddle, signature and perforator assembly (assumption)").min(0.0).feeds(stage::LOADS),
        guide_f = Var::parameter("guide.f", 0.005, "", "Rolling friction coefficient of the guide rollers on the load m*g + |Fn*sin(theta_p)| (assumption)").min(0.0).feeds(stage::LOADS),
        cam_J = Var::parameter("cam.J", 0.02, "kg.m2", "Moment of inertia of the cam on the main shaft (assumption)").min(0.0).feeds(stage::FORCES.or(stage::ELASTIC)),
        rocking_J = Var::parameter("rocking.J", 0.8712, "kg.m2", "Rocking table's moment of inertia about its axis (assumption: table.m at the saddle radius R*unit = 0.33 m)").min(0.0).feeds(stage::ROCKING.or(stage::FORCES)),
        // ---- input besides the shaft
        table_F_ext = Var::input("table.F_ext", 0.0, "N", "Force on the table along +x (towards sewing) from outside, e.g. Perforators.table.F"),
        // ---- calculated parameters (paper 000's synthesis)
        synth_alpha1 = Var::calculated("synth.alpha1", "rad", "alpha1 = arcsin(l1/R) (paper 000: 5.22 deg)").needs(stage::SYNTHESIS),
        synth_A1A2 = Var::calculated("synth.A1A2", "", "A1A2 = 2R*sin(alpha2/2) (paper 000: 3.82)").needs(stage::SYNTHESIS),
        synth_k1 = Var::calculated("synth.k1", "", "k1 = R*cos(alpha2/2) (paper 000: 10.83)").needs(stage::SYNTHESIS),
        synth_alpha3 = Var::calculated("synth.alpha3", "rad", "alpha3 = 90 deg - (alpha1 + alpha2) (paper 000: 64.78 deg)").needs(stage::SYNTHESIS),
        synth_k2 = Var::calculated("synth.k2", "", "k2 = R*sin(alpha3) (paper 000: 9.95)").needs(stage::SYNTHESIS),
        synth_k0 = Var::calculated("synth.k0", "", "k0 = k1 - k2, vertical offset of the rocking saddle, eq. (1) (paper 000: 0.88)").needs(stage::SYNTHESIS),
        synth_l2 = Var::calculated("synth.l2", "", "l2 = sqrt(A1A2^2 - k0^2): travel of the translating table, relative (paper 000: 3.72)").needs(stage::SYNTHESIS),
        table_stroke = Var::calculated("table.stroke", "m", "Table travel l2*unit (0.11152 m)").needs(stage::SYNTHESIS),
        cycle_dwell_load = Var::calculated("cycle.dwell_load", "rad", "Dwell at loading: 360 deg minus the other phases").needs(stage::SYNTHESIS),
        cam_R0_min = Var::calculated("cam.R0_min", "m", "Smallest base radius without an undercut slot flank, for these laws and roller").needs(stage::SYNTHESIS),
        // ---- outputs
        table_x = Var::output("table.x", "m", "Table position: 0 at loading, table.stroke at sewing (rocking: the saddle's horizontal displacement)").depends(ON_PHI),
        table_v = Var::output("table.v", "m/s", "Table velocity").depends(ON_PHI_W),
        table_a = Var::output("table.a", "m/s2", "Table acceleration").depends(ON_ALL),
        table_phase = Var::int_output("table.phase", "0 forward travel, 1 dwell at sewing, 2 return, 3 dwell at loading").depends(ON_PHI).event(),
        table_F_inertia = Var::output("table.F_inertia", "N", "Inertia force -m*a of the translating table (kinetostatic level)").depends(ON_ALL).needs(stage::FORCES),
        table_F_friction = Var::output("table.F_friction", "N", "Guide friction on the table along +x, -f*N*sgn(v) (kinetostatic level; 0 for rocking)").depends(ON_ALL_F).needs(stage::FORCES),
        cam_theta = Var::output("cam.theta", "rad", "Pressure angle theta_p of the slot cam (translating table)").depends(ON_PHI),
        cam_rho = Var::output("cam.rho", "m", "Curvature radius of the loaded slot flank, + convex, - concave (translating table; an inflection: 1000 m)").depends(ON_ALL_F).needs(stage::FLANK),
        cam_F = Var::output("cam.F", "N", "Normal contact force cam - roller, + when pushing towards sewing (kinetostatic level)").depends(ON_ALL_F).needs(stage::FORCES),
        cam_sigma_H = Var::output("cam.sigma_H", "Pa", "Hertz stress at the loaded flank, paper 002 eq. 8 (kinetostatic level)").depends(ON_ALL_F).needs(stage::HERTZ),
        rocking_beta = Var::output("rocking.beta", "rad", "Rocking table for comparison: swing from loading, 0 .. alpha2").depends(ON_PHI).needs(stage::ROCKING),
        rocking_x = Var::output("rocking.x", "m", "Rocking table's saddle: horizontal displacement from loading towards sewing").depends(ON_PHI).needs(stage::ROCKING),
        rocking_y = Var::output("rocking.y", "m", "Rocking table's saddle: vertical displacement from loading, up positive").depends(ON_PHI).needs(stage::ROCKING),
        rocking_M_inertia = Var::output("rocking.M_inertia", "N.m", "Rocking table's inertia torque -J*beta'' about its axis").depends(ON_ALL).needs(stage::ROCKING.or(stage::FORCES)),
        // ---- elastodynamic level (dynamics.md; translating table)
        @with crate::chain_variables { spring(stage::ELASTIC;
            1e7,
            "Stiffness of the cam-follower chain between the rigid table position and the table (elastodynamic level; assumption)",
            "Damping ratio of the follower chain, c = 2*zeta*sqrt(k*m) (elastodynamic level; assumption)",
        ) },
        cam_clearance = Var::parameter("cam.clearance", 0.0, "m", "Play of the roller in the cam slot (total); with play the roller crosses it and impacts the other flank (elastodynamic level)").min(0.0).feeds(stage::ELASTIC),
        @with crate::chain_variables { solver(stage::ELASTIC) },
        table_x_kin = Var::output("table.x_kin", "m", "Rigid reference position of the table (elastodynamic level; equals table.x at the others)").depends(ON_PHI),
        elastic_deflection = Var::output("elastic.deflection", "m", "Deflection of the follower chain table.x_kin - table.x, play included (elastodynamic level)").depends(ON_PHI).needs(stage::ELASTIC),
        elastic_F = Var::output("elastic.F", "N", "Dynamic force of the cam on the table along +x (0 while the roller crosses the play; elastodynamic level)").depends(ON_PHI_W).needs(stage::ELASTIC),
        dyn_factor = Var::output("dyn.factor", "", concat!("Dynamic factor K_d: peak |elastic.F| over the peak rigid (kinetostatic) cam force along x, of the last complete shaft turn (the running one before), the peaks taken ", crate::at_accepted_steps!(), " (elastodynamic level)")).needs(stage::ELASTIC),
        @with crate::chain_variables { contact(stage::ELASTIC;
            "Times the roller left a slot flank",
            "cam force after a landing of the roller on a flank",
            "with play; elastodynamic level",
        ) },
        @with crate::chain_variables { results(stage::ELASTIC) },
        // ---- Model Exchange states of the elastodynamic level and their derivatives
        @with crate::chain_variables { states(stage::ELASTIC, length;
            "State: table position x (elastodynamic level)",
            "State: table velocity (elastodynamic level)",
            "State: work done on table and follower spring by cam, guides, damping and table.F_ext (for the energy balance)",
        ) },
        // ---- events (FMI 3.0 early return)
        contact_open = Var::bool_output("contact.open", "True while the roller crosses the slot's play, off both flanks: it rises when the roller leaves a flank, falls when it lands on one (elastodynamic level with cam.clearance; false otherwise)").needs(stage::ELASTIC).event(),
    }
}

/// The cam-follower chain of the elastodynamic level: its constants.
#[derive(Clone, Debug, PartialEq)]
struct TableChain {
    spring: SpringDamper,
    /// Half the slot's clearance, m.
    gap: f64,
}

/// What the elastodynamic level carries between steps.
type Dynamic = Chain<TableChain>;

/// The default Model Exchange hooks: a flank contact that opened or closed since the last event
/// or completed step is counted (a lift-off) or marked (a landing) at whichever comes first.
impl ChainModel for TableChain {
    type Var = V;
    type Physics = Params;
    type Memory = TableMemory;
    type Ode<'a> = TableOde<'a>;
    const SAVED_INDICATORS: usize = <SewingTable as Dynamics<V>>::EVENT_INDICATORS;

    fn ode<'a>(
        &self,
        p: &'a Params,
        path: ShaftPath,
        v: &Values<V>,
        m: &TableMemory,
    ) -> TableOde<'a> {
        TableOde {
            p,
            spring: self.spring,
            gap: self.gap,
            f_ext: v[V::table_F_ext],
            path,
            memory: Cell::new(*m),
            rigid: LastAt::default(),
        }
    }
    fn start(_: &TableOde, path: &ShaftPath, m: &mut TableMemory) {
        m.peaks.turn = (path.cycle(path.t0), 0.0, 0.0);
    }
    fn absorb(ode: &TableOde, m: &mut TableMemory) {
        *m = ode.memory.get();
    }
    /// A deflection beyond the table's travel: the chain is too soft to drive the table.
    fn non_physical(&self, ode: &TableOde, t: f64, y: &[f64; 3]) -> Option<String> {
        let names = ["follower chain", "table's travel", "table"];
        let delta = ode.point(t, y).delta;
        chain::beyond_travel(delta, ode.p.stroke(), t, self.spring.k, names)
    }
}

/// The translating sewing table of paper 000 as an FMU model.
pub struct SewingTable {
    params: Params,
    r0_min: f64,
    dynamic: Option<Dynamic>,
}

impl SewingTable {
    /// The physics parameters from the variables.
    pub fn params(v: &Values<V>) -> Params {
        Params {
            kind: Kind::from_item(v.int(V::table_kind)).unwrap_or(Kind::Translating),
            cam_r0: v[V::cam_R0],
            cam_e: v[V::cam_e],
            roller: Roller::new(v[V::roller_r], v[V::roller_b], v[V::cam_E], v[V::roller_E]),
            table_m: v[V::table_m],
            guide_f: v[V::guide_f],
            cam_j: v[V::cam_J],
            rocking_j: v[V::rocking_J],
            ..table_params(v)
        }
    }
}

impl Model for SewingTable {
    type Var = V;
    const IDENTIFIER: &'static str = "SewingTable";
    const DESCRIPTION: &'static str = "Cam-driven translating table of a thread-sewing machine, synthesized from the rocking table of the BNSh-6A (paper 000)";
    const EXPERIMENT: Experiment = Experiment::until(1.2, 1e-3);
    const STAGES: &'static [Stage] = STAGES;

    fn prepare(v: &Values<V>) -> Result<Self, ParamError> {
        let params = Self::params(v);
        params.validate()?;
        let r0_min = if v.wants(stage::SYNTHESIS) {
            params.smallest_r0()
        } else {
            f64::NAN
        };
        let dynamic = if shaft::fidelity(v) == Fidelity::Elastodynamic {
            if params.kind == Kind::Rocking {
                return Err(ParamError {
                    param: "table.kind",
                    value: 2.0,
                    condition: "the elastodynamic level models the translating table only".into(),
                });
            }
            SpringDamper::check_mass(params.table_m, "table.m", params.table_m, "table.m")?;
            let model = TableChain {
                spring: TableOde::spring(&params, v[V::elastic_k], v[V::elastic_zeta]),
                gap: 0.5 * v[V::cam_clearance],
            };
            let memory = TableMemory {
                peaks: Peaks::new(0.0),
                liftoffs: 0.0,
                impact: 0.0,
                landed: false,
            };
            Some(Chain::new(model, v, memory))
        } else {
            None
        };
        Ok(SewingTable {
            params,
            r0_min,
            dynamic,
        })
    }

    fn evaluate(&mut self, v: &mut Values<V>, time: f64, _log: &mut dyn Log) {
        let p = &self.params;
        if v.wants(stage::SYNTHESIS) {
            let s = p.synthesis();
            v[V::synth_alpha1] = s.alpha1;
            v[V::synth_A1A2] = s.a1a2;
            v[V::synth_k1] = s.k1;
            v[V::synth_alpha3] = s.alpha3;
            v[V::synth_k2] = s.k2;
            v[V::synth_k0] = s.k0;
            v[V::synth_l2] = s.l2;
            v[V::table_stroke] = p.stroke();
            v[V::cycle_dwell_load] = p.cyclogram().dwell_near();
            v[V::cam_R0_min] = self.r0_min;
        }
        let st = shaft::state(v, time);
        let f_ext = v[V::table_F_ext];
        let wants = Wants::of(v);
        let chain = self.dynamic.as_ref().map(|d| {
            let ode = d.ode(p, shaft::path(v, time), v);
            let y = d.held_state(&ode, time);
            (ode, y)
        });
        let chain = chain.as_ref().map(|(ode, y)| (ode, *y));
        let out = self.outputs(wants, &st, f_ext, chain, |var, x| v[var] = x);
        v[V::table_phase] = f64::from(Params::phase_index(out.phase));
        if let (Some(d), Some((_, y))) = (self.dynamic.as_ref(), chain) {
            for (s, x) in [V::elastic_x, V::elastic_xd, V::elastic_W]
                .into_iter()
                .zip(y)
            {
                v[s] = x;
            }
            v.set_flag(V::contact_open, out.pen < 0.0);
            v[V::contact_liftoffs] = d.memory.liftoffs;
            v[V::solver_steps] = d.integ.mem.stats.steps as f64;
        }
    }

    const PARTIALS: bool = true;

    /// [`SewingTable::outputs`] on dual numbers; the knowns: `shaft.phi`, `shaft.w`, `shaft.a`,
    /// `table.F_ext` and in Model Exchange `elastic.x`, `elastic.xd`, `elastic.W`. Before the
    /// first step the chain starts from an equilibrium, a function of the inputs. Held (the
    /// derivative 0): [`HELD_BELOW_ELASTIC`] and the forces at the kinematic level; the
    /// statistics of past steps `dyn.factor` and `contact.F_impact`.
    fn partials(&mut self, at: &Seeded<V>, time: f64, put: Put<V>) -> Result<(), String> {
        let v = at.values();
        let p = &self.params;
        let st = at.shaft(time);
        let f_ext = at.get(V::table_F_ext);
        let wants = Wants::of(v);
        let chain = self.dynamic.as_ref().map(|d| {
            let ode = d.ode(p, shaft::path(v, time), v);
            let y = if d.started {
                at.own_all([V::elastic_x, V::elastic_xd, V::elastic_W], d.y)
            } else {
                ode.initial_state_at(&p.kinematics(st.phi, st.w, st.a), st.a, f_ext)
            };
            (ode, y)
        });
        let chain = chain.as_ref().map(|(ode, y)| (ode, *y));
        self.outputs(wants, &st, f_ext, chain, &mut *put);
        if chain.is_none() {
            put_zero(put, HELD_BELOW_ELASTIC);
            if !wants.kinetostatic {
                put_zero(put, KINETOSTATIC_FORCES);
            }
        }
        Ok(())
    }
}

/// What [`SewingTable::outputs`] computes, from the level and the stages wanted.
#[derive(Clone, Copy, Debug)]
struct Wants {
    /// The kinetostatic level: the forces and the torque.
    kinetostatic: bool,
    /// The rocking table alongside (or it is the table).
    rocking: bool,
    /// The loaded flank (`cam.rho`) or the Hertz stress.
    flank: bool,
    /// The flank, the forces or the Hertz stress: the force solution runs.
    forces: bool,
    /// The Hertz stress.
    hertz: bool,
}

impl Wants {
    fn of(v: &Values<V>) -> Wants {
        Wants {
            kinetostatic: shaft::fidelity(v) == Fidelity::Kinetostatic,
            rocking: v.wants(stage::ROCKING),
            flank: v.wants(stage::FLANK.or(stage::HERTZ)),
            forces: v.wants(stage::FLANK.or(stage::FORCES).or(stage::HERTZ)),
            hertz: v.wants(stage::HERTZ),
        }
    }
}

/// The rigid (kinetostatic) forces on the motion `k` at the shaft acceleration `a` where
/// `wanted` (zero otherwise; the Hertz stress with `hertz`, [`Params::forces_with`]), with
/// `cam.rho` put: the loaded flank's radius of curvature, infinite at an inflection of the pitch
/// curve and reported as 1000 m there.
fn rigid_forces<T: Scalar>(
    p: &Params,
    k: &Kinematics<T>,
    a: T,
    f_ext: T,
    wanted: bool,
    hertz: bool,
    put: &mut impl FnMut(V, T),
) -> Forces<T> {
    let f = if wanted {
        p.forces_with(k, a, f_ext, hertz)
    } else {
        Forces::zero()
    };
    put(V::cam_rho, clamp_of(f.rho_flank, -1000.0, 1000.0));
    f
}

/// The outputs below the elastodynamic level that `evaluate` does not write (held), and the
/// Model Exchange state derivatives there (0, as `fmi2GetDerivatives` gives): derivative 0.
const HELD_BELOW_ELASTIC: [V; 7] = [
    V::elastic_deflection,
    V::elastic_F,
    V::contact_F_impact,
    V::elastic_E_residual,
    V::der_elastic_x,
    V::der_elastic_xd,
    V::der_elastic_W,
];

/// The kinetostatic outputs of the rigid levels, held at the kinematic level.
const KINETOSTATIC_FORCES: [V; 4] = [
    V::table_F_inertia,
    V::table_F_friction,
    V::cam_F,
    V::cam_sigma_H,
];

/// What [`SewingTable::outputs`] gives `evaluate` for its Integer and Boolean outputs.
struct Discrete {
    /// `table.phase`.
    phase: Phase,
    /// The chain's penetration of the loaded flank (`contact.open` where < 0; 0 below the
    /// elastodynamic level).
    pen: f64,
}

impl SewingTable {
    /// Every continuous Real output at the shaft state `st` and the external force `f_ext`, as
    /// `put(variable, value)`, and at the elastodynamic level (`chain`: the ODE and its states
    /// `y`) the state derivatives: the one source of the outputs ([`Model::evaluate`], `f64`)
    /// and of their exact partial derivatives ([`Model::partials`], dual numbers). What a level
    /// does not compute is not put (held: [`HELD_BELOW_ELASTIC`], at the kinematic level
    /// [`KINETOSTATIC_FORCES`]).
    fn outputs<T: Scalar>(
        &self,
        w: Wants,
        st: &ShaftState<T>,
        f_ext: T,
        chain: Option<(&TableOde, [T; 3])>,
        mut put: impl FnMut(V, T),
    ) -> Discrete {
        let p = &self.params;
        let k = p.kinematics(st.phi, st.w, st.a);
        let r = if p.kind == Kind::Rocking || w.rocking {
            p.rocking(st.phi, st.w, st.a)
        } else {
            Rocking::zero()
        };
        put(V::rocking_beta, r.beta);
        put(V::rocking_x, r.x);
        put(V::rocking_y, r.y);
        put(
            V::rocking_M_inertia,
            if w.kinetostatic {
                r.m_inertia
            } else {
                T::zero()
            },
        );
        put(V::table_x_kin, k.c.x);
        if let (Some(d), Some((ode, y))) = (self.dynamic.as_ref(), chain) {
            let pt = ode.point_with(&k, &y, f_ext);
            let m = p.table_m;
            put(V::der_elastic_x, y[1]);
            put(V::der_elastic_xd, pt.xdd);
            put(V::der_elastic_W, pt.power);
            put(V::table_x, pt.x);
            put(V::table_v, pt.xd);
            put(V::table_a, pt.xdd);
            put(V::cam_theta, k.theta);
            put(V::elastic_deflection, pt.delta);
            put(V::elastic_F, pt.f_c);
            let rigid = rigid_forces(p, &k, st.a, f_ext, w.flank, w.hertz, &mut put);
            put(V::table_F_inertia, pt.xdd * -m);
            put(V::table_F_friction, -pt.f_fr);
            put(V::cam_F, pt.f_c / k.theta.cos());
            // the Hertz stress (paper 002 eq. 8) under the dynamic cam force on the flank the
            // rigid force loads; no rigid force (no flank wanted): 0
            let sigma_h = if rigid.cam_f.re() == 0.0 {
                T::zero()
            } else if !w.hertz {
                T::from(f64::NAN)
            } else {
                let surface = if rigid.rho_flank.re() > 0.0 {
                    Surface::Convex
                } else {
                    Surface::Concave
                };
                let force = (pt.f_c / k.theta.cos()).abs();
                p.roller.stress(force, rigid.rho_flank.abs(), surface)
            };
            put(V::cam_sigma_H, sigma_h);
            // statistics of the steps taken: constants now
            put(V::dyn_factor, T::from(d.memory.peaks.dyn_factor()));
            put(V::contact_F_impact, T::from(d.memory.impact));
            put(
                V::elastic_E_residual,
                if d.started {
                    ode.energy_of(&pt) - d.e0 - y[2]
                } else {
                    T::zero()
                },
            );
            let tau = pt.f_c * k.c.dx + st.a * p.cam_j;
            let red = shaft::reduce_at_rest(tau, st.a, |a| {
                let ka = p.kinematics(st.phi, st.w, a);
                ode.point_with(&ka, &y, f_ext).f_c * ka.c.dx + a * p.cam_j
            });
            put(V::shaft_J_red, red.j_red);
            put(V::shaft_tau0, red.tau0);
            put(V::shaft_tau, tau);
            put(V::shaft_P, tau * st.w);
            return Discrete {
                phase: k.c.phase,
                pen: pt.pen.re(),
            };
        }
        put(V::dyn_factor, T::one());
        let tau = match p.kind {
            Kind::Translating => {
                put(V::table_x, k.c.x);
                put(V::table_v, k.v);
                put(V::table_a, k.a);
                put(V::cam_theta, k.theta);
                let f = rigid_forces(p, &k, st.a, f_ext, w.forces, w.hertz, &mut put);
                if w.kinetostatic {
                    put(V::table_F_inertia, f.f_inertia);
                    put(V::table_F_friction, f.f_friction);
                    put(V::cam_F, f.cam_f);
                    put(V::cam_sigma_H, f.sigma_h);
                }
                f.tau
            }
            Kind::Rocking => {
                put(V::table_x, r.x);
                put(V::table_v, r.dx_dbeta * r.w);
                // d²x/dt² = x''(β)·β̇² + x'(β)·β̈, x(β) = R·u·(sin ψ0 − sin(ψ0 − β))
                let ddx = -(r.x - p.r * p.unit * (p.synthesis().alpha1 + p.alpha2).sin());
                let table_a = ddx * r.w * r.w + r.dx_dbeta * r.a;
                put(V::table_a, table_a);
                put(V::cam_theta, T::zero());
                put(V::cam_rho, T::zero());
                put(
                    V::table_F_inertia,
                    if w.kinetostatic {
                        table_a * -p.table_m
                    } else {
                        T::zero()
                    },
                );
                put(V::table_F_friction, T::zero());
                put(V::cam_F, T::zero());
                put(V::cam_sigma_H, T::zero());
                if w.kinetostatic {
                    p.rocking_tau(&r, st.a, f_ext)
                } else {
                    T::zero()
                }
            }
        };
        // at the kinematic level every branch gives no torque
        shaft::rigid_torque(
            st,
            w.kinetostatic.then_some(tau),
            |a| match p.kind {
                Kind::Translating => {
                    p.forces_with(&p.kinematics(st.phi, st.w, a), a, f_ext, false)
                        .tau
                }
                Kind::Rocking => p.rocking_tau(&p.rocking(st.phi, st.w, a), a, f_ext),
            },
            &mut put,
        );
        Discrete {
            phase: k.c.phase,
            pen: 0.0,
        }
    }
}

// Co-Simulation, Model Exchange and the FMU state from solver::chain; at an event or a completed
// step a flank contact that opened or closed counts a lift-off or marks a landing ([`TableChain`])
crate::chain_dynamics!(SewingTable, dynamic, params,
    /// The cyclogram's phase boundaries, both slot flanks (with clearance) and the rigid
    /// velocity's sign ([`TableOde`]'s events).
    EVENT_INDICATORS = 7);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::NoLog;
    use crate::model::partials::check;

    #[test]
    fn a_massless_table_is_refused_at_the_elastodynamic_level_naming_table_m() {
        let mut v = Values::<V>::start();
        v[V::table_m] = 0.0;
        check::refused_only_elastodynamic::<SewingTable>(&mut v, "table.m");
    }

    #[test]
    fn outputs_from_the_variables() {
        let mut v = Values::<V>::start();
        let mut m = SewingTable::prepare(&v).unwrap();
        v[V::shaft_phi] = 0.5;
        m.evaluate(&mut v, 0.0, &mut NoLog);
        assert!((v[V::table_x] - 0.024560).abs() < 5e-7);
        assert!((v[V::table_v] - 1.29297).abs() < 5e-6);
        assert_eq!(v.int(V::table_phase), 0);
        assert!((v[V::table_stroke] - 0.11152).abs() < 5e-6);
        assert!(v[V::cam_R0_min] > 0.0 && v[V::cam_R0_min] < 0.1);
        // the external force enters the torque: -F_ext*dx/dphi
        let tau0 = v[V::shaft_tau];
        v[V::table_F_ext] = -100.0;
        m.evaluate(&mut v, 0.0, &mut NoLog);
        let k = m.params.kinematics(0.5, v[V::shaft_w], 0.0);
        assert!(v[V::shaft_tau] - tau0 > 0.9 * 100.0 * k.c.dx);
    }

    /// The elastodynamic level's Hertz stress is the kinetostatic one's formula (paper 002 eq.
    /// 8) under the chain's force: at the chain's starting equilibrium, where the spring carries
    /// the rigid force, the two levels agree; with the chain force doubled (the deflection
    /// doubled, no damping rate) the stress grows by √2, as Hertz line contact does.
    #[test]
    fn hertz_stress_under_the_chain_force() {
        for phi in [0.5, 0.9, 4.0] {
            let mut v = Values::<V>::start();
            v[V::shaft_phi] = phi;
            v[V::model_fidelity] = 2.0;
            let mut rigid = SewingTable::prepare(&v).unwrap();
            rigid.evaluate(&mut v, 0.0, &mut NoLog);
            let sigma = v[V::cam_sigma_H];
            assert!(sigma > 0.0, "phi {phi}");
            v[V::model_fidelity] = 3.0;
            let mut m = SewingTable::prepare(&v).unwrap();
            m.evaluate(&mut v, 0.0, &mut NoLog);
            let rel = (v[V::cam_sigma_H] - sigma).abs() / sigma;
            assert!(
                rel < 1e-9,
                "phi {phi}: {} against {sigma}",
                v[V::cam_sigma_H]
            );
            let (x_kin, x) = (v[V::table_x_kin], v[V::table_x]);
            m.me_set_states(&v, 0.0, &[x_kin - 2.0 * (x_kin - x), v[V::table_v], 0.0]);
            m.evaluate(&mut v, 0.0, &mut NoLog);
            let rel = (v[V::cam_sigma_H] - sigma * 2f64.sqrt()).abs() / sigma;
            assert!(
                rel < 1e-6,
                "phi {phi}: {} against √2·{sigma}",
                v[V::cam_sigma_H]
            );
        }
    }

    #[test]
    fn model_exchange_bookkeeping_travels_with_the_fmu_state() {
        let mut v = Values::<V>::start();
        v[V::model_fidelity] = 3.0;
        let gap = 1e-4;
        v[V::cam_clearance] = 2.0 * gap;
        let mut m = SewingTable::prepare(&v).unwrap();
        m.evaluate(&mut v, 0.0, &mut NoLog);
        let x_kin = v[V::table_x_kin];
        // the roller pressed on a flank (deflection 2*gap > gap), a completed step sees it
        m.me_set_states(&v, 0.0, &[x_kin - 2.0 * gap, 0.0, 0.0]);
        m.me_completed_step(&v, 0.0, &mut NoLog);
        let saved = m.save_state();
        assert_eq!(
            saved.len(),
            Dynamic::STATE_LEN + SewingTable::EVENT_INDICATORS
        );
        let bits = |s: &[f64]| s.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        // restored elsewhere, the roller then crosses into the play: one lift-off is counted
        let mut r = SewingTable::prepare(&v).unwrap();
        r.restore_state(&saved).unwrap();
        assert_eq!(bits(&r.save_state()), bits(&saved));
        r.me_set_states(&v, 0.0, &[x_kin, 0.0, 0.0]);
        r.me_completed_step(&v, 0.0, &mut NoLog);
        assert_eq!(r.dynamic.as_ref().unwrap().memory.liftoffs, 1.0);
        // a Co-Simulation state (no indicators) is accepted; a truncated one is not
        let mut c = SewingTable::prepare(&v).unwrap();
        c.restore_state(&saved[..Dynamic::STATE_LEN]).unwrap();
        assert!(c.restore_state(&saved[..5]).is_err());
    }

    /// The exact partial derivatives against central differences of `evaluate`: every
    /// continuous Real output and the state derivatives, along the inputs (`shaft.*`,
    /// `table.F_ext`) and at the elastodynamic level the states, at the three levels; the
    /// translating table in each travel and the far dwell, the rocking one; the
    /// constant-speed drive; the chain without play and with play on either flank and in the
    /// gap (tests/partials.rs checks the default FMU over the C ABI).
    #[test]
    fn partials_equal_central_differences() {
        // level, table.kind, drive.mode, phi, w, a, time, cam.clearance, chain deflection
        for (level, kind, mode, phi, w, a, time, clearance, delta) in [
            (1.0, 1.0, 1.0, 0.5, 10.0, 3.0, 0.0, 0.0, 0.0),
            (2.0, 1.0, 1.0, 0.5, 10.0, 3.0, 0.0, 0.0, 0.0),
            (2.0, 1.0, 1.0, 4.0, 11.0, -2.0, 0.01, 0.0, 0.0),
            (2.0, 1.0, 1.0, 2.0, 9.0, 0.4, 0.0, 0.0, 0.0),
            (2.0, 1.0, 2.0, 0.5, 10.0, 0.0, 0.12, 0.0, 0.0),
            (1.0, 2.0, 1.0, 0.7, 10.0, 0.5, 0.0, 0.0, 0.0),
            (2.0, 2.0, 1.0, 4.2, 10.0, 0.5, 0.0, 0.0, 0.0),
            (3.0, 1.0, 1.0, 0.5, 10.0, 3.0, 0.0, 0.0, 5e-4),
            (3.0, 1.0, 1.0, 4.0, 11.0, -2.0, 0.0, 2e-4, 5e-4),
            (3.0, 1.0, 1.0, 0.9, 10.0, 1.0, 0.0, 2e-4, -5e-4),
            (3.0, 1.0, 1.0, 0.9, 10.0, 1.0, 0.0, 2e-4, 0.0),
        ] {
            let mut v = Values::<V>::start();
            v[V::model_fidelity] = level;
            v[V::table_kind] = kind;
            v[V::drive_mode] = mode;
            v[V::cam_clearance] = clearance;
            v[V::table_F_ext] = 40.0;
            let mut m = SewingTable::prepare(&v).unwrap();
            check::set_shaft(&mut v, phi, w, a);
            m.evaluate(&mut v, time, &mut NoLog);
            let elastic = level == 3.0;
            if elastic {
                // the chain deflected by `delta` and moving slower than the rigid table
                let y0 = [v[V::table_x_kin] - delta, 0.9 * v[V::table_v], 0.3];
                m.me_set_states(&v, time, &y0);
            }
            check::inputs_and_states(
                &mut m,
                &v,
                time,
                &[V::table_F_ext],
                elastic,
                // the table's position on the scale of the chain's deflection
                |k, x| {
                    if k == V::elastic_x {
                        1e-9
                    } else {
                        check::relative_step(k, x)
                    }
                },
                1e-14,
                &format!(
                    "level {level} kind {kind} mode {mode} phi {phi} clearance {clearance} delta {delta}"
                ),
            );
        }
    }

    #[test]
    fn rocking_table_acceleration_by_differences() {
        let mut v = Values::<V>::start();
        v[V::table_kind] = 2.0;
        let mut m = SewingTable::prepare(&v).unwrap();
        let w = v[V::shaft_w];
        let at = |m: &mut SewingTable, v: &mut Values<V>, phi: f64| {
            v[V::shaft_phi] = phi;
            m.evaluate(v, 0.0, &mut NoLog);
            (v[V::table_x], v[V::table_v], v[V::table_a])
        };
        for k in 1..100 {
            let phi = 0.05 * k as f64 + 0.013;
            let h = 1e-6;
            let (_, v0, a0) = at(&mut m, &mut v, phi);
            let (xp, vp, _) = at(&mut m, &mut v, phi + h);
            let (xm, vm, _) = at(&mut m, &mut v, phi - h);
            assert!((v0 - (xp - xm) / (2.0 * h) * w).abs() < 1e-6);
            assert!((a0 - (vp - vm) / (2.0 * h) * w).abs() < 1e-4, "{phi}: {a0}");
        }
    }
}
