use super::*;
use crate::model::Severity;

struct Rec(Vec<(Severity, String)>);
impl Log for Rec {
    fn log(&mut self, s: Severity, m: &str) {
        self.0.push((s, m.to_string()));
    }
}

/// Runs `turns` shaft turns at `rpm` in steps of `h`, returning the model, values and log.
fn run(rpm: f64, m0: f64, turns: f64, h: f64) -> (Perforators, Values<V>, Rec) {
    let mut v = Values::<V>::start();
    v[V::spring_M0] = m0;
    let mut m = Perforators::prepare(&v).unwrap();
    let w = rpm * std::f64::consts::PI / 30.0;
    let mut log = Rec(vec![]);
    let n = (turns * TAU / w / h).round() as usize;
    let mut t = 0.0;
    for _ in 0..n {
        v[V::shaft_phi] = w * t;
        v[V::shaft_w] = w;
        m.do_step(&mut v, t, h, &mut log).unwrap();
        t += h;
    }
    v[V::shaft_phi] = w * t;
    v[V::shaft_w] = w;
    m.evaluate(&mut v, t, &mut log);
    (m, v, log)
}

#[test]
fn no_lift_off_at_the_nominal_speed() {
    let (m, v, log) = run(100.0, 6.0, 2.5, 1e-3);
    assert!(log.0.is_empty(), "{:?}", log.0);
    assert!(!v.flag(V::roller_lost_contact));
    // the margin is the smallest force of the last full turn, found independently
    let (fmin, _) = m
        .drive()
        .min_contact_force(100.0 * std::f64::consts::PI / 30.0, 1440);
    assert!(v[V::roller_F_margin] > 0.0);
    assert!(
        (v[V::roller_F_margin] - fmin).abs() < 0.01 * fmin.abs(),
        "{} vs {fmin}",
        v[V::roller_F_margin]
    );
}

