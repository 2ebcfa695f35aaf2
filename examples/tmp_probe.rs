use bindery_fmu::mechanisms::geneva_knife_drive::GenevaKnifeDrive;
use bindery_fmu::model::{Model, NoLog, Values, VarSet};
fn main() {
    type M = GenevaKnifeDrive;
    let index = |name: &str| {
        <<M as Model>::Var as VarSet>::table()
            .iter()
            .position(|d| d.name == name)
            .unwrap()
    };
    let mut v = Values::<<M as Model>::Var>::start();
    for (n, x) in [
        ("model.fidelity", 3.0),
        ("drive.mode", 2.0),
        ("drive.n", std::f64::consts::PI),
        ("solver.method", 3.0),
        ("solver.rtol", 1e-9),
        ("solver.atol", 1e-12),
        ("elastic.k", 1e4),
        ("elastic.zeta", 0.0),
    ] {
        v.raw_mut()[index(n)] = x;
    }
    let mut m = M::prepare(&v).unwrap();
    for i in 0..215 {
        if let Err(e) = m.step(&mut v, i as f64 * 1e-3, 1e-3, &mut NoLog) {
            println!("err {e:?}");
            break;
        }
    }
}
