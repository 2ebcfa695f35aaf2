//! The two bookbinding machines as systems of FMUs, written as SSP 1.0 files (System Structure
//! and Parameterization: a zip with `SystemStructure.ssd` and the FMUs under `resources/`).
//!
//! A machine is a small table ([`machines`]): its components (an FMU of the catalog, a name,
//! parameter values, the outputs a designer reads) and its connections (output → input, 1:1 as
//! SSP wants). The main shaft's load is summed by giving MainShaft one input pair per mechanism
//! (`load1..3.tau0`, `load1..3.J_red`; unused ones stay 0), so any SSP tool can run it without
//! an adder element.
//!
//! Where a tool finds the machine's values: not every tool applies an SSD's parameter bindings
//! (FMPy's `simulate_ssp` reads them but sets only a `parameter_set` passed by hand), so each
//! component is an FMU tailored to the machine: a scene ([`scene_text`], `resources/scene.toml`
//! of the FMU) whose start values are the machine's, whose outputs are the connected and the
//! recorded ones, and whose binary is the catalog's. The same values are also the system's
//! `ParameterBinding` (names `<component>.<variable>`, SSP 1.0, 5.3.3), for the tools that apply
//! it, and for a user who edits it. The root system carries OMSimulator's vendor annotation
//! (`org.openmodelica`: a fixed-step master and its step), without which OMSimulator 3.0 does
//! not import a system; other readers skip it (SSP 1.0 annotations are `processContents="lax"`).

use crate::catalog;
use crate::model::Causality;
use crate::scene::{Scene, Tailored};
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
    /// `modelIdentifier` of the catalog FMU it is tailored from.
    pub fmu: &'static str,
    /// Real parameter values `(variable, value)`; `drive.phi0` is a mechanism's mounting phase on
    /// the shaft (its scene's `[drive]`).
    pub params: Vec<(&'static str, f64)>,
    /// Outputs a designer reads, besides the connected ones.
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
    /// Communication step of the fixed-step master, s (OMSimulator's annotation, the tailored
    /// FMUs' `DefaultExperiment`).
    pub step: f64,
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

/// What a machine's drive shows besides the shaft it turns: the motor's torque (at the motor
/// shaft), speed and power, and the load torque at the main shaft.
const DRIVE_RECORD: &[&str] = &["motor.tau", "motor.w", "motor.P", "shaft.tau_load"];

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
                    record: DRIVE_RECORD.to_vec(),
                },
                Component {
                    name: "table",
                    fmu: "SewingTable",
                    params: vec![],
                    // cam contact force and its Hertz stress, the table's inertia force
                    record: vec![
                        "table.x",
                        "cam.F",
                        "cam.sigma_H",
                        "table.F_inertia",
                        "shaft.tau",
                    ],
                },
                Component {
                    name: "perforators",
                    fmu: "Perforators",
                    params: vec![],
                    // rod force, ramp-roller contact force, piercing load (table.F is connected)
                    record: vec![
                        "perforators.s",
                        "rod.F",
                        "roller.F",
                        "pierce.Q_T",
                        "shaft.tau",
                    ],
                },
            ],
            connections,
            nominal_w: 100.0 * RPM,
            stop: 4.0,
            step: 1e-3,
        }
    };
    // the same machine with the needle drive it replaced: its cams on the main shaft, the lever
    // chain on the frame (the needles pierce while the table rests), its torque a load of its own
    let sewing_legacy = {
        let mut connections = shaft_to("table", 1);
        connections.extend(shaft_to("needles", 2));
        let mut components = sewing.components.clone();
        components[2] = Component {
            name: "needles",
            fmu: "LegacyNeedleDrive",
            params: vec![],
            // rod force, cam-roller force and its Hertz stress, piercing load
            record: vec![
                "perforators.s",
                "rod.F",
                "roller.F",
                "roller.sigma_H",
                "pierce.Q_T",
                "shaft.tau",
            ],
        };
        Machine {
            name: "ThreadSewingMachineLegacy",
            description: "Thread-sewing machine with the needle drive the perforators replace: main-shaft drive, cam-driven sewing table and the legacy three-contour needle drive, cams on the main shaft (papers 000, 002)",
            components,
            connections,
            ..sewing.clone()
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
            // rod force, cutting force, roller-slot contact force of the Geneva pair
            record: vec!["knife.s", "rod.F", "knife.F_cut", "geneva.F", "shaft.tau"],
        };
        Machine {
            name: "ThreeKnifeTrimmer",
            description: "Three-knife trimmer: main-shaft drive and the Geneva knife drives of the two side knives (in phase) and the front knife (half a turn later; assumption) (paper 003)",
            components: vec![
                Component {
                    name: "drive",
                    fmu: "MainShaft",
                    params: trimmer_drive(TRIMMER_FLY_J),
                    record: DRIVE_RECORD.to_vec(),
                },
                knife("side_left", 0.0),
                knife("side_right", 0.0),
                knife("front", PI),
            ],
            connections,
            nominal_w: 30.0 * RPM,
            stop: 12.0,
            step: 2e-3,
        }
    };
    vec![sewing, trimmer, sewing_legacy]
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