#[test]
fn lift_off_is_flagged_and_logged_with_the_shaft_angle() {
    // a weak spring at the nominal speed
    let (m, v, log) = run(100.0, 0.5, 1.5, 1e-3);
    let w = 100.0 * std::f64::consts::PI / 30.0;
    let (fmin, phi_min) = m.drive().min_contact_force(w, 3600);
    assert!(fmin < 0.0);
    assert!(v[V::roller_F_margin] < 0.0);
    let warnings: Vec<_> = log
        .0
        .iter()
        .filter(|(s, _)| *s == Severity::Warning)
        .collect();
    assert!(!warnings.is_empty());
    assert!(
        warnings[0].1.contains("shaft angle") && warnings[0].1.contains("spring.M0"),
        "{}",
        warnings[0].1
    );
    // the logged angle lies where the contact force is negative
    let deg: f64 = warnings[0]
        .1
        .split("shaft angle ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let f = m
        .drive()
        .forces(&m.drive().kinematics(deg.to_radians(), w, 0.0))
        .roller_f;
    assert!(
        f < 0.0 || (deg.to_radians() - phi_min).abs() < 0.05,
        "{deg}: {f}"
    );
    // one warning per lift-off episode: at most a few per turn
    assert!(warnings.len() <= 6, "{}", warnings.len());
}

#[test]
fn state_round_trips() {
    let (mut m, mut v, _) = run(100.0, 0.5, 0.7, 1e-3);
    let saved = m.save_state();
    let bits = |s: &[f64]| s.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let mut fresh = Perforators::prepare(&v).unwrap();
    fresh.restore_state(&saved).unwrap();
    assert_eq!(bits(&fresh.save_state()), bits(&saved));
    // a state saved before Model Exchange watched its steps (5 numbers) still restores
    let mut old = Perforators::prepare(&v).unwrap();
    old.restore_state(&saved[..5]).unwrap();
    assert_eq!(bits(&old.save_state()[..5]), bits(&saved[..5]));
    let mut log = Rec(vec![]);
    let (mut a, mut b) = (v.clone(), v.clone());
    m.do_step(&mut a, 0.7, 1e-3, &mut log).unwrap();
    fresh.do_step(&mut b, 0.7, 1e-3, &mut log).unwrap();
    m.evaluate(&mut a, 0.701, &mut log);
    fresh.evaluate(&mut b, 0.701, &mut log);
    assert_eq!(a.raw(), b.raw());
    assert!(fresh.restore_state(&[1.0]).is_err());
    m.evaluate(&mut v, 0.7, &mut log);
}

/// The elastodynamic level's lift-off flag in Model Exchange covers the span between the host's
/// completed steps, and a step that ends at an event (FMPy completes it at the root, then enters
/// event mode) continues the span: a lift-off and a landing inside one output interval are
/// reported at its end, as a Co-Simulation step over that interval reports them.
#[test]
fn the_lift_off_flag_spans_the_hosts_steps_through_their_events() {
    let mut l = Lost::default();
    l.completed(); // t1
    l.completed(); // the host stops at a root: the lift-off
    l.event(true);
    assert!(!l.step, "until the span ends, the last span's flag");
    l.completed(); // the next root: the landing
    l.event(false);
    assert!(!l.step);
    l.completed(); // t2
    assert!(l.step, "the span (t1, t2] had a lift-off");
    l.completed(); // t3
    assert!(!l.step);
    // saved in one number; a state saved before holds 0 or 1
    let all = Lost {
        step: true,
        pending: true,
        just_completed: false,
        before: true,
    };
    assert_eq!(Lost::restore(all.save()), all);
    assert_eq!(
        Lost::restore(1.0),
        Lost {
            step: true,
            ..Lost::default()
        }
    );
    l.co_simulation_step(true);
    assert_eq!(
        l,
        Lost {
            step: true,
            ..Lost::default()
        }
    );
}

/// The exact partial derivatives against central differences of `evaluate`: every continuous
/// Real output and the state derivatives, along the shaft inputs and at the elastodynamic level
/// the states, at the three levels: the needles rising below, inside and above the piercing
/// band, the table's return and far dwell, the constant-speed drive, the lever pressed into the
/// ramp (tests/partials.rs checks the default FMU over the C ABI).
#[test]
fn partials_equal_central_differences() {
    use crate::model::partials::check;
    // level, drive.mode, phi, w, a, time, extra deflection of the lever (elastodynamic)
    for (level, mode, phi, w, a, time, dq) in [
        (1.0, 1.0, 0.5, 10.0, 3.0, 0.0, 0.0),
        (2.0, 1.0, 0.5, 10.0, 3.0, 0.0, 0.0),
        (2.0, 1.0, 0.55, 10.0, -2.0, 0.01, 0.0),
        (2.0, 1.0, 0.62, 11.0, 0.5, 0.0, 0.0),
        (2.0, 1.0, 1.2, 9.0, 0.4, 0.0, 0.0),
        (2.0, 1.0, 4.0, 10.0, 1.0, 0.0, 0.0),
        (2.0, 2.0, 0.5, 10.0, 0.0, 0.12, 0.0),
        (3.0, 1.0, 0.5, 10.0, 3.0, 0.0, 2e-5),
        (3.0, 1.0, 0.55, 10.0, -2.0, 0.0, 1e-5),
        (3.0, 1.0, 4.0, 11.0, 1.0, 0.0, 3e-5),
    ] {
        let mut v = Values::<V>::start();
        v[V::model_fidelity] = level;
        v[V::drive_mode] = mode;
        let mut m = Perforators::prepare(&v).unwrap();
        check::set_shaft(&mut v, phi, w, a);
        // the elastodynamic level's penetration is the difference of two nearly equal roller
        // positions: its forces carry their rounding, some 1e-11 of the force
        let elastic = level == 3.0;
        let noise = if elastic { 1e-11 } else { 1e-14 };
        if elastic {
            // the lever in equilibrium, pressed further in, a little faster, some work done
            let mut y0 = [0.0; 3];
            m.me_states(&v, time, &mut y0);
            m.me_set_states(&v, time, &[y0[0] + dq, y0[1] + 0.01, 0.3]);
        }
        check::inputs_and_states(
            &mut m,
            &v,
            time,
            &[],
            elastic,
            // the lever's deflection on the scale of the contact's penetration
            |k, x| {
                if k == V::elastic_q {
                    1e-7
                } else {
                    check::relative_step(k, x)
                }
            },
            noise,
            &format!("level {level} mode {mode} phi {phi} a {a} dq {dq}"),
        );
    }
}

/// The contact's natural frequency (the floor of the lever rate's absolute tolerance,
/// [`crate::solver::chain::rate_tolerance`]): √(k/m_red) for the linear law; for Hertz's the
/// law's slope at the roller's force in the loading dwell (`contact.c`'s description: 3.0e8 N/m
/// at 150 N, with m_red = 3.83 kg).
#[test]
fn the_contacts_natural_frequency_is_its_stiffness_at_the_preload_over_the_reduced_mass() {
    let v = Values::<V>::start();
    let d = Perforators::params(&v).drive().unwrap();
    let m_red = LeverOde::reduced_mass(&d);
    assert!((m_red - 3.83).abs() < 0.005, "m_red = {m_red}");
    let linear = Contact::new(&d, ContactLaw::Linear, 1e8, 0.0);
    assert!(((linear.omega / (1e8 / m_red).sqrt()) - 1.0).abs() < 1e-12);
    let hertz = Contact::new(&d, ContactLaw::Hertz, 0.0, 0.0);
    let k_preload = hertz.omega * hertz.omega * m_red;
    let f = d.loading_force();
    // the roller carries 180 N there (the preload through the lever); the slope goes as F^0.1
    let stated = 3.0e8 * (f / 150.0).powf(0.1);
    assert!(
        (k_preload / stated - 1.0).abs() < 0.01,
        "{k_preload:e} N/m at {f} N"
    );
}
