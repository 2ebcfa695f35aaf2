use super::*;
use crate::mechanisms::assert_printed;
use approx::assert_abs_diff_eq;
use std::f64::consts::PI;

const W100: f64 = 100.0 * PI / 30.0;

fn drive(mode: Mode) -> Drive {
    Params {
        mode,
        ..Params::default()
    }
    .drive()
    .unwrap()
}

fn frictionless() -> Params {
    Params {
        guide_mu: 0.0,
        joint_f: 0.0,
        pierce_q: 0.0,
        ..Params::default()
    }
}

#[test]
fn paper_synthesis_numbers() {
    let s = Params::default().synthesis();
    assert_printed(s.nu.to_degrees(), 28.79, 2);
    assert_printed(s.gamma_sum.to_degrees(), 28.93, 2);
    assert_printed(s.s_sum, 0.7023, 4);
    assert_printed(s.s_sum * 30.0, 21.07, 2);
    // eq. (2) is the exact rod angle at the lowest position
    let p = Params::default();
    assert_abs_diff_eq!(p.carriage(0.0f64).sin_nu.asin(), s.nu, epsilon = 1e-14);
}

#[test]
fn paper_approximation_error() {
    let d = drive(Mode::Paper);
    let e = drive(Mode::Exact);
    // the exact linkage with the paper's swing: 1.0228 units, 30.68 mm, +2.3 %
    assert_printed(d.stroke / d.p.unit, 1.0228, 4);
    assert_printed(1000.0 * d.stroke, 30.68, 2);
    assert_printed(100.0 * d.stroke_error(), 2.3, 1);
    assert_abs_diff_eq!(d.stroke_error(), e.stroke_error(), epsilon = 1e-15);
    // the rod ends 1.65 deg off the carriage line
    assert_printed(
        d.p.carriage(d.gamma_paper).sin_nu.asin().to_degrees(),
        1.65,
        2,
    );
    // the swing giving exactly lambda_S
    assert_printed(e.gamma_exact.to_degrees(), 28.27, 2);
    assert_abs_diff_eq!(e.stroke, 0.030, epsilon = 1e-12);
    assert_eq!(d.gamma_sw, d.gamma_paper);
    assert_eq!(e.gamma_sw, e.gamma_exact);
}

#[test]
fn spec_reference_values() {
    for (mode, x_frac, s_mm, g_deg, rise_mm) in [
        (Mode::Paper, 0.25, 15.342, 14.077, 9.521),
        (Mode::Paper, 0.5, 30.685, 28.931, 21.068),
        (Mode::Exact, 0.5, 30.000, 28.271, 20.532),
    ] {
        let d = drive(mode);
        let (g, _, _, s, _, _) = d.gamma_of_x(x_frac * d.cyc.h);
        assert_printed(1000.0 * s, s_mm, 3);
        assert_printed(g.to_degrees(), g_deg, 3);
        let l4 = d.p.lambda4 * d.p.unit;
        assert_printed(
            1000.0 * l4 * (d.p.gamma1.cos() - (d.p.gamma1 + g).cos()),
            rise_mm,
            3,
        );
    }
}

#[test]
fn top_at_half_the_travel_41_degrees() {
    // paper 000, Fig. 2 c: the perforators reach the top at half the forward travel, phi = 41 deg
    let d = drive(Mode::Exact);
    let k = d.kinematics(41f64.to_radians(), W100, 0.0);
    assert_abs_diff_eq!(k.x_t, d.cyc.h / 2.0, epsilon = 1e-15);
    assert_abs_diff_eq!(k.s, d.stroke, epsilon = 1e-15);
    let top = (0..=8200).map(|i| i as f64 * 0.01).max_by(|a, b| {
        let s = |deg: f64| d.kinematics(deg.to_radians(), W100, 0.0).s;
        s(*a).total_cmp(&s(*b))
    });
    assert_abs_diff_eq!(top.unwrap(), 41.0, epsilon = 0.011);
    // and down again at sewing (82 deg) and at loading
    assert_abs_diff_eq!(
        d.kinematics(82f64.to_radians(), W100, 0.0).s,
        0.0,
        epsilon = 1e-15
    );
    assert_eq!(d.kinematics(5.0, W100, 0.0).s, 0.0);
}

