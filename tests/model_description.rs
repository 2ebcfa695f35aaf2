//! The committed `modelDescription/<id>.xml` of every FMU is what the code generates: any
//! interface change shows up in review. Regenerate with `cargo run --release -- describe`.

use bindery_fmu::catalog;
use bindery_fmu::md;
use std::path::Path;

#[test]
fn committed_model_descriptions_are_current() {
    for e in catalog::all() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("modelDescription")
            .join(format!("{}.xml", e.identifier));
        let committed = std::fs::read_to_string(&path)
            .unwrap_or_else(|err| panic!("{}: {err}", path.display()));
        let (generated, guid) = (e.describe)();
        assert!(
            committed == generated,
            "{} is stale: run `cargo run --release -- describe` and commit it",
            path.display()
        );
        assert!(committed.contains(&format!("guid=\"{guid}\"")));
    }
}

/// The same for the FMI 3.0 descriptions (`modelDescription/fmi3/<id>.xml`), whose
/// instantiation token is the FMI 2.0 GUID of the same declarations.
#[test]
fn committed_fmi3_model_descriptions_are_current() {
    for e in catalog::all() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("modelDescription/fmi3")
            .join(format!("{}.xml", e.identifier));
        let committed = std::fs::read_to_string(&path)
            .unwrap_or_else(|err| panic!("{}: {err}", path.display()));
        let (generated, token) = (e.describe3)();
        assert!(
            committed == generated,
            "{} is stale: run `cargo run --release -- describe` and commit it",
            path.display()
        );
        assert_eq!(token, (e.describe)().1, "{}", e.identifier);
        assert!(committed.contains(&format!("instantiationToken=\"{token}\"")));
        assert!(committed.contains("fmiVersion=\"3.0\""));
    }
}

#[test]
fn declarations_are_valid_fmi2() {
    for e in catalog::all() {
        let vars: Vec<_> = (e.variables)()
            .into_iter()
            .map(|(_, v)| v.clone())
            .collect();
        md::check(&vars).unwrap_or_else(|err| panic!("{}: {err}", e.identifier));
    }
}

