//! The behaviour of every FMU as text, bit for bit, for a refactoring's before/after check
//! (`ARCHITECTURE.md`): every Real output's bits, every Integer and Boolean output, every
//! Model Exchange state, derivative and event indicator, every status and every log line, over
//! runs at each level in both interfaces, with input derivatives, a constant-speed drive, every
//! solver method, a stiffer chain and an FMU state set again mid-run. It names no GUID and no
//! serialized state (a refactoring may change those on purpose).
//!
//! ```text
//! cargo run --release -- build            # the FMU binaries it loads (target/release)
//! cargo run --release --example bit_dump > after.txt
//! ```
//! then the same at the commit before, and `cmp before.txt after.txt`.

#[path = "../tests/common/mod.rs"]
mod common;

use bindery_fmu::catalog::{self, Entry};
use bindery_fmu::fmi2::types::*;
use bindery_fmu::model::{Causality, VarType};
use common::*;
use std::fmt::Write;

struct Outs {
    reals: Vec<u32>,
    ints: Vec<u32>,
    bools: Vec<u32>,
}

fn outs(e: &Entry) -> Outs {
    let vars = (e.variables)();
    let pick = |ty: fn(&VarType) -> bool| -> Vec<u32> {
        vars.iter()
            .filter(|(_, v)| {
                matches!(
                    v.causality,
                    Causality::Output | Causality::CalculatedParameter
                ) && ty(&v.ty)
            })
            .map(|(vr, _)| *vr)
            .collect()
    };
    Outs {
        reals: pick(|t| *t == VarType::Real),
        ints: pick(|t| matches!(t, VarType::Integer | VarType::Enumeration(_))),
        bools: pick(|t| *t == VarType::Boolean),
    }
}

fn row(s: &Slave, o: &Outs, out: &mut String) {
    let (a, r) = s.get_real(&o.reals);
    let (b, i) = s.get_integer(&o.ints);
    let (c, bo) = s.get_boolean(&o.bools);
    write!(out, "  get {a:?} {b:?} {c:?}:").unwrap();
    for x in r {
        write!(out, " {:x}", x.to_bits()).unwrap();
    }
    write!(out, " |").unwrap();
    for x in i {
        write!(out, " {x}").unwrap();
    }
    write!(out, " |").unwrap();
    for x in bo {
        write!(out, " {}", x as u8).unwrap();
    }
    out.push('\n');
}

fn logs(s: &Slave, seen: &mut usize, out: &mut String) {
    let l = s.logs();
    for (st, cat, msg) in &l[*seen..] {
        writeln!(out, "  log {st:?} {cat}: {msg}").unwrap();
    }
    *seen = l.len();
}

/// Every log category on.
fn debug_logging(s: &Slave) {
    type SetLogging = unsafe extern "C" fn(Component, Boolean, usize, *const FmiString) -> Status;
    // SAFETY: the FMI function, no categories (all).
    let st =
        unsafe { s.fmu.sym::<SetLogging>("fmi2SetDebugLogging")(s.c, TRUE, 0, std::ptr::null()) };
    assert_eq!(st, Status::Ok);
}