#[test]
fn velocities_and_accelerations_match_finite_differences() {
    for law in [MotionLaw::Cycloidal, MotionLaw::Poly345] {
        let d = Params {
            law_fall: law,
            ..Params::default()
        }
        .drive()
        .unwrap();
        let (w, eps) = (W100, 4.0);
        for i in 0..400 {
            let phi = TAU * (i as f64 + 0.31) / 400.0;
            let h = 1e-6;
            let k = |t: f64| d.kinematics(phi + w * t + 0.5 * eps * t * t, w + eps * t, eps);
            let (k0, kp, km) = (k(0.0), k(h), k(-h));
            let fd = |a: f64, b: f64| (a - b) / (2.0 * h);
            assert_abs_diff_eq!(k0.v, fd(kp.s, km.s), epsilon = 1e-6);
            assert_abs_diff_eq!(k0.a, fd(kp.v, km.v), epsilon = 1e-3 * (1.0 + k0.a.abs()));
            assert_abs_diff_eq!(k0.gamma_w, fd(kp.gamma, km.gamma), epsilon = 1e-5);
            assert_abs_diff_eq!(
                k0.gamma_a,
                fd(kp.gamma_w, km.gamma_w),
                epsilon = 1e-3 * (1.0 + k0.gamma_a.abs())
            );
            assert_abs_diff_eq!(k0.v_t, fd(kp.x_t, km.x_t), epsilon = 1e-6);
            assert_abs_diff_eq!(k0.a_t, fd(kp.v_t, km.v_t), epsilon = 1e-4);
        }
        // the ramp's derivatives in x_t
        for i in 1..100 {
            let x = d.cyc.h * i as f64 / 100.0;
            let e = 1e-7;
            let (c, c1, c2) = d.ramp(x);
            let (cp, c1p, _) = d.ramp(x + e);
            let (cm, c1m, _) = d.ramp(x - e);
            assert_abs_diff_eq!(c1.0, (cp.0 - cm.0) / (2.0 * e), epsilon = 1e-6);
            assert_abs_diff_eq!(c1.1, (cp.1 - cm.1) / (2.0 * e), epsilon = 1e-6);
            assert_abs_diff_eq!(
                c2.0,
                (c1p.0 - c1m.0) / (2.0 * e),
                epsilon = 1e-3 * (1.0 + c2.0.abs())
            );
            assert_abs_diff_eq!(
                c2.1,
                (c1p.1 - c1m.1) / (2.0 * e),
                epsilon = 1e-3 * (1.0 + c2.1.abs())
            );
            let _ = c;
        }
    }
}

#[test]
fn the_ramp_is_fixed_and_the_linkage_closes() {
    let d = drive(Mode::Exact);
    for i in 0..=40 {
        let x = d.cyc.h * i as f64 / 40.0;
        let (g, ..) = d.gamma_of_x(x);
        // the roller centre in the ground frame is the ramp's pitch curve
        let (r, _, _) = d.p.roller(g);
        let (c, _, _) = d.ramp(x);
        assert_abs_diff_eq!(c.0, r.0 - x, epsilon = 1e-15);
        // the rod keeps its length; the inverse gives back the needle law
        let (s, ..) = d.needle_law(x);
        assert_abs_diff_eq!(d.p.carriage(g).s - d.s0, s, epsilon = 1e-12);
    }
}

#[test]
fn power_balance_without_friction() {
    // the power the table delivers, -table.F*v_t, is the rate of the drive's energy
    let d = frictionless().drive().unwrap();
    for eps in [0.0, 6.0] {
        let w0 = W100;
        for i in 0..360 {
            let phi = TAU * (i as f64 + 0.5) / 360.0;
            let h = 1e-6;
            let k = |t: f64| d.kinematics(phi + w0 * t + 0.5 * eps * t * t, w0 + eps * t, eps);
            let k0 = k(0.0);
            let f = d.forces(&k0);
            let de = (d.energy(&k(h)) - d.energy(&k(-h))) / (2.0 * h);
            let p = -f.table_f * k0.v_t;
            assert_abs_diff_eq!(p, de, epsilon = 1e-5 * (1.0 + de.abs()));
            assert_abs_diff_eq!(f.tau * (w0), p, epsilon = 1e-9 * (1.0 + p.abs()));
        }
    }
}

#[test]
fn piercing_and_guide_friction_dissipate_exactly_what_they_should() {
    let d = Params {
        joint_f: 0.0,
        ..Params::default()
    }
    .drive()
    .unwrap();
    for i in 0..720 {
        let phi = TAU * (i as f64 + 0.5) / 720.0;
        let h = 1e-6;
        let k = |t: f64| d.kinematics(phi + W100 * t, W100, 0.0);
        let k0 = k(0.0);
        let f = d.forces(&k0);
        let de = (d.energy(&k(h)) - d.energy(&k(-h))) / (2.0 * h);
        let loss = (f.pierce_q + d.p.guide_mu * f.guide_n) * k0.v.abs();
        assert_abs_diff_eq!(
            -f.table_f * k0.v_t,
            de + loss,
            epsilon = 1e-5 * (1.0 + de.abs() + loss)
        );
    }
    // hinge friction only adds power drawn
    let with = drive(Mode::Exact);
    let mut extra = 0.0;
    for i in 0..720 {
        let phi = TAU * (i as f64 + 0.5) / 720.0;
        let k = with.kinematics(phi, W100, 0.0);
        extra += (with.forces(&k).tau - d.forces(&k).tau) * W100;
    }
    assert!(extra > 0.0);
}

