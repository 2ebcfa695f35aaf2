//! Tests of `physics.rs`.

use super::*;

#[test]
fn kloss_passes_through_the_rated_and_breakdown_points() {
    let m = Motor::default();
    // synchronous speed 1500 rpm from 1400 rpm and slip 1/15
    assert!((m.w_sync() * 30.0 / std::f64::consts::PI - 1500.0).abs() < 1e-9);
    // rated point: M_n = P_n/ω_n
    let mn = m.torque(m.w_rated);
    assert!((mn - m.p_rated / m.w_rated).abs() < 1e-9 * mn, "{mn}");
    // breakdown point: the maximum, λ·M_n, at s_k
    let wk = m.w_sync() * (1.0 - m.s_break());
    assert!((m.torque(wk) - m.lambda * mn).abs() < 1e-9 * mn);
    for dw in [-1.0, 1.0] {
        assert!(m.torque(wk + dw) < m.torque(wk));
    }
    // no torque at synchronous speed, braking above it
    assert!(m.torque(m.w_sync()).abs() < 1e-12);
    assert!(m.torque(1.01 * m.w_sync()) < 0.0);
    // starting torque 2 M_k s_k/(1 + s_k²)
    let sk = m.s_break();
    assert!((m.torque(0.0) - 2.0 * m.tau_break() * sk / (1.0 + sk * sk)).abs() < 1e-9);
}

#[test]
fn acceleration_balances_the_torques() {
    let p = Params::default();
    let load = Load {
        tau: 3.0,
        tau0: 40.0,
        j_red: 1.5,
    };
    let w = 10.0;
    let pt = p.point(w, &load).unwrap();
    let lhs = (p.j_drive() + load.j_red) * pt.eps;
    let rhs = p.gear_i * p.motor.torque(p.gear_i * w) - p.friction(w) - 43.0;
    assert!((lhs - rhs).abs() < 1e-12 * rhs.abs());
    // the load torque the shaft sees includes the load's inertia torque
    assert!((pt.load_tau - (43.0 + 1.5 * pt.eps)).abs() < 1e-12);
    assert!(
        p.point(
            w,
            &Load {
                j_red: -10.0,
                ..load
            }
        )
        .is_err()
    );
}

#[test]
fn steady_speed_is_just_below_synchronous() {
    let p = Params::default();
    let w = p.steady_speed(50.0).unwrap();
    assert!(w < p.w_sync_shaft() && w > 0.9 * p.w_sync_shaft());
    let pt = p
        .point(
            w,
            &Load {
                tau: 50.0,
                ..Load::default()
            },
        )
        .unwrap();
    assert!(pt.eps.abs() < 1e-9);
    // more than the breakdown torque at the shaft: no steady speed
    assert!(
        p.steady_speed(2.0 * p.gear_i * p.motor.tau_break())
            .is_none()
    );
}

#[test]
fn bad_data_is_named() {
    let mut p = Params::default();
    p.motor.lambda = 0.9;
    assert_eq!(p.validate().unwrap_err().param, "motor.lambda");
    let mut p = Params::default();
    p.motor.s_rated = 1.0;
    assert_eq!(p.validate().unwrap_err().param, "motor.s_rated");
    let p = Params {
        gear_i: 0.0,
        ..Params::default()
    };
    assert_eq!(p.validate().unwrap_err().param, "gear.i");
    let mut p = Params {
        fly_j: 0.0,
        ..Params::default()
    };
    p.motor.j = 0.0;
    assert_eq!(p.validate().unwrap_err().param, "fly.J");
}
