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

#[test]
fn guid_is_the_hash_of_the_content() {
    for e in catalog::all() {
        let (xml, guid) = (e.describe)();
        let unsigned = xml.replace(&format!("guid=\"{guid}\""), "guid=\"\"");
        assert_eq!(md::format_guid(md::fnv1a_128(unsigned.as_bytes())), guid);
        // any change of content changes the GUID
        let changed = unsigned.replace("shaft.phi", "shaft.Phi"); // in every FMU
        assert_ne!(md::format_guid(md::fnv1a_128(changed.as_bytes())), guid);
    }
}
