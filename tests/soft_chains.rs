//! A compliant chain so soft that it cannot drive its mechanism (`elastic.k` at its allowed
//! minimum, 1 N/m) is refused with the reason, never integrated into a member kilometres from
//! its stroke: every FMU with an elastodynamic level, through the C ABI.

mod common;

use bindery_fmu::catalog;
use bindery_fmu::fmi2::types::*;
use common::*;

#[test]
fn every_chain_too_soft_to_drive_its_mechanism_is_refused_with_the_reason() {
    let mut tested = 0;
    for e in catalog::all() {
        let vars = (e.variables)();
        if !vars.iter().any(|(_, v)| v.name == "elastic.k") {
            continue;
        }
        let f = Fmu::of(&e);
        let soft = Start {
            stop: Some(4.0),
            reals: &[(vr_of(&e, "elastic.k"), 1.0)],
            integers: &[(vr_of(&e, "model.fidelity"), 3)],
            ..Start::default()
        };
        let s = f.started("soft", &soft);
        let (h, mut t, mut refused) = (0.01, 0.0, None);
        for _ in 0..400 {
            match s.do_step(t, h) {
                Status::Ok => t += h,
                st => {
                    refused = Some(st);
                    break;
                }
            }
        }
        assert_eq!(
            refused,
            Some(Status::Discard),
            "{}: elastic.k = 1 N/m ran to t = {t} without a word",
            e.identifier
        );
        let why = s
            .logs()
            .iter()
            .rev()
            .find(|l| l.0 == Status::Discard)
            .map(|l| l.2.clone())
            .unwrap_or_default();
        assert!(
            why.contains("soft") && why.contains("elastic.k"),
            "{}: {why}",
            e.identifier
        );
        eprintln!("{} refused at t = {t}: {why}", e.identifier);
        tested += 1;
    }
    assert!(tested >= 3, "{tested} mechanisms with a compliant chain");
}
