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

/// One row of [`UNITS`]: name, exponents of kg, m, s, rad, display units.
const fn unit(
    name: &'static str,
    base: [i8; 4],
    display: &'static [(&'static str, f64)],
) -> UnitDef {
    UnitDef {
        name,
        base,
        display,
    }
}

const DEG_PER_RAD: f64 = 180.0 / std::f64::consts::PI;
const RPM_PER_RAD_S: f64 = 30.0 / std::f64::consts::PI;

/// Every unit the models may use. A variable with a unit not listed here is a programming
/// error caught by the tests of every model.
pub const UNITS: &[UnitDef] = &[
    unit("m", [0, 1, 0, 0], &[("mm", 1000.0)]),
    unit("m/s", [0, 1, -1, 0], &[("mm/s", 1000.0)]),
    unit("m/s2", [0, 1, -2, 0], &[]),
    unit("rad", [0, 0, 0, 1], &[("deg", DEG_PER_RAD)]),
    unit(
        "rad/s",
        [0, 0, -1, 1],
        &[("rpm", RPM_PER_RAD_S), ("deg/s", DEG_PER_RAD)],
    ),
    unit("rad/s2", [0, 0, -2, 1], &[("deg/s2", DEG_PER_RAD)]),
    unit("s", [0, 0, 1, 0], &[]),
    unit("kg", [1, 0, 0, 0], &[]),
    unit("kg.m2", [1, 2, 0, 0], &[]),
    unit("N", [1, 1, -2, 0], &[("kN", 1e-3)]),
    unit("N/m", [1, 0, -2, 0], &[]),
    unit("N.s/m", [1, 0, -1, 0], &[]),
    unit("N.m", [1, 2, -2, 0], &[]),
    unit("N.m/rad", [1, 2, -2, -1], &[]),
    unit("N.m.s/rad", [1, 2, -1, -1], &[]),
    unit("J", [1, 2, -2, 0], &[]),
    unit("W", [1, 2, -3, 0], &[]),
    unit("Pa", [1, -1, -2, 0], &[("MPa", 1e-6)]),
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

/// The unit a quantity in `unit` is shown in (its default display unit: mm for m, deg for rad,
/// rpm for rad/s, MPa for Pa) and the factor from `unit` to it; `unit` itself and 1 if it has none.
pub fn display_of(unit: &'static str) -> (&'static str, f64) {
    super::default_display_unit(unit)
        .and_then(|d| display_factor(unit, d).map(|f| (d, f)))
        .unwrap_or((unit, 1.0))
}