/// A Co-Simulation run of `n` steps of `h`; the shaft inputs (if `inputs`) set before each step
/// to a turning shaft, with input derivatives when `derivatives`; the state got at `n / 3` and
/// set again at `2n / 3`, the run going on from there.
#[allow(clippy::too_many_arguments)]
fn cs(
    f: &Fmu,
    e: &Entry,
    start: &Start,
    n: usize,
    h: f64,
    inputs: bool,
    derivatives: bool,
) -> String {
    let o = outs(e);
    let mut out = String::new();
    let s = f.slave("dump");
    debug_logging(&s);
    let mut seen = 0;
    writeln!(out, " setup {:?}", s.setup(start.time, start.stop)).unwrap();
    for &(vr, x) in start.reals {
        writeln!(out, " set {vr} = {x}: {:?}", s.set_real(&[vr], &[x])).unwrap();
    }
    for &(vr, x) in start.integers {
        writeln!(out, " set {vr} = {x}: {:?}", s.set_integer(&[vr], &[x])).unwrap();
    }
    writeln!(out, " init {:?}", s.init()).unwrap();
    logs(&s, &mut seen, &mut out);
    let w = 3.0;
    let mut saved: Option<FMUstate> = None;
    let mut j = 0;
    let mut restored = false;
    while j < n {
        let t = j as f64 * h;
        if inputs {
            let st = s.set_real(&[0, 1, 2], &[w * t + 0.5 * 0.2 * t * t, w + 0.2 * t, 0.2]);
            if st != Status::Ok {
                writeln!(out, " set inputs {st:?}").unwrap();
            }
            if derivatives {
                let st = s.set_input_derivatives(&[0, 0, 1], &[1, 2, 1], &[w + 0.2 * t, 0.2, 0.2]);
                if st != Status::Ok {
                    writeln!(out, " set derivatives {st:?}").unwrap();
                }
            }
        }
        let st = s.do_step(t, h);
        writeln!(out, " step {j} {st:?}").unwrap();
        row(&s, &o, &mut out);
        logs(&s, &mut seen, &mut out);
        if st != Status::Ok && st != Status::Warning {
            break;
        }
        if j == n / 3 && saved.is_none() {
            let mut p: FMUstate = std::ptr::null_mut();
            writeln!(out, " get state {:?}", s.get_state(&mut p)).unwrap();
            saved = Some(p);
        }
        j += 1;
        if j == 2 * n / 3
            && !restored
            && let Some(p) = saved
        {
            writeln!(out, " set state {:?}", s.set_state(p)).unwrap();
            j = n / 3 + 1;
            restored = true;
        }
    }
    if let Some(mut p) = saved {
        s.free_state(&mut p);
    }
    writeln!(out, " terminate {:?}", s.call0("fmi2Terminate")).unwrap();
    logs(&s, &mut seen, &mut out);
    out
}

/// A Model Exchange run: Heun's steps of `h`, events where an indicator changes sign.
fn me(f: &Fmu, e: &Entry, integers: &[(u32, i32)], n: usize, h: f64) -> String {
    let o = outs(e);
    let vars = (e.variables)();
    let nx = vars.iter().filter(|(_, v)| v.derivative.is_some()).count();
    let nz = (e.info)().event_indicators as usize;
    let mut out = String::new();
    let s = f.me_instance("dump-me");
    debug_logging(&s);
    let mut seen = 0;
    s.me_start(|s| {
        for &(vr, x) in integers {
            s.ok(s.set_integer(&[vr], &[x]), "set");
        }
    });
    logs(&s, &mut seen, &mut out);
    let (_, mut x) = s.get_array("fmi2GetContinuousStates", nx);
    let (_, mut z) = s.get_array("fmi2GetEventIndicators", nz);
    for j in 0..n {
        let t = j as f64 * h;
        let (_, k1) = s.get_array("fmi2GetDerivatives", nx);
        let xp: Vec<f64> = x.iter().zip(&k1).map(|(a, b)| a + h * b).collect();
        s.set_time(t + h);
        s.set_states(&xp);
        let (_, k2) = s.get_array("fmi2GetDerivatives", nx);
        x = x
            .iter()
            .zip(k1.iter().zip(&k2))
            .map(|(a, (b, c))| a + 0.5 * h * (b + c))
            .collect();
        let st = s.set_states(&x);
        let (cst, enter) = s.completed_step();
        let (_, z1) = s.get_array("fmi2GetEventIndicators", nz);
        let crossed = z.iter().zip(&z1).any(|(a, b)| (*a > 0.0) != (*b > 0.0));
        if enter || crossed {
            s.event();
            let (_, x2) = s.get_array("fmi2GetContinuousStates", nx);
            x = x2;
        }
        let (_, z2) = s.get_array("fmi2GetEventIndicators", nz);
        z = z2;
        let (_, dx) = s.get_array("fmi2GetDerivatives", nx);
        write!(out, " me {j} {st:?} {cst:?} {}:", enter || crossed).unwrap();
        for v in x.iter().chain(&dx).chain(&z) {
            write!(out, " {:x}", v.to_bits()).unwrap();
        }
        out.push('\n');
        row(&s, &o, &mut out);
        logs(&s, &mut seen, &mut out);
    }
    writeln!(out, " terminate {:?}", s.call0("fmi2Terminate")).unwrap();
    logs(&s, &mut seen, &mut out);
    out
}

