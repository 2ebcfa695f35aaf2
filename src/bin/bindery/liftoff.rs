//! `bindery liftoff`: the lowest main-shaft speed at which the Perforators' spring lets the
//! roller lift off the ramp (the kinetostatic model: the smallest ramp contact force over a turn
//! at a constant speed turns negative), by bisection on the speed, for any parameter set.

use crate::params::{self, Setting, shown};
use bindery_fmu::catalog::variables_of;
use bindery_fmu::mechanisms::perforators::model::{Perforators, V};
use bindery_fmu::model::{Model, Values, VarSet};

/// Samples per shaft turn of the lift-off search.
const LIFTOFF_SAMPLES: usize = 7200;
const RPM: f64 = std::f64::consts::PI / 30.0;

/// The settings of `--m0`, `--kt` and `--set`, checked against the Perforators' parameters.
pub fn settings(m0: Option<f64>, kt: Option<f64>, set: &[String]) -> Result<Vec<Setting>, String> {
    let vars = variables_of::<Perforators>();
    let mut texts: Vec<String> = Vec::new();
    texts.extend(m0.map(|x| format!("spring.M0={x}")));
    texts.extend(kt.map(|x| format!("spring.kt={x}")));
    texts.extend(set.iter().cloned());
    params::parse_all(
        "Perforators",
        &vars,
        &texts,
        &["drive.n", "drive.mode", "drive.phi0"],
        "the search sets the speed itself (--from, --to, rpm)",
    )
}

pub fn liftoff(from: f64, to: f64, set: &[Setting]) -> Result<(), String> {
    if !(from.is_finite() && to.is_finite() && from > 0.0 && to > from) {
        return Err(format!("--from {from} --to {to}: want 0 < from < to (rpm)"));
    }
    let mut v = Values::<V>::start();
    for s in set {
        v.raw_mut()[s.vr as usize] = s.value;
    }
    let model = Perforators::prepare(&v).map_err(|e| format!("refused: {e}"))?;
    let d = model.drive();
    let table = <V as VarSet>::table();
    let with = if set.is_empty() {
        "default parameters".to_string()
    } else {
        set.iter()
            .map(|s| format!("{} = {}", s.name, shown(&table[s.vr as usize], s.value)))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let (f_from, phi_from) = d.min_contact_force(from * RPM, LIFTOFF_SAMPLES);
    if f_from < 0.0 {
        println!(
            "{with}: the roller lifts off already at {from} rpm, the lowest speed searched \
             (the ramp would have to pull with {:.2} N at shaft angle {:.2} deg): search from a lower --from",
            -f_from,
            phi_from.to_degrees()
        );
        return Ok(());
    }
    let (f_to, phi_to) = d.min_contact_force(to * RPM, LIFTOFF_SAMPLES);
    if f_to >= 0.0 {
        println!(
            "{with}: no lift-off up to {to} rpm (the smallest contact force at {to} rpm is {f_to:.2} N, \
             at shaft angle {:.2} deg)",
            phi_to.to_degrees()
        );
        return Ok(());
    }
    let w = d
        .liftoff_speed(from * RPM, to * RPM, 1e-6, LIFTOFF_SAMPLES)
        .ok_or("the bisection found no threshold although the ends bracket one")?;
    let (f, phi) = d.min_contact_force(w, LIFTOFF_SAMPLES);
    let (f_below, _) = d.min_contact_force(w - 1e-4, LIFTOFF_SAMPLES);
    println!(
        "{with}: the roller lifts off the ramp above {:.2} rpm \
         (first at shaft angle {:.2} deg, phase {:?}; smallest contact force {f:.4} N there, {f_below:.4} N just below)",
        w / RPM,
        phi.to_degrees(),
        d.cyc.at(phi).phase
    );
    Ok(())
}
