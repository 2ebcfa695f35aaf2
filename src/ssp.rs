//! The two bookbinding machines as systems of FMUs, written as SSP 1.0 files (System Structure
//! and Parameterization: a zip with `SystemStructure.ssd` and the FMUs under `resources/`).
//!
//! A machine is a small table ([`machines`]): its components (an FMU of the catalog, a name,
//! parameter values) and its connections (output → input, 1:1 as SSP wants). The main shaft's
//! load is summed by giving MainShaft one input pair per mechanism (`load1..3.tau0`,
//! `load1..3.J_red`; unused ones stay 0), so any SSP tool can run it without an adder element.
//! Parameter values are one `ParameterBinding` of the system with names `<component>.<variable>`
//! (SSP 1.0, 5.3.3); FMPy's `simulate_ssp` takes them as its `parameter_set`.

use crate::catalog;
use crate::model::Causality;
use std::f64::consts::PI;
use std::io::Write;
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, DateTime, ZipWriter};

/// One FMU instance of a machine.
#[derive(Clone, Debug, PartialEq)]
pub struct Component {
    /// Element name; no name may be a prefix of another plus `.` (FMPy matches parameters by
    /// prefix).
    pub name: &'static str,
    /// `modelIdentifier` of a catalog FMU.
    pub fmu: &'static str,
    /// Real parameter values `(variable, value)`.
    pub params: Vec<(&'static str, f64)>,
    /// Outputs to record besides the connected ones.
    pub record: Vec<&'static str>,
}

/// A connection `((element, output), (element, input))`.
pub type Wire = ((&'static str, &'static str), (&'static str, &'static str));

/// A machine: its components and connections `((element, output), (element, input))`.
#[derive(Clone, Debug, PartialEq)]
pub struct Machine {
    /// File name (without `.ssp`) and system name.
    pub name: &'static str,
    pub description: &'static str,
    pub components: Vec<Component>,
    pub connections: Vec<Wire>,
    /// Nominal main-shaft speed, rad/s (for reports).
    pub nominal_w: f64,
    /// `DefaultExperiment` stop time, s.
    pub stop: f64,
}

const RPM: f64 = PI / 30.0;

/// Connections of the main shaft `drive` to a mechanism `m`, its loads to input pair `k`.
fn shaft_to(m: &'static str, k: usize) -> Vec<Wire> {
    let (j, t) = match k {
        1 => ("load1.J_red", "load1.tau0"),
        2 => ("load2.J_red", "load2.tau0"),
        _ => ("load3.J_red", "load3.tau0"),
    };
    vec![
        (("drive", "shaft.phi"), (m, "shaft.phi")),
        (("drive", "shaft.w"), (m, "shaft.w")),
        (("drive", "shaft.a"), (m, "shaft.a")),
        ((m, "shaft.J_red"), ("drive", j)),
        ((m, "shaft.tau0"), ("drive", t)),
    ]
}

/// The drive parameters of the three-knife trimmer (30 rpm main shaft): every value an
/// assumption (the paper gives none): a 3 kW four-pole motor, gear 1:50, a flywheel, and the
/// shaft already at its nominal speed. From rest, the first cut comes before the flywheel has
/// the energy for it (about 0.9 kJ a knife) and the shaft stalls: a trimmer's clutch engages the
/// knife drive once the flywheel runs (the start-up is computed without the cutting load).
pub fn trimmer_drive(fly_j: f64) -> Vec<(&'static str, f64)> {
    vec![
        ("motor.P_rated", 3000.0),
        ("motor.J", 0.0095),
        ("gear.i", 50.0),
        ("fly.J", fly_j),
        ("init.w", 30.0 * RPM),
    ]
}

/// Default flywheel of the trimmer's main shaft, kg·m² (assumption).
pub const TRIMMER_FLY_J: f64 = 3000.0;

/// The two machines.
pub fn machines() -> Vec<Machine> {
    let sewing = {
        let mut connections = shaft_to("table", 1);
        connections.extend([
            (("drive", "shaft.phi"), ("perforators", "shaft.phi")),
            (("drive", "shaft.w"), ("perforators", "shaft.w")),
            (("drive", "shaft.a"), ("perforators", "shaft.a")),
            // the perforator drive rides on the table: its force on the table is part of the
            // table's torque (tests/python/test_sewing_coupling.py), so the perforators' own
            // torque is not summed again at the main shaft
            (("perforators", "table.F"), ("table", "table.F_ext")),
        ]);
        Machine {
            name: "ThreadSewingMachine",
            description: "Thread-sewing machine: main-shaft drive, cam-driven sewing table and the perforator drive riding on it (papers 000, 002)",
            components: vec![
                Component {
                    name: "drive",
                    fmu: "MainShaft",
                    params: vec![],
                    record: vec!["motor.tau", "motor.P", "shaft.tau_load"],
                },
                Component {
                    name: "table",
                    fmu: "SewingTable",
                    params: vec![],
                    record: vec!["table.x", "shaft.tau"],
                },
                Component {
                    name: "perforators",
                    fmu: "Perforators",
                    params: vec![],
                    record: vec!["perforators.s", "shaft.tau"],
                },
            ],
            connections,
            nominal_w: 100.0 * RPM,
            stop: 4.0,
        }
    };
    let trimmer = {
        let mut connections = shaft_to("side_left", 1);
        connections.extend(shaft_to("side_right", 2));
        connections.extend(shaft_to("front", 3));
        let knife = |name, phi0: f64| Component {
            name,
            fmu: "GenevaKnifeDrive",
            params: if phi0 != 0.0 {
                vec![("drive.phi0", phi0)]
            } else {
                vec![]
            },
            record: vec!["knife.s", "shaft.tau"],
        };
        Machine {
            name: "ThreeKnifeTrimmer",
            description: "Three-knife trimmer: main-shaft drive and the Geneva knife drives of the two side knives (in phase) and the front knife (half a turn later; assumption) (paper 003)",
            components: vec![
                Component {
                    name: "drive",
                    fmu: "MainShaft",
                    params: trimmer_drive(TRIMMER_FLY_J),
                    record: vec!["motor.tau", "motor.P", "shaft.tau_load"],
                },
                knife("side_left", 0.0),
                knife("side_right", 0.0),
                knife("front", PI),
            ],
            connections,
            nominal_w: 30.0 * RPM,
            stop: 12.0,
        }
    };
    vec![sewing, trimmer]
}

fn esc(s: &str) -> String {
    crate::docs::escape(s)
}

/// Checks a machine against the catalog: every FMU known, every connection from an output to an
/// input of the named components, every input connected at most once, every parameter a
/// parameter, no component name a prefix of another.
pub fn check(m: &Machine) -> Result<(), String> {
    let all = catalog::all();
    let vars_of = |c: &Component| {
        all.iter()
            .find(|e| e.identifier == c.fmu)
            .map(|e| (e.variables)())
            .ok_or_else(|| format!("{}: component {}: unknown FMU {}", m.name, c.name, c.fmu))
    };
    let comp = |name: &str| {
        m.components
            .iter()
            .find(|c| c.name == name)
            .ok_or_else(|| format!("{}: no component {name}", m.name))
    };
    let causality = |c: &Component, var: &str| -> Result<Causality, String> {
        vars_of(c)?
            .iter()
            .find(|(_, v)| v.name == var)
            .map(|(_, v)| v.causality)
            .ok_or_else(|| format!("{}: {} ({}) has no variable {var}", m.name, c.name, c.fmu))
    };
    for a in &m.components {
        for b in &m.components {
            if a.name != b.name && b.name.starts_with(a.name) || a.name.is_empty() {
                return Err(format!(
                    "{}: component name {} is a prefix of {}",
                    m.name, a.name, b.name
                ));
            }
        }
        for (p, x) in &a.params {
            if causality(a, p)? != Causality::Parameter || !x.is_finite() {
                return Err(format!(
                    "{}: {}.{p} = {x} is not a parameter value",
                    m.name, a.name
                ));
            }
        }
        for r in &a.record {
            if causality(a, r)? != Causality::Output {
                return Err(format!("{}: {}.{r} is not an output", m.name, a.name));
            }
        }
    }
    let mut ends = std::collections::HashSet::new();
    for ((e1, c1), (e2, c2)) in &m.connections {
        if causality(comp(e1)?, c1)? != Causality::Output {
            return Err(format!("{}: {e1}.{c1} is not an output", m.name));
        }
        if causality(comp(e2)?, c2)? != Causality::Input {
            return Err(format!("{}: {e2}.{c2} is not an input", m.name));
        }
        if !ends.insert((e2, c2)) {
            return Err(format!("{}: {e2}.{c2} connected twice", m.name));
        }
    }
    Ok(())
}

/// `SystemStructure.ssd` of a machine (SSP 1.0).
pub fn ssd(m: &Machine) -> Result<String, String> {
    check(m)?;
    let mut x = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    x += "<ssd:SystemStructureDescription xmlns:ssc=\"http://ssp-standard.org/SSP1/SystemStructureCommon\" xmlns:ssd=\"http://ssp-standard.org/SSP1/SystemStructureDescription\" xmlns:ssv=\"http://ssp-standard.org/SSP1/SystemStructureParameterValues\" version=\"1.0\"";
    x += &format!(
        " name=\"{}\" generationTool=\"bindery-fmu {}\">\n",
        esc(m.name),
        env!("CARGO_PKG_VERSION")
    );
    x += &format!(
        "  <ssd:System name=\"{}\" description=\"{}\">\n",
        esc(m.name),
        esc(m.description)
    );
    let params: Vec<_> = m
        .components
        .iter()
        .flat_map(|c| c.params.iter().map(move |(p, v)| (c.name, *p, *v)))
        .collect();
    if !params.is_empty() {
        x += "    <ssd:ParameterBindings>\n      <ssd:ParameterBinding>\n        <ssd:ParameterValues>\n";
        x += &format!(
            "          <ssv:ParameterSet version=\"1.0\" name=\"{}\">\n            <ssv:Parameters>\n",
            esc(m.name)
        );
        for (c, p, v) in params {
            x += &format!(
                "              <ssv:Parameter name=\"{}.{}\"><ssv:Real value=\"{}\"/></ssv:Parameter>\n",
                esc(c),
                esc(p),
                crate::md::fmt_real(v)
            );
        }
        x += "            </ssv:Parameters>\n          </ssv:ParameterSet>\n        </ssd:ParameterValues>\n      </ssd:ParameterBinding>\n    </ssd:ParameterBindings>\n";
    }
    x += "    <ssd:Elements>\n";
    for c in &m.components {
        x += &format!(
            "      <ssd:Component name=\"{}\" type=\"application/x-fmu-sharedlibrary\" source=\"resources/{}.fmu\">\n        <ssd:Connectors>\n",
            esc(c.name),
            esc(c.fmu)
        );
        // connected inputs and outputs, then the recorded outputs, each once, in that order
        let mut seen: Vec<(&str, &str)> = Vec::new();
        let mut connectors = Vec::new();
        for ((e1, c1), (e2, c2)) in &m.connections {
            if *e2 == c.name && !seen.contains(&(c2, "input")) {
                seen.push((c2, "input"));
                connectors.push((*c2, "input"));
            }
            if *e1 == c.name && !seen.contains(&(c1, "output")) {
                seen.push((c1, "output"));
                connectors.push((*c1, "output"));
            }
        }
        for r in &c.record {
            if !seen.contains(&(r, "output")) {
                seen.push((r, "output"));
                connectors.push((*r, "output"));
            }
        }
        for (name, kind) in connectors {
            x += &format!(
                "          <ssd:Connector name=\"{}\" kind=\"{kind}\"><ssc:Real/></ssd:Connector>\n",
                esc(name)
            );
        }
        x += "        </ssd:Connectors>\n      </ssd:Component>\n";
    }
    x += "    </ssd:Elements>\n    <ssd:Connections>\n";
    for ((e1, c1), (e2, c2)) in &m.connections {
        x += &format!(
            "      <ssd:Connection startElement=\"{}\" startConnector=\"{}\" endElement=\"{}\" endConnector=\"{}\"/>\n",
            esc(e1),
            esc(c1),
            esc(e2),
            esc(c2)
        );
    }
    x += "    </ssd:Connections>\n  </ssd:System>\n";
    x += &format!(
        "  <ssd:DefaultExperiment startTime=\"0.0\" stopTime=\"{}\"/>\n",
        crate::md::fmt_real(m.stop)
    );
    x += "</ssd:SystemStructureDescription>\n";
    Ok(x)
}

/// The `.ssp` archive: `SystemStructure.ssd` and `resources/<id>.fmu` of every FMU used, read by
/// `fmu(id)` (the built FMU's bytes). Reproducible: fixed order and timestamps.
pub fn package(
    m: &Machine,
    mut fmu: impl FnMut(&str) -> Result<Vec<u8>, String>,
) -> Result<Vec<u8>, String> {
    let ssd = ssd(m)?;
    let mut ids: Vec<&str> = m.components.iter().map(|c| c.fmu).collect();
    ids.sort_unstable();
    ids.dedup();
    let mut zip = ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let opts = SimpleFileOptions::default()
        .compression_method(CompressionMethod::Deflated)
        .last_modified_time(DateTime::default())
        .unix_permissions(0o644);
    zip.start_file("SystemStructure.ssd", opts)
        .map_err(|e| e.to_string())?;
    zip.write_all(ssd.as_bytes()).map_err(|e| e.to_string())?;
    for id in ids {
        let bytes = fmu(id)?;
        let path = format!("resources/{id}.fmu");
        zip.start_file(
            path.as_str(),
            opts.compression_method(CompressionMethod::Stored),
        )
        .map_err(|e| format!("{path}: {e}"))?;
        zip.write_all(&bytes).map_err(|e| format!("{path}: {e}"))?;
    }
    Ok(zip.finish().map_err(|e| e.to_string())?.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn machines_are_consistent_with_the_catalog() {
        for m in machines() {
            check(&m).unwrap();
            let x = ssd(&m).unwrap();
            // every MainShaft input a connection feeds is declared once as a connector
            for ((_, _), (e2, c2)) in &m.connections {
                assert!(x.contains(&format!("endElement=\"{e2}\" endConnector=\"{c2}\"")));
            }
        }
    }

    #[test]
    fn bad_machines_are_refused_by_name() {
        let mut m = machines().remove(0);
        m.connections
            .push((("table", "table.x"), ("drive", "load.tau")));
        m.connections
            .push((("table", "table.x"), ("drive", "load.tau")));
        assert!(check(&m).unwrap_err().contains("connected twice"));
        let mut m = machines().remove(0);
        m.connections
            .push((("drive", "load.tau"), ("table", "table.F_ext")));
        assert!(
            check(&m)
                .unwrap_err()
                .contains("drive.load.tau is not an output")
        );
        let mut m = machines().remove(1);
        m.components[1].params.push(("knife.s", 1.0));
        assert!(check(&m).unwrap_err().contains("not a parameter"));
    }

    #[test]
    fn archive_layout_and_reproducibility() {
        let m = machines().remove(1);
        let fake = |id: &str| Ok(id.as_bytes().to_vec());
        let a = package(&m, fake).unwrap();
        assert_eq!(a, package(&m, fake).unwrap());
        let mut z = zip::ZipArchive::new(std::io::Cursor::new(a)).unwrap();
        let names: Vec<String> = (0..z.len())
            .map(|i| z.by_index(i).unwrap().name().unwrap().to_string())
            .collect();
        assert_eq!(
            names,
            [
                "SystemStructure.ssd",
                "resources/GenevaKnifeDrive.fmu",
                "resources/MainShaft.fmu"
            ]
        );
    }
}