fn main() {
    let mut all = String::new();
    for e in catalog::all() {
        let f = Fmu::of(&e);
        let vars = (e.variables)();
        let vr = |name: &str| vars.iter().find(|(_, v)| v.name == name).map(|(vr, _)| *vr);
        let mechanism = vr("model.fidelity").is_some();
        let method = vr("solver.method");
        let mut runs: Vec<(String, String)> = vec![];
        if mechanism {
            let fid = vr("model.fidelity").unwrap();
            let mode = vr("drive.mode").unwrap();
            for level in levels(&e) {
                let ints = [(fid, level)];
                let start = Start {
                    integers: &ints,
                    ..Start::default()
                };
                let h = if level == 3 { 1e-3 } else { 4e-3 };
                runs.push((
                    format!("level {level}, inputs"),
                    cs(&f, &e, &start, 240, h, true, false),
                ));
                runs.push((
                    format!("level {level}, inputs and derivatives"),
                    cs(&f, &e, &start, 240, h, true, true),
                ));
                let ints = [(fid, level), (mode, 2)];
                let phi0 = vr("drive.phi0").map(|v| (v, 0.7));
                let reals: Vec<(u32, f64)> = phi0.into_iter().collect();
                let start = Start {
                    integers: &ints,
                    reals: &reals,
                    ..Start::default()
                };
                runs.push((
                    format!("level {level}, constant speed"),
                    cs(&f, &e, &start, 240, h, false, false),
                ));
                if level == 3 {
                    runs.push((
                        format!("level {level}, model exchange"),
                        me(&f, &e, &ints, 1500, 2e-5),
                    ));
                }
            }
            if let Some(n) = vr("drive.n") {
                // four times the nominal speed: lift-offs, dead points, large forces
                let n0 = vars
                    .iter()
                    .find(|(r, _)| *r == n)
                    .and_then(|(_, v)| v.start)
                    .unwrap();
                for level in levels(&e).into_iter().filter(|&l| l >= 2) {
                    let ints = [(fid, level), (mode, 2)];
                    let reals = [(n, 4.0 * n0)];
                    let start = Start {
                        integers: &ints,
                        reals: &reals,
                        ..Start::default()
                    };
                    runs.push((
                        format!("level {level}, fast"),
                        cs(&f, &e, &start, 240, 1e-3, false, false),
                    ));
                }
            }
            if let Some(m) = method {
                for k in 1..=4 {
                    let ints = [(fid, 3), (mode, 2), (m, k)];
                    let start = Start {
                        integers: &ints,
                        ..Start::default()
                    };
                    runs.push((
                        format!("method {k}"),
                        cs(&f, &e, &start, 200, 2e-3, false, false),
                    ));
                }
                if let Some(k) = vr("elastic.k") {
                    let k0 = vars
                        .iter()
                        .find(|(r, _)| *r == k)
                        .and_then(|(_, v)| v.start)
                        .unwrap();
                    let ints = [(fid, 3), (mode, 2)];
                    let reals = [(k, 100.0 * k0)];
                    let start = Start {
                        integers: &ints,
                        reals: &reals,
                        ..Start::default()
                    };
                    runs.push((
                        "stiffer chain".into(),
                        cs(&f, &e, &start, 200, 2e-3, false, false),
                    ));
                }
            }
        } else {
            runs.push((
                "defaults".into(),
                cs(&f, &e, &Start::default(), 400, 1e-3, false, false),
            ));
            runs.push(("model exchange".into(), me(&f, &e, &[], 1500, 5e-5)));
        }
        for (name, text) in runs {
            writeln!(all, "== {} {name}", e.identifier).unwrap();
            all.push_str(&text);
        }
    }
    print!("{all}");
}
