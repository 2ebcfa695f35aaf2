//! The units variables are declared in, with their SI base-unit exponents and display units
//! (`interface.md`: deg for rad, mm for m, rpm for rad/s, MPa for Pa), as the model description
//! defines them.

/// A unit: its SI base-unit exponents and display units (name, factor: display = factor*value).
pub struct UnitDef {
    pub name: &'static str,
    /// exponents of kg, m, s, rad
    pub base: [i8; 4],
    pub display: &'static [(&'static str, f64)],
}

const DEG_PER_RAD: f64 = 180.0 / std::f64::consts::PI;
const RPM_PER_RAD_S: f64 = 30.0 / std::f64::consts::PI;

/// Every unit the models may use. A variable with a unit not listed here is a programming
/// error caught by the tests of every model.
pub const UNITS: &[UnitDef] = &[
    UnitDef {
        name: "m",
        base: [0, 1, 0, 0],
        display: &[("mm", 1000.0)],
    },
    UnitDef {
        name: "m/s",
        base: [0, 1, -1, 0],
        display: &[("mm/s", 1000.0)],
    },
    UnitDef {
        name: "m/s2",
        base: [0, 1, -2, 0],
        display: &[],
    },
    UnitDef {
        name: "rad",
        base: [0, 0, 0, 1],
        display: &[("deg", DEG_PER_RAD)],
    },
    UnitDef {
        name: "rad/s",
        base: [0, 0, -1, 1],
        display: &[("rpm", RPM_PER_RAD_S), ("deg/s", DEG_PER_RAD)],
    },
    UnitDef {
        name: "rad/s2",
        base: [0, 0, -2, 1],
        display: &[("deg/s2", DEG_PER_RAD)],
    },
    UnitDef {
        name: "s",
        base: [0, 0, 1, 0],
        display: &[],
    },
    UnitDef {
        name: "kg",
        base: [1, 0, 0, 0],
        display: &[],
    },
    UnitDef {
        name: "kg.m2",
        base: [1, 2, 0, 0],
        display: &[],
    },
    UnitDef {
        name: "N",
        base: [1, 1, -2, 0],
        display: &[("kN", 1e-3)],
    },
    UnitDef {
        name: "N/m",
        base: [1, 0, -2, 0],
        display: &[],
    },
    UnitDef {
        name: "N.s/m",
        base: [1, 0, -1, 0],
        display: &[],
    },
    UnitDef {
        name: "N.m",
        base: [1, 2, -2, 0],
        display: &[],
    },
    UnitDef {
        name: "N.m/rad",
        base: [1, 2, -2, -1],
        display: &[],
    },
    UnitDef {
        name: "N.m.s/rad",
        base: [1, 2, -1, -1],
        display: &[],
    },
    UnitDef {
        name: "J",
        base: [1, 2, -2, 0],
        display: &[],
    },
    UnitDef {
        name: "W",
        base: [1, 2, -3, 0],
        display: &[],
    },
    UnitDef {
        name: "Pa",
        base: [1, -1, -2, 0],
        display: &[("MPa", 1e-6)],
    },
];

pub fn unit_def(name: &str) -> Option<&'static UnitDef> {
    UNITS.iter().find(|u| u.name == name)
}

/// The factor of a display unit of `unit` (display value = factor × SI value), as declared in
/// the model description: `display_factor("rad/s", "rpm")` = 30/π.
pub fn display_factor(unit: &str, display: &str) -> Option<f64> {
    unit_def(unit)?
        .display
        .iter()
        .find(|(n, _)| *n == display)
        .map(|(_, f)| *f)
}