#[test]
fn piercing_load_profile() {
    let d = drive(Mode::Exact);
    let s = d.stroke;
    let q = d.p.pierce_q;
    assert_printed(q, 215.75, 2);
    assert_eq!(d.pierce_load(0.5 * s, 1.0, 0), 0.0);
    assert_abs_diff_eq!(d.pierce_load(0.65 * s, 1.0, 0), q, epsilon = 1e-9);
    assert_abs_diff_eq!(d.pierce_load(0.75 * s, 1.0, 0), 0.15 * q, epsilon = 1e-9);
    assert_abs_diff_eq!(d.pierce_load(0.9 * s, 1.0, 0), 0.15 * q, epsilon = 1e-12);
    assert_abs_diff_eq!(d.pierce_load(0.6 * s, -1.0, 0), 0.15 * q, epsilon = 1e-12);
    assert_eq!(d.pierce_load(0.5 * s, -1.0, 0), 0.0);
    assert_eq!(d.pierce_load(0.65 * s, 1.0, 2), 0.0); // return travel: empty saddle
}

#[test]
fn hertz_stress_at_the_ramp() {
    let d = drive(Mode::Exact);
    for i in 0..200 {
        let phi = 82f64.to_radians() * (i as f64 + 0.5) / 200.0;
        let k = d.kinematics(phi, W100, 0.0);
        let f = d.forces(&k);
        if f.roller_f > 0.0 {
            let inv = 1.0 / d.p.roller.r + 1.0 / k.rho;
            let expected = 0.418 * (f.roller_f / d.p.roller.b * 2.1e11 * inv).sqrt();
            assert_abs_diff_eq!(f.sigma_h, expected, epsilon = 1e-9 * expected);
        }
    }
}

#[test]
fn lift_off_above_the_found_speed_not_below() {
    let d = drive(Mode::Exact);
    // the nominal 100 rpm keeps contact
    assert!(d.min_contact_force(W100, 3600).0 > 0.0);
    let w = d
        .liftoff_speed(W100, 100.0 * W100, 1e-6, 3600)
        .expect("lifts off below 10000 rpm");
    assert!(d.min_contact_force(w * 1.001, 3600).0 < 0.0);
    assert!(d.min_contact_force(w * 0.999, 3600).0 > 0.0);
    // a weaker spring lifts off at a lower speed
    let weak = Params {
        spring_m0: 1.0,
        ..Params::default()
    }
    .drive()
    .unwrap();
    let w_weak = weak.liftoff_speed(0.1, 100.0 * W100, 1e-6, 3600).unwrap();
    assert!(w_weak < w);
}

#[test]
fn refusals_name_the_parameter() {
    let p = Params::default();
    let e = |q: Params| q.drive().unwrap_err();
    assert_eq!(e(Params { lambda1: 0.3, ..p }).param, "synth.lambda1");
    assert_eq!(e(Params { lambda_s: 5.0, ..p }).param, "synth.lambda_S");
    assert_eq!(
        e(Params {
            pierce_s_out: 0.5,
            ..p
        })
        .param,
        "pierce.s_out"
    );
    assert_eq!(
        e(Params {
            rise_fraction: 1.0,
            ..p
        })
        .param,
        "travel.rise_fraction"
    );
    assert_eq!(
        e(Params {
            roller: Roller { r: 0.2, ..p.roller },
            ..p
        })
        .param,
        "roller.r"
    );
    let t = TableParams {
        dwell_sew: 3.5,
        ..p.table
    };
    assert_eq!(e(Params { table: t, ..p }).param, "cycle.dwell_sew");
}

