//! The layers of `ARCHITECTURE.md`, checked on the source: what the FMI runtime, the model
//! interface, the solver and the shared mechanics may name of the crate, and that no two
//! modules use each other (no cycle among the top-level modules and the mechanisms' folders).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The module a file of `src/` belongs to: `fmi2`, `model`, `mechanisms/perforators`...
fn module_of(rel: &Path) -> Option<String> {
    let parts: Vec<&str> = rel.iter().map(|s| s.to_str().unwrap()).collect();
    let top = parts[0].trim_end_matches(".rs");
    match top {
        "lib" | "bin" => None,
        "mechanisms" if parts.len() > 2 => Some(format!("mechanisms/{}", parts[1])),
        t => Some(t.to_string()),
    }
}

/// The code of a file without comments and without its test modules.
fn code(text: &str, file: &Path) -> String {
    if file
        .file_name()
        .is_some_and(|n| n.to_str().unwrap().contains("tests"))
    {
        return String::new();
    }
    let text = match text.find("#[cfg(test)]\nmod tests {") {
        Some(i) => &text[..i],
        None => text,
    };
    text.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// Module -> the crate's modules it names (`crate::x`, `crate::mechanisms::y`).
fn uses() -> BTreeMap<String, BTreeSet<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = vec![];
    rust_files(&src, &mut files);
    let modules: BTreeSet<String> = files
        .iter()
        .filter_map(|f| module_of(f.strip_prefix(&src).unwrap()))
        .collect();
    let mut out: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for f in &files {
        let Some(m) = module_of(f.strip_prefix(&src).unwrap()) else {
            continue;
        };
        let text = code(&std::fs::read_to_string(f).unwrap(), f);
        let entry = out.entry(m.clone()).or_default();
        for (i, _) in text.match_indices("crate::") {
            let rest = &text[i + "crate::".len()..];
            let word = |s: &str| -> String {
                s.chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect()
            };
            let mut d = word(rest);
            if d == "mechanisms" {
                let next = word(&rest["mechanisms::".len().min(rest.len())..]);
                if !next.is_empty() && modules.contains(&format!("mechanisms/{next}")) {
                    d = format!("mechanisms/{next}");
                }
            }
            if modules.contains(&d)
                && d != m
                && !(m.starts_with("mechanisms/") && d == "mechanisms")
            {
                entry.insert(d);
            }
        }
    }
    out
}

#[test]
fn the_layers_use_only_what_architecture_md_allows() {
    let uses = uses();
    let allowed: [(&str, &[&str]); 6] = [
        ("mechanics", &[]),
        ("model", &["mechanics", "lifetime"]),
        ("solver", &["model", "mechanics"]),
        ("md", &["model"]),
        ("fmi2", &["model", "md", "scene", "lifetime"]),
        ("fmi3", &["fmi2", "model"]),
    ];
    for (m, ok) in allowed {
        let used = uses.get(m).cloned().unwrap_or_default();
        let bad: Vec<&String> = used.iter().filter(|d| !ok.contains(&d.as_str())).collect();
        assert!(
            bad.is_empty(),
            "{m} uses {bad:?}; ARCHITECTURE.md allows {ok:?}"
        );
    }
    // the runtime names no mechanism, no mechanism names the runtime
    for (m, used) in &uses {
        if m.starts_with("mechanisms") {
            assert!(!used.contains("fmi2"), "{m} uses the FMI runtime");
            assert!(!used.contains("fmi3"), "{m} uses the FMI 3.0 runtime");
        }
    }
}

#[test]
fn no_two_modules_use_each_other() {
    let uses = uses();
    // a cycle through any number of modules: a module that reaches itself
    for start in uses.keys() {
        let mut seen = BTreeSet::new();
        let mut stack: Vec<(String, Vec<String>)> = vec![(start.clone(), vec![start.clone()])];
        while let Some((m, path)) = stack.pop() {
            for d in uses.get(&m).into_iter().flatten() {
                assert!(d != start, "import cycle: {} -> {d}", path.join(" -> "));
                if seen.insert(d.clone()) {
                    let mut p = path.clone();
                    p.push(d.clone());
                    stack.push((d.clone(), p));
                }
            }
        }
    }
    assert!(uses.len() >= 15, "{:?}", uses.keys());
}
