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
        // the GUID is the hash without the date: it names the interface, not the packaging
        let unsigned = xml
            .replace(&format!("guid=\"{guid}\""), "guid=\"\"")
            .replace(
                &format!(" generationDateAndTime=\"{}\"", md::VERSION_DATE),
                "",
            );
        assert_eq!(md::format_guid(md::fnv1a_128(unsigned.as_bytes())), guid);
        // any change of content changes the GUID
        let changed = unsigned.replace("shaft.phi", "shaft.Phi"); // in every FMU
        assert_ne!(md::format_guid(md::fnv1a_128(changed.as_bytes())), guid);
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
