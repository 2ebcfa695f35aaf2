//! What a user reads cites only what a user has (issue 16): the README, `docs/`, the scenes'
//! README, the CLI's help, every FMU's and scene FMU's documentation page and model description
//! name no working file of the project's authors (`../shared`, the spec's pages), and every
//! relative link of the Markdown pages leads to a file of the repository.

use bindery_fmu::catalog;
use bindery_fmu::scene::Scene;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Texts a user never has: the authors' working material.
const FOREIGN: &[&str] = &[
    "../shared",
    "shared/spec",
    "spec/",
    "dynamics.md",
    "interface.md",
    "scenes.md",
    "motion-laws.md",
    "sewing-table.md",
    "perforators.md",
    "geneva-knife-drive.md",
    "disc-knife-drive.md",
    "legacy-needle-drive.md",
    "the spec",
];

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The Markdown pages a user reads.
fn markdown() -> Vec<PathBuf> {
    let mut pages = vec![
        root().join("README.md"),
        root().join("scenes/README.md"),
        root().join("BENCHMARKS.md"),
    ];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    docs.sort();
    pages.extend(docs);
    pages
}

fn foreign_in(what: &str, text: &str) -> Vec<String> {
    FOREIGN
        .iter()
        .filter(|f| text.contains(**f))
        .map(|f| format!("{what}: {f:?}"))
        .collect()
}

#[test]
fn markdown_pages_cite_only_what_is_in_the_repository() {
    let mut bad = vec![];
    for page in markdown() {
        let text = std::fs::read_to_string(&page).unwrap();
        let name = page.strip_prefix(root()).unwrap().display().to_string();
        bad.extend(foreign_in(&name, &text));
        // every relative link: ](target) with target a file or folder of the repository
        for part in text.split("](").skip(1) {
            let target = part.split(')').next().unwrap_or("");
            let file = target.split('#').next().unwrap_or("");
            if file.is_empty() || file.contains("://") {
                continue;
            }
            if !page.parent().unwrap().join(file).exists() {
                bad.push(format!("{name}: link to {target:?}, which is not there"));
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn cli_help_cites_only_what_is_in_the_repository() {
    let help = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_bindery"))
            .args(args)
            .output()
            .unwrap();
        assert!(out.status.success(), "{args:?}");
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let mut bad = foreign_in("bindery --help", &help(&["--help"]));
    for cmd in [
        "build", "docs", "liftoff", "report", "ssp", "machines", "scene", "describe",
    ] {
        bad.extend(foreign_in(
            &format!("bindery {cmd} --help"),
            &help(&[cmd, "--help"]),
        ));
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn fmu_pages_and_descriptions_cite_only_what_is_in_the_fmu() {
    let mut bad = vec![];
    for e in catalog::all() {
        let (files, _) = (e.documentation)().unwrap();
        let page = String::from_utf8(files[0].1.clone()).unwrap();
        bad.extend(foreign_in(&format!("{} index.html", e.identifier), &page));
        bad.extend(foreign_in(
            &format!("{} modelDescription.xml", e.identifier),
            &(e.describe)().0,
        ));
    }
    let mut scenes: Vec<PathBuf> = std::fs::read_dir(root().join("scenes"))
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    scenes.sort();
    assert!(!scenes.is_empty());
    for f in scenes {
        let scene = Scene::parse(&std::fs::read_to_string(&f).unwrap()).unwrap();
        let (entry, t) = catalog::tailor(&scene).unwrap();
        let files = (entry.scene_documentation)(&t).unwrap();
        let page = String::from_utf8(files[0].1.clone()).unwrap();
        bad.extend(foreign_in(&format!("{} index.html", t.identifier), &page));
        bad.extend(foreign_in(
            &format!("{} modelDescription.xml", t.identifier),
            &t.model_description(),
        ));
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}