/// The connectors of a component in the SSD: its connected inputs and outputs, then the
/// recorded outputs, each once, in that order: `(variable, kind)`.
fn connectors<'a>(m: &'a Machine, c: &Component) -> Vec<(&'a str, &'static str)> {
    let mut out: Vec<(&str, &str)> = Vec::new();
    for ((e1, c1), (e2, c2)) in &m.connections {
        if *e2 == c.name && !out.contains(&(c2, "input")) {
            out.push((c2, "input"));
        }
        if *e1 == c.name && !out.contains(&(c1, "output")) {
            out.push((c1, "output"));
        }
    }
    for r in &c.record {
        if !out.contains(&(r, "output")) {
            out.push((r, "output"));
        }
    }
    out
}

/// The scene a component's FMU is tailored to: the machine's parameter values as start values
/// (`drive.phi0` as the `[drive]` phase), its connected and recorded outputs, the kinetostatic
/// level (the catalog FMU's default) for a mechanism, the machine's experiment.
pub fn scene_text(m: &Machine, c: &Component) -> String {
    let mut x = format!(
        "# {} of the {}: the FMU tailored to the machine (`bindery ssp`)\n",
        c.name, m.name
    );
    x += &format!(
        "name = \"{}_{}\"\nmechanism = \"{}\"\n",
        m.name, c.name, c.fmu
    );
    if c.fmu != "MainShaft" {
        x += "fidelity = \"kinetostatic\"\n";
    }
    let outputs: Vec<String> = connectors(m, c)
        .into_iter()
        .filter(|(_, kind)| *kind == "output")
        .map(|(v, _)| format!("\"{v}\""))
        .collect();
    x += &format!("outputs = [{}]\n", outputs.join(", "));
    let (phase, params): (Vec<_>, Vec<_>) = c.params.iter().partition(|(p, _)| *p == "drive.phi0");
    if !params.is_empty() {
        x += "\n[parameters]\n";
        for (p, v) in params {
            x += &format!("\"{p}\" = {}\n", crate::md::fmt_real(v));
        }
    }
    if let Some((_, phi0)) = phase.first() {
        x += &format!(
            "\n[drive]\nmode = \"input\"\nphi0 = {}\n",
            crate::md::fmt_real(*phi0)
        );
    }
    x += &format!(
        "\n[experiment]\nstop = {}\nstep = {}\n",
        crate::md::fmt_real(m.stop),
        crate::md::fmt_real(m.step)
    );
    x
}