/// The GUID the binary computes from the declarations (no XML written) is the one the written
/// description carries, and it names the content: every change of what a description states
/// changes it, whichever attribute of whichever variable, or of the model, changes.
#[test]
fn guid_names_what_the_description_states() {
    use bindery_fmu::model::{Causality, Initial, Var, VarType, Variability};
    let unsigned = |xml: &str, guid: &str| xml.replace(&format!("guid=\"{guid}\""), "guid=\"\"");
    let mut seen = std::collections::HashMap::<String, String>::new();
    for e in catalog::all() {
        let (xml, guid) = (e.describe)();
        assert!(xml.contains(&format!("guid=\"{guid}\"")));
        let info = (e.info)();
        let vars: Vec<(u32, Var)> = (e.variables)()
            .into_iter()
            .map(|(vr, v)| (vr, v.clone()))
            .collect();
        let describe = |info: &md::ModelInfo, vars: &[(u32, Var)]| {
            let refs: Vec<(u32, &Var)> = vars.iter().map(|(vr, v)| (*vr, v)).collect();
            md::describe_vars(info, &refs)
        };
        assert_eq!(describe(&info, &vars), (xml.clone(), guid.clone()));
        let mut variants = vec![];
        // every attribute of a few variables of each kind
        let picks: Vec<usize> = [
            Causality::Parameter,
            Causality::Input,
            Causality::Output,
            Causality::Local,
            Causality::CalculatedParameter,
        ]
        .iter()
        .filter_map(|c| vars.iter().position(|(_, v)| v.causality == *c))
        .collect();
        for &i in &picks {
            let edits: [fn(&mut Var); 13] = [
                |v| v.name = "renamed.variable",
                |v| v.description = "another description",
                |v| v.start = Some(v.start.unwrap_or(0.0) + 1.0),
                |v| v.min = Some(v.min.unwrap_or(-1e9) - 1.0),
                |v| v.max = Some(v.max.unwrap_or(1e9) + 1.0),
                |v| {
                    v.unit = if v.unit == Some("m") {
                        Some("rad")
                    } else {
                        Some("m")
                    }
                },
                |v| {
                    v.display_unit = if v.display_unit.is_some() {
                        None
                    } else {
                        Some("mm")
                    }
                },
                |v| {
                    v.causality = if v.causality == Causality::Local {
                        Causality::Output
                    } else {
                        Causality::Local
                    }
                },
                |v| {
                    v.variability = if v.variability == Variability::Fixed {
                        Variability::Tunable
                    } else {
                        Variability::Fixed
                    }
                },
                |v| {
                    v.initial = if v.initial == Some(Initial::Exact) {
                        Some(Initial::Approx)
                    } else {
                        Some(Initial::Exact)
                    }
                },
                |v| {
                    v.ty = if v.ty == VarType::Real {
                        VarType::Integer
                    } else {
                        VarType::Real
                    }
                },
                |v| v.depends = if v.depends.is_empty() { &[0] } else { &[] },
                |v| {
                    v.derivative = if v.derivative.is_some() {
                        None
                    } else {
                        Some(0)
                    }
                },
            ];
            for edit in &edits {
                let mut changed = vars.clone();
                edit(&mut changed[i].1);
                variants.push((info.clone(), changed));
            }
            let mut fewer = vars.clone();
            fewer.remove(i);
            variants.push((info.clone(), fewer));
        }
        let mut other = info.clone();
        other.description = "another model";
        variants.push((other, vars.clone()));
        let mut other = info.clone();
        other.experiment.stop += 1.0;
        variants.push((other, vars.clone()));
        let mut other = info.clone();
        other.can_interpolate_inputs = !other.can_interpolate_inputs;
        variants.push((other, vars.clone()));
        let mut count = 0;
        for (info, vars) in &variants {
            let (x, g) = describe(info, vars);
            let content = unsigned(&x, &g);
            if content != unsigned(&xml, &guid) {
                assert_ne!(
                    g, guid,
                    "{}: a changed description kept the GUID",
                    e.identifier
                );
                count += 1;
            }
            // one GUID, one content, over every variant of every model
            if let Some(c) = seen.insert(g.clone(), content.clone()) {
                assert_eq!(c, content, "{}: two contents share GUID {g}", e.identifier);
            }
        }
        // all but edits that leave a variable as it was (a unit already "m", say) or that the
        // writer cannot state (a derivative on a non-state) change the description
        assert!(
            count >= 10 * picks.len(),
            "{}: {count} variants of {} changed the description",
            e.identifier,
            variants.len()
        );
    }
}

/// FMPy and other hosts show who made an FMU, its version and when (issue 16): author, version,
/// copyright, license (Cargo.toml's), generation tool and date. The committed files carry the
/// stable [`md::VERSION_DATE`]; a build stamps the commit's date, which leaves the GUID alone.
#[test]
fn descriptions_say_who_made_them_when_and_on_which_terms() {
    let cargo =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("Cargo.toml")).unwrap();
    let license = cargo
        .lines()
        .find_map(|l| l.strip_prefix("license = "))
        .expect("Cargo.toml names a license")
        .trim_matches('"');
    for e in catalog::all() {
        let (xml, guid) = (e.describe)();
        let head = xml.lines().nth(1).unwrap();
        for attr in [
            format!("author=\"{}\"", md::AUTHOR),
            format!("version=\"{}\"", env!("CARGO_PKG_VERSION")),
            format!("copyright=\"{}\"", md::COPYRIGHT),
            format!("license=\"{license}\""),
            format!(
                "generationTool=\"bindery-fmu {}\"",
                env!("CARGO_PKG_VERSION")
            ),
            format!("generationDateAndTime=\"{}\"", md::VERSION_DATE),
        ] {
            assert!(
                head.contains(&attr),
                "{}: {attr} not in {head}",
                e.identifier
            );
        }
        let stamped = md::stamp(&xml, "2030-01-02T03:04:05Z");
        assert!(stamped.contains("generationDateAndTime=\"2030-01-02T03:04:05Z\""));
        assert!(stamped.contains(&format!("guid=\"{guid}\"")));
        assert_eq!(
            stamped.replace("2030-01-02T03:04:05Z", md::VERSION_DATE),
            xml,
            "only the date changes"
        );
    }
}
