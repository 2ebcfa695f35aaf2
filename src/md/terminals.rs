//! FMI 3.0's `terminalsAndIcons/terminalsAndIcons.xml` (quick-xml and serde): the FMU's icon
//! area and its terminals ([`crate::model::shaft::Terminal`], declared with the shaft
//! connector and by the drive), those whose variables the FMU lists. Elements follow
//! `fmi3TerminalsAndIcons.xsd`.

use crate::model::Var;
use crate::model::shaft::{TERMINAL_KIND, Terminal};
use serde::Serialize;

#[derive(Serialize)]
#[serde(rename = "fmiTerminalsAndIcons")]
struct Doc {
    #[serde(rename = "@fmiVersion")]
    fmi_version: &'static str,
    #[serde(rename = "GraphicalRepresentation")]
    graphics: Graphics,
    #[serde(rename = "Terminals", skip_serializing_if = "Terminals::is_empty")]
    terminals: Terminals,
}

#[derive(Serialize)]
struct Graphics {
    #[serde(rename = "CoordinateSystem")]
    coordinates: Coordinates,
    #[serde(rename = "Icon")]
    icon: Extent,
}

#[derive(Serialize)]
struct Coordinates {
    #[serde(flatten)]
    extent: Extent,
    #[serde(rename = "@suggestedScalingFactorTo_mm")]
    to_mm: f64,
}

#[derive(Clone, Copy, Serialize)]
struct Extent {
    #[serde(rename = "@x1")]
    x1: f64,
    #[serde(rename = "@y1")]
    y1: f64,
    #[serde(rename = "@x2")]
    x2: f64,
    #[serde(rename = "@y2")]
    y2: f64,
}

/// The coordinate system and the icon: 200 × 200 units around the origin.
const SQUARE: Extent = Extent {
    x1: -100.0,
    y1: -100.0,
    x2: 100.0,
    y2: 100.0,
};

#[derive(Serialize)]
struct Terminals {
    #[serde(rename = "Terminal")]
    terminal: Vec<TerminalXml>,
}

impl Terminals {
    fn is_empty(&self) -> bool {
        self.terminal.is_empty()
    }
}

#[derive(Serialize)]
struct TerminalXml {
    #[serde(rename = "@name")]
    name: &'static str,
    #[serde(rename = "@matchingRule")]
    matching_rule: &'static str,
    #[serde(rename = "@terminalKind")]
    kind: &'static str,
    #[serde(rename = "@description")]
    description: String,
    #[serde(rename = "TerminalMemberVariable")]
    members: Vec<Member>,
}

#[derive(Serialize)]
struct Member {
    #[serde(rename = "@variableName")]
    variable: &'static str,
    #[serde(rename = "@memberName")]
    member: &'static str,
    #[serde(rename = "@variableKind")]
    kind: &'static str,
}

/// `terminalsAndIcons.xml` of an FMU listing `vars`, with the `terminals` whose variables it
/// all lists: the members are causal signals (inputs one way, outputs the other), connected
/// member by member (`plug`); the icon fills the coordinate system of 200 × 200 units (20 mm).
pub fn terminals_and_icons(terminals: &[Terminal], vars: &[(u32, &Var)]) -> String {
    let listed = |name: &str| vars.iter().find(|(_, v)| v.name == name).map(|(_, v)| *v);
    let terminal = terminals
        .iter()
        .filter(|t| t.members.iter().all(|(_, v)| listed(v).is_some()))
        .map(|t| TerminalXml {
            name: t.name,
            matching_rule: "plug",
            kind: TERMINAL_KIND,
            description: t.description.to_string(),
            members: (t.members.iter())
                .map(|&(member, variable)| Member {
                    variable,
                    member,
                    kind: "signal",
                })
                .collect(),
        })
        .collect();
    let doc = Doc {
        fmi_version: "3.0",
        graphics: Graphics {
            coordinates: Coordinates {
                extent: SQUARE,
                to_mm: 0.1,
            },
            icon: SQUARE,
        },
        terminals: Terminals { terminal },
    };
    let mut body = String::new();
    let mut ser = quick_xml::se::Serializer::new(&mut body);
    ser.indent(' ', 2);
    doc.serialize(ser)
        .expect("terminalsAndIcons.xml serializes");
    format!("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n{body}\n")
}

/// `terminalsAndIcons.xml` of model `M`'s full FMU.
pub fn of<M: crate::model::Model>() -> String {
    terminals_and_icons(M::TERMINALS, &crate::model::variables_of::<M>())
}