/// The FMU of every component, tailored to the machine ([`scene_text`]), in component order;
/// refuses a machine whose connectors are not all variables of these FMUs, with the right
/// causality.
pub fn tailored(m: &Machine) -> Result<Vec<Tailored>, String> {
    check(m)?;
    let mut out = Vec::new();
    for c in &m.components {
        let text = scene_text(m, c);
        let culprit =
            |e: crate::scene::SceneError| format!("{}: component {}: {e}", m.name, c.name);
        let (_, t) = catalog::tailor(&Scene::parse(&text).map_err(culprit)?).map_err(culprit)?;
        for (name, kind) in connectors(m, c) {
            let want = if kind == "input" {
                Causality::Input
            } else {
                Causality::Output
            };
            if !t
                .variables
                .iter()
                .any(|(_, v)| v.name == name && v.causality == want)
            {
                return Err(format!(
                    "{}: {} has no {kind} {name} (the FMU tailored to {})",
                    m.name, t.identifier, c.name
                ));
            }
        }
        out.push(t);
    }
    Ok(out)
}

/// `SystemStructure.ssd` of a machine (SSP 1.0), its components the FMUs [`tailored`] to it.
pub fn ssd(m: &Machine) -> Result<String, String> {
    let fmus = tailored(m)?;
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
    for (c, t) in m.components.iter().zip(&fmus) {
        x += &format!(
            "      <ssd:Component name=\"{}\" type=\"application/x-fmu-sharedlibrary\" source=\"resources/{}.fmu\">\n        <ssd:Connectors>\n",
            esc(c.name),
            esc(&t.identifier)
        );
        for (name, kind) in connectors(m, c) {
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
    x += "    </ssd:Connections>\n";
    // OMSimulator's vendor annotation: its fixed-step master ("oms-ma") at the machine's step;
    // the tolerances are those it writes itself (the fixed-step master does not use them)
    x += &format!(
        "    <ssd:Annotations>\n      <ssc:Annotation type=\"org.openmodelica\">\n        <oms:Annotations xmlns:oms=\"{OMS_NAMESPACE}\">\n          <oms:SimulationInformation>\n            <oms:FixedStepMaster description=\"oms-ma\" stepSize=\"{}\" absoluteTolerance=\"0.0001\" relativeTolerance=\"0.0001\"/>\n          </oms:SimulationInformation>\n        </oms:Annotations>\n      </ssc:Annotation>\n    </ssd:Annotations>\n",
        crate::md::fmt_real(m.step)
    );
    x += "  </ssd:System>\n";
    // and its result settings (the values it uses when none are given), without which it warns
    // of "wrong/deprecated content" on import
    x += &format!(
        "  <ssd:DefaultExperiment startTime=\"0.0\" stopTime=\"{}\">\n    <ssd:Annotations>\n      <ssc:Annotation type=\"org.openmodelica\">\n        <oms:Annotations xmlns:oms=\"{OMS_NAMESPACE}\">\n          <oms:SimulationInformation resultFile=\"{}_res.mat\" loggingInterval=\"0.0\" bufferSize=\"10\" signalFilter=\".*\"/>\n        </oms:Annotations>\n      </ssc:Annotation>\n    </ssd:Annotations>\n  </ssd:DefaultExperiment>\n",
        crate::md::fmt_real(m.stop),
        esc(m.name)
    );
    x += "</ssd:SystemStructureDescription>\n";
    Ok(x)
}

/// The namespace of OMSimulator's annotations (what OMSimulator writes).
pub const OMS_NAMESPACE: &str =
    "https://raw.githubusercontent.com/OpenModelica/OMSimulator/master/schema/oms.xsd";

/// The `.ssp` archive: `SystemStructure.ssd` and `resources/<id>.fmu`, the FMU [`tailored`] to
/// each component, its binaries the catalog FMU's, read by `binaries(id)` (`id` the catalog
/// modelIdentifier; one library per platform built), with its reference results (FMI-LS-REF:
/// the component's default experiment on its mechanism's cross-check inputs, `inputs(id)`, the
/// text of `<id>_in.csv`), `date` their `generationDateAndTime`. Reproducible: fixed order and
/// timestamps.
pub fn package(
    m: &Machine,
    binaries: &dyn Fn(&str) -> Result<crate::package::Binaries, String>,
    inputs: &dyn Fn(&str) -> Result<String, String>,
    date: &str,
) -> Result<Vec<u8>, String> {
    let ssd = ssd(m)?;
    let mut fmus = Vec::new();
    for c in &m.components {
        let csv = inputs(c.fmu)?;
        let v2 = crate::package::Fmi::V2;
        fmus.push(catalog::scene_fmu_of(
            &scene_text(m, c),
            binaries,
            date,
            v2,
            Some(&csv),
        )?);
    }
    fmus.sort_by(|a, b| a.0.cmp(&b.0));
    let mut zip = ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let opts = SimpleFileOptions::default()
        .compression_method(CompressionMethod::Deflated)
        .last_modified_time(DateTime::default())
        .unix_permissions(0o644);
    zip.start_file("SystemStructure.ssd", opts)
        .map_err(|e| e.to_string())?;
    zip.write_all(ssd.as_bytes()).map_err(|e| e.to_string())?;
    for (id, bytes) in fmus {
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
    fn every_component_is_tailored_to_the_machine() {
        for m in machines() {
            let fmus = tailored(&m).unwrap();
            for (c, t) in m.components.iter().zip(&fmus) {
                assert_eq!(t.identifier, format!("{}_{}_{}", c.fmu, m.name, c.name));
                // the machine's values are the FMU's start values, and it lists them
                for (p, x) in &c.params {
                    let (vr, v) = t
                        .variables
                        .iter()
                        .find(|(_, v)| v.name == *p)
                        .unwrap_or_else(|| panic!("{}: {p} not listed", t.identifier));
                    assert_eq!(t.start[*vr as usize], *x, "{}: {p}", t.identifier);
                    assert_eq!(v.start, Some(*x), "{}: {p}", t.identifier);
                }
                // its outputs are the SSD's output connectors, nothing else
                let mut outs: Vec<&str> = t
                    .variables
                    .iter()
                    .filter(|(_, v)| v.causality == Causality::Output)
                    .map(|(_, v)| v.name)
                    .collect();
                let mut want: Vec<&str> = connectors(&m, c)
                    .into_iter()
                    .filter(|c| c.1 == "output")
                    .map(|c| c.0)
                    .collect();
                outs.sort_unstable();
                want.sort_unstable();
                assert_eq!(outs, want, "{}", t.identifier);
                assert_eq!(t.info.experiment.stop, m.stop);
                assert_eq!(t.info.experiment.step, m.step);
            }
        }
        // the front knife's phase is a parameter of its FMU; the side knives' is not set
        let trimmer = machines().remove(1);
        let fmus = tailored(&trimmer).unwrap();
        let phase = |i: usize| {
            fmus[i]
                .variables
                .iter()
                .find(|(_, v)| v.name == "drive.phi0")
                .and_then(|(_, v)| v.start)
        };
        assert_eq!(trimmer.components[3].name, "front");
        assert_eq!(phase(3), Some(PI));
        assert_eq!(phase(1), None);
        // the drive's: the trimmer's motor, gear and flywheel
        let x = &fmus[0];
        assert!(x.model_description().contains("name=\"fly.J\""));
        assert_eq!(x.start[vr_of(x, "fly.J")], TRIMMER_FLY_J);
        assert_eq!(x.start[vr_of(x, "gear.i")], 50.0);
    }

    fn vr_of(t: &Tailored, name: &str) -> usize {
        t.variables.iter().find(|(_, v)| v.name == name).unwrap().0 as usize
    }

    #[test]
    fn a_connector_the_tailored_fmu_leaves_out_is_refused() {
        // a table whose only output is its position: the tailored FMU has no use for the
        // needles' force table.F_ext, so the connection from the perforators has no end
        let mut m = machines().remove(0);
        m.components.retain(|c| c.name != "drive");
        m.connections = vec![(("perforators", "table.F"), ("table", "table.F_ext"))];
        for c in &mut m.components {
            c.record = if c.name == "table" {
                vec!["table.x"]
            } else {
                vec![]
            };
        }
        let e = tailored(&m).unwrap_err();
        assert!(
            e.contains("SewingTable_ThreadSewingMachine_table has no input table.F_ext"),
            "{e}"
        );
    }

    #[test]
    fn the_ssd_carries_omsimulators_annotations_where_it_reads_them() {
        for m in machines() {
            let x = ssd(&m).unwrap();
            let at = |s: &str| x.find(s).unwrap_or_else(|| panic!("{s} missing"));
            // the root system's master, after its connections (SSP 1.0: last child of System)
            let master = at(&format!(
                "<oms:FixedStepMaster description=\"oms-ma\" stepSize=\"{}\"",
                crate::md::fmt_real(m.step)
            ));
            assert!(at("</ssd:Connections>") < master && master < at("  </ssd:System>"));
            // the result settings, inside the DefaultExperiment
            let results = at(&format!(
                "<oms:SimulationInformation resultFile=\"{}_res.mat\"",
                m.name
            ));
            assert!(at("<ssd:DefaultExperiment ") < results);
            assert!(results < at("</ssd:DefaultExperiment>"));
            assert_eq!(
                x.matches("<ssc:Annotation type=\"org.openmodelica\">")
                    .count(),
                2
            );
        }
    }

    #[test]
    fn archive_layout_and_reproducibility() {
        let m = machines().remove(1);
        let fake = |id: &str| {
            Ok(vec![(
                crate::package::Platform::Linux64,
                id.as_bytes().to_vec(),
            )])
        };
        let inputs = |id: &str| {
            let p = format!("{}/fmus/{id}/{id}_in.csv", env!("CARGO_MANIFEST_DIR"));
            std::fs::read_to_string(&p).map_err(|e| format!("{p}: {e}"))
        };
        let date = crate::md::VERSION_DATE;
        let a = package(&m, &fake, &inputs, date).unwrap();
        assert_eq!(a, package(&m, &fake, &inputs, date).unwrap());
        let names = crate::package::entry_names(&a);
        let mut z = zip::ZipArchive::new(std::io::Cursor::new(a)).unwrap();
        assert_eq!(
            names,
            [
                "SystemStructure.ssd",
                "resources/GenevaKnifeDrive_ThreeKnifeTrimmer_front.fmu",
                "resources/GenevaKnifeDrive_ThreeKnifeTrimmer_side_left.fmu",
                "resources/GenevaKnifeDrive_ThreeKnifeTrimmer_side_right.fmu",
                "resources/MainShaft_ThreeKnifeTrimmer_drive.fmu",
            ]
        );
        // each FMU carries its scene and the catalog binary under its own identifier
        let mut f = z
            .by_name("resources/MainShaft_ThreeKnifeTrimmer_drive.fmu")
            .unwrap();
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(&mut f, &mut bytes).unwrap();
        let mut fmu = zip::ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
        let mut so = Vec::new();
        std::io::Read::read_to_end(
            &mut fmu
                .by_name("binaries/linux64/MainShaft_ThreeKnifeTrimmer_drive.so")
                .unwrap(),
            &mut so,
        )
        .unwrap();
        assert_eq!(so, b"MainShaft");
        let mut scene = String::new();
        std::io::Read::read_to_string(
            &mut fmu.by_name("resources/scene.toml").unwrap(),
            &mut scene,
        )
        .unwrap();
        assert_eq!(scene, scene_text(&m, &m.components[0]));
        // and its reference results, of the FMU itself (FMI-LS-REF)
        let refs = "extra/org.fmi-standard.fmi-ls-ref";
        let out = format!("{refs}/MainShaft_ThreeKnifeTrimmer_drive_out.csv");
        let mut csv = String::new();
        std::io::Read::read_to_string(&mut fmu.by_name(&out).unwrap(), &mut csv).unwrap();
        assert!(csv.lines().count() > 10, "{csv}");
        assert!(fmu.by_name(&format!("{refs}/fmi-ls-manifest.xml")).is_ok());
    }
}