/// The linkage as made: the ramp (so the lever angle) is the design's, the needles' travel is
/// the made linkage's, by the plain geometry of the rod between the lever arm and the carriage
/// line; velocity and acceleration are the derivatives of that travel (central differences).
#[test]
fn the_linkage_as_made_moves_the_needles_by_its_own_geometry() {
    let design = Params::default().drive().expect("assembles");
    let made = Made {
        d_rod: 1e-4,
        d_arm: -1e-4,
        d_line: 5e-5,
    };
    let p = Params {
        made,
        ..Params::default()
    };
    let d = p.drive().expect("assembles as made");
    // the rod's ends: A on the lever arm, B on the carriage line n·B = e, |B − A| = l
    let s_of = |g: f64| {
        let u = p.unit;
        let (l, e, r) = (
            p.lambda1 * u + made.d_rod,
            p.lambda2 * u + made.d_line,
            p.lambda3 * u + made.d_arm,
        );
        let a = (r * (g - p.gamma0).cos(), r * (g - p.gamma0).sin());
        let (n, t) = (
            (p.alpha.cos(), p.alpha.sin()),
            (-p.alpha.sin(), p.alpha.cos()),
        );
        let off = e - (n.0 * a.0 + n.1 * a.1);
        (t.0 * a.0 + t.1 * a.1) + (l * l - off * off).sqrt()
    };
    let w = 110.0 * PI / 30.0;
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..720 {
        let phi = TAU * i as f64 / 720.0;
        let (k, k0) = (d.kinematics(phi, w, 0.0), design.kinematics(phi, w, 0.0));
        assert_eq!(
            k.gamma.to_bits(),
            k0.gamma.to_bits(),
            "the ramp sets the lever angle"
        );
        let s = s_of(k.gamma) - s_of(0.0);
        assert!((k.s - s).abs() < 1e-12, "phi {phi}: {} vs {s}", k.s);
        let h = 1e-5;
        let (kp, km) = (d.kinematics(phi + h, w, 0.0), d.kinematics(phi - h, w, 0.0));
        let v = (kp.s - km.s) / (2.0 * h) * w;
        let a = (kp.v - km.v) / (2.0 * h) * w;
        assert!(
            (k.v - v).abs() < 1e-6 * (1.0 + v.abs()),
            "phi {phi}: v {} vs {v}",
            k.v
        );
        // where the table's motion has a corner (a phase boundary) a central difference
        // straddles it: there the design's own acceleration misses its difference too
        let (kp0, km0) = (
            design.kinematics(phi + h, w, 0.0),
            design.kinematics(phi - h, w, 0.0),
        );
        let a0 = (kp0.v - km0.v) / (2.0 * h) * w;
        if (k0.a - a0).abs() < 1e-4 * (1.0 + a0.abs()) {
            assert!(
                (k.a - a).abs() < 1e-4 * (1.0 + a.abs()),
                "phi {phi}: a {} vs {a}",
                k.a
            );
        }
        lo = lo.min(k.s);
        hi = hi.max(k.s);
    }
    // a shorter lever arm and a longer rod: the travel is not the design's 30 mm any more
    let stroke = hi - lo;
    assert!(
        (stroke - design.stroke).abs() > 1e-6,
        "{stroke} vs {}",
        design.stroke
    );
    assert!(
        (stroke - design.stroke).abs() < 1e-3,
        "{stroke} vs {}",
        design.stroke
    );
    // made exactly: the design, bit for bit (the same linkage)
    let exact = Params {
        made: Made::default(),
        ..p
    }
    .drive()
    .expect("assembles");
    for i in 0..90 {
        let phi = TAU * i as f64 / 90.0;
        assert_eq!(
            exact.kinematics(phi, w, 0.0),
            design.kinematics(phi, w, 0.0)
        );
        let (f, f0) = (
            exact.forces(&exact.kinematics(phi, w, 0.0)),
            design.forces(&design.kinematics(phi, w, 0.0)),
        );
        assert_eq!(f, f0);
    }
}

/// The kinetostatic contact force balances the lever about O1 with the hinge friction it
/// causes, to the rounding of the moments (the balance is solved, not iterated a fixed number
/// of times: four fixed-point passes left 2e-8 of the force), over a turn in both modes.
#[test]
fn kinetostatic_contact_force_balances_the_lever_with_its_hinge_friction() {
    for mode in [Mode::Paper, Mode::Exact] {
        let d = drive(mode);
        let mut worst: f64 = 0.0;
        for i in 0..720 {
            let phi = i as f64 * 2.0 * PI / 720.0;
            let k = d.kinematics(phi, W100, 0.0);
            let f = d.forces_with(&k, false);
            let signs = (crate::mechanics::sgn(k.v), crate::mechanics::sgn(k.gamma_w));
            let (left, d_left, _) = d.moment_left(&k, &d.linkage(k.gamma), signs, f.roller_f);
            // the moment left over, as a force at the roller (d_left: the arm and the friction)
            let err = (left / d_left).abs() / f.roller_f.abs().max(1.0);
            worst = worst.max(err);
        }
        assert!(
            worst < 1e-13,
            "{mode:?}: the balance is off by {worst:e} of the force"
        );
    }
}
