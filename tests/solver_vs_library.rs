//! The hand-written integrators (`src/solver/`) against a maintained library,
//! `differential-equations` 0.7 (its Radau5 at rtol 1e-10), on every stiff case of the
//! GenevaKnifeDrive matrix (chain stiffness 1e8 … 1e12 N/m, damping ratio 0, 0.01, 1), over the
//! knife's stroke down to just before cut-through (entry, cut start, the cutting phase): the
//! knife positions agree to 1e-7 m at every millisecond. (The library's ESDIRK3(2)4L[2]SA
//! stops on these cases with "stiffness detected", so it is not the reference.)
//!
//! The same for the DiscKnifeDrive's compliant rod (1e8 … 1e12 N/m, damping ratio 0, 0.01, 1)
//! from 170° over the jamming window, the inner dead centre (the cutting force switching on)
//! and the friction wedge after it: the slider positions agree to 1e-8 m at every 0.5 ms. And
//! the Perforators' lever on its ramp contact (1e8, 1e10 N/m; damping ratio 0, 0.01, 1) over the
//! needles' rise and piercing: the deflections agree to 3 % of their scale.

mod common;

use bindery_fmu::mechanisms::geneva_knife_drive::elastic::{KnifeMemory, KnifeOde};
use bindery_fmu::mechanisms::geneva_knife_drive::physics::Params;
use bindery_fmu::solver::chain::ChainOde;
use bindery_fmu::solver::{Method, Settings, ShaftPath};
use common::ode::{Library, assert_agrees_with_library, max_diff_at, ours_on_grid};
use differential_equations::prelude::*;
use std::cell::Cell;

fn ode(p: &Params, k: f64, zeta: f64) -> KnifeOde<'_> {
    KnifeOde {
        p,
        geneva: p.geneva(),
        spring: KnifeOde::spring(p, k, zeta),
        path: ShaftPath::new(0.0, 0.0, std::f64::consts::PI, 0.0),
        memory: Cell::new(KnifeMemory::new(0.0)),
        rigid: Default::default(),
        last: Default::default(),
    }
}

const STOP: f64 = 0.23; // cut-through is at 0.236 s

/// Our integrator's settings for the cross-checks (`atol` resolving the compliance).
fn settings(method: Method, atol: f64) -> Settings {
    Settings {
        method,
        rtol: 1e-8,
        atol,
        max_step: 1e-3,
        max_steps: 1_000_000,
    }
}

#[test]
fn radau5_and_auto_agree_with_differential_equations_on_every_stiff_case() {
    let p = Params::default();
    assert_agrees_with_library(
        |k, zeta| ode(&p, k, zeta),
        |o| o.initial_state(0.0),
        |method| settings(method, 1e-11),
        (STOP, 1e-3),
        1e-13,
        1e-7,
    );
}

// ---- DiscKnifeDrive: the compliant rod ---------------------------------------------------

use bindery_fmu::mechanisms::disc_knife_drive::elastic::{RodOde, dead_point_threshold};
use bindery_fmu::mechanisms::disc_knife_drive::physics::Params as DiscParams;

fn disc_ode(p: &DiscParams, k: f64, zeta: f64) -> RodOde<'_> {
    RodOde::new(
        p,
        RodOde::spring(p, k, zeta),
        ShaftPath::new(0.0, 170f64.to_radians(), p.drive_n, 0.0),
        dead_point_threshold(p),
        bindery_fmu::solver::chain::Peaks::new(0.0),
    )
}

/// 170° to 192° at 300 rpm.
const DISC_STOP: f64 = 0.012;
const DISC_DT: f64 = 5e-4;

#[test]
fn disc_knife_rod_radau5_and_auto_agree_with_differential_equations() {
    let p = DiscParams::default();
    assert_agrees_with_library(
        |k, zeta| disc_ode(&p, k, zeta),
        |o| o.initial_state(0.0),
        |method| settings(method, 1e-13),
        (DISC_STOP, DISC_DT),
        1e-14,
        1e-8,
    );
}

// ---- Perforators: the lever on the ramp through the unilateral contact -------------------------

use bindery_fmu::mechanisms::perforators::elastic::{Contact, ContactLaw, LeverOde, Track};
use bindery_fmu::mechanisms::perforators::physics::{Drive, Params as PerfParams};

fn lever(d: &Drive, k: f64, zeta: f64) -> LeverOde<'_> {
    LeverOde {
        d,
        contact: Contact::new(
            d,
            ContactLaw::Linear,
            k,
            2.0 * zeta * (k * LeverOde::reduced_mass(d)).sqrt(),
        ),
        path: ShaftPath::new(0.0, 0.0, 100.0 * std::f64::consts::PI / 30.0, 0.0),
        track: Cell::new(Track::new(0.0)),
        range: LeverOde::linkage_range(d),
        out_of_range: Cell::new(f64::NAN),
        rigid: Default::default(),
        last: Default::default(),
    }
}

/// The rise of the needles at 100 rpm from 5 ms into the forward travel (the friction switching
/// on at the phase boundary t = 0 is a jump the library would step over), the climb, the
/// piercing load's corners (pierce.s_in, its peak, pierce.s_out), short of the top (0.068 s)
/// where the friction reverses; the roller stays on the ramp. Contact 1e8 and 1e10 N/m (the
/// library's radau5 stops with "step size became too small" on the undamped 1e12 N/m contact).
const PERF_STOP: f64 = 0.06;
const T0: f64 = 0.005;

#[test]
fn perforators_radau5_and_auto_agree_with_differential_equations_on_stiff_contacts() {
    let d = PerfParams::default().drive().unwrap();
    let n = ((PERF_STOP - T0) / 1e-3).round() as usize;
    for k in [1e8, 1e10] {
        for zeta in [0.0, 0.01, 1.0] {
            let o = lever(&d, k, zeta);
            let y0 = o.initial_state(T0);
            // the deflection's scale: the contact force (some 100 .. 1500 N) over k at a 0.04 m arm
            let scale = 100.0 / k / 0.04;
            // the library's dense output is of low order between its long stiff steps: it
            // integrates each millisecond on its own, from where the last one ended
            let lever_ode = lever(&d, k, zeta);
            let lib = Library(&lever_ode);
            let mut yl = y0;
            let mut lib_q = vec![];
            for i in 0..n {
                let (a, b) = (T0 + i as f64 * 1e-3, T0 + (i + 1) as f64 * 1e-3);
                let sol = IVP::ode(&lib, a, b, yl)
                    .method(ImplicitRungeKutta::radau5().rtol(1e-10).atol(1e-4 * scale))
                    .solve()
                    .unwrap_or_else(|e| panic!("library radau5 k = {k}, zeta = {zeta}: {e:?}"));
                yl = *sol.iter().next_back().expect("a solution").1;
                lib_q.push((i + 1, yl[0]));
            }
            for method in [Method::Radau5, Method::Auto] {
                let o = lever(&d, k, zeta);
                let q = ours_on_grid(
                    &o,
                    settings(method, 1e-5 * scale),
                    o.initial_state(T0),
                    T0,
                    1e-3,
                    n,
                );
                // the deflection to 3 % of its scale (3 N of the 100 .. 1500 N contact force):
                // what remains is the piercing load's corners (at the elastic needle position),
                // which ours locates as events and the library steps over
                let dq = max_diff_at(&q, &lib_q);
                assert!(
                    dq < 3e-2 * scale,
                    "k = {k}, zeta = {zeta}, {method:?}: {dq:e} rad of {scale:e}"
                );
            }
        }
    }
}
