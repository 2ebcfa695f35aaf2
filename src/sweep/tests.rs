//! The sweep file's checks, the design's runs and the runner's numbers against what the model
//! gives by itself.

use super::file::{Length, StepSize, parse};
use super::sample::Axis;
use crate::mechanisms::main_shaft::MainShaft;
use crate::mechanisms::perforators::Perforators;

const GOOD: &str = r#"
model = "Perforators"
fidelity = "kinetostatic"
[fixed]
"roller.r" = 0.012
[swept]
"spring.M0" = { from = 2.0, to = 8.0, points = 4 }
"speed" = { values = [100, 130.0] }
[experiment]
turns = 1
steps_per_turn = 7200
[metrics]
F_min = { output = "roller.F", stat = "min" }
stroke = { output = "perforators.s", stat = "ptp", over = "run" }
"#;

fn err_of(text: &str) -> String {
    parse::<Perforators>(text, None)
        .expect_err("refused")
        .to_string()
}

#[test]
fn a_good_file_gives_the_design_in_the_order_written() {
    let p = parse::<Perforators>(GOOD, None).expect("parses");
    assert_eq!(p.runs(), 8);
    assert_eq!(p.columns(), ["spring.M0", "speed", "F_min", "stroke"]);
    assert_eq!(p.design.axes[0], Axis::Values(vec![2.0, 4.0, 6.0, 8.0]));
    assert_eq!(
        (p.length, p.step),
        (Length::Turns(1.0), StepSize::PerTurn(7200))
    );
    assert_eq!(p.design.point(3), vec![4.0, 130.0]);
    assert_eq!(p.swept[1].unit, "rpm");
    assert_eq!(p.metrics[0].unit, "N");
}

#[test]
fn a_bad_file_is_refused_with_the_key_its_line_and_the_valid_choices() {
    let line = |needle: &str, text: &str| {
        text.lines()
            .position(|l| l.contains(needle))
            .expect("in the text")
            + 1
    };
    let cases: Vec<(String, &str, Vec<&str>)> = vec![
        (
            GOOD.replace("[fixed]", "[fixd]"),
            "[fixd]",
            vec!["unknown key", "fixed"],
        ),
        (
            GOOD.replace("\"spring.M0\" = {", "\"spring.M1\" = {"),
            "spring.M1",
            vec!["no parameter \"spring.M1\"", "spring.M0"],
        ),
        (
            GOOD.replace("stat = \"min\"", "stat = \"median\""),
            "median",
            vec!["unknown stat", "rms"],
        ),
        (
            GOOD.replace("\"roller.F\"", "\"elastic.F\""),
            "elastic.F",
            vec!["not computed at the kinetostatic level", "elastodynamic"],
        ),
        (
            GOOD.replace("\"roller.r\" = 0.012", "\"drive.n\" = 10.0"),
            "drive.n",
            vec!["`speed`"],
        ),
        (
            GOOD.replace("\"roller.r\" = 0.012", "\"roller.r\" = -1.0"),
            "[fixed]",
            vec!["roller.r"],
        ),
        (
            GOOD.replace("points = 4 }", "points = 4, to2 = 1 }"),
            "spring.M0",
            vec!["to2"],
        ),
        (
            GOOD.replace(
                "{ from = 2.0, to = 8.0, points = 4 }",
                "{ normal = [6.0, 0.5] }",
            ),
            "[swept]",
            vec!["[sampling]", "samples"],
        ),
        (
            GOOD.replace("turns = 1", "turns = 1\nstop = 2.0"),
            "stop = 2.0",
            vec!["not both"],
        ),
        (
            GOOD.replace("over = \"run\"", "over = \"turn\""),
            "turn\"",
            vec!["last_turn, run"],
        ),
        (
            GOOD.replace(
                "model = \"Perforators\"\n",
                "model = \"Perforators\"\nmodel = \"X\"\n",
            ),
            "model = \"X\"",
            vec!["duplicate"],
        ),
    ];
    for (text, at, words) in cases {
        let e = err_of(&text);
        assert!(
            e.starts_with(&format!("line {}:", line(at, &text))),
            "{at}: {e}"
        );
        for w in words {
            assert!(e.contains(w), "{at}: {e:?} does not say {w:?}");
        }
    }
    // a sampling block without a random parameter, a MainShaft sweep in turns
    let e = err_of(&format!("{GOOD}[sampling]\nsamples = 10\n"));
    assert!(e.contains("no swept parameter is random"), "{e}");
    let e = parse::<MainShaft>(
        "model = \"MainShaft\"\n[experiment]\nturns = 2\nstep = 1e-3\n[metrics]\nw = { output = \"shaft.w\", stat = \"max\" }\n",
        None,
    )
    .expect_err("refused")
    .to_string();
    assert!(
        e.contains("drives itself") && e.starts_with("line 3:"),
        "{e}"
    );
}

#[test]
fn a_run_the_model_refuses_is_a_row_with_the_reason_and_the_others_run() {
    let text = GOOD.replace(
        "{ from = 2.0, to = 8.0, points = 4 }",
        "{ values = [-1.0, 6.0] }",
    );
    let p = parse::<Perforators>(&text, None).expect("parses: bounds are the model's, per run");
    let bad = p.run(0);
    assert!(
        bad.metrics.is_empty() && bad.error.contains("spring.M0"),
        "{bad:?}"
    );
    let good = p.run(2);
    assert_eq!(good.params, vec![6.0, 100.0]);
    assert_eq!(good.metrics.len(), 2);
    assert!(good.error.is_empty());
}

#[test]
fn the_runner_reproduces_the_model_on_its_own() {
    let p = parse::<Perforators>(GOOD, None).expect("parses");
    for k in 0..p.runs() {
        let r = p.run(k);
        // the stroke is the synthesis' λS·unit = 30 mm at every speed and spring
        assert!(
            (r.metrics[1] - 0.030).abs() < 1e-9,
            "run {k}: {}",
            r.metrics[1]
        );
        // the smallest contact force over the turn: the lift-off search's own function, at the
        // same 7200 angles (drive.phi0 = 0: the samples are the turn's angles 2πi/7200)
        let mut v = crate::model::Values::<<Perforators as crate::model::Model>::Var>::start();
        let table = <<Perforators as crate::model::Model>::Var as crate::model::VarSet>::table();
        let at = |name: &str| {
            table
                .iter()
                .position(|x| x.name == name)
                .expect("a variable")
        };
        v.raw_mut()[at("roller.r")] = 0.012;
        v.raw_mut()[at("spring.M0")] = r.params[0];
        let m = <Perforators as crate::model::Model>::prepare(&v).expect("prepared");
        let (f_min, _) = m
            .drive()
            .min_contact_force(r.params[1] * std::f64::consts::PI / 30.0, 7200);
        assert!(
            (r.metrics[0] - f_min).abs() <= 1e-9 * f_min.abs().max(1.0),
            "run {k}: sweep {} vs the model's {f_min}",
            r.metrics[0]
        );
    }
}

#[test]
fn a_sweep_from_a_scene_takes_its_level_parameters_and_speed() {
    let scene = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/perforators-liftoff-dynamics.toml"
    ))
    .expect("the example scene");
    let text = r#"
scene = "../scenes/perforators-liftoff-dynamics.toml"
[fixed]
"spring.kt" = 25.0
[swept]
"spring.M0" = { values = [6.0, 9.0] }
[experiment]
turns = 1
[metrics]
bounces = { output = "contact.liftoffs", stat = "increase" }
"#;
    assert_eq!(
        super::file::model_of(text).expect("names its scene"),
        (
            None,
            Some("../scenes/perforators-liftoff-dynamics.toml".to_string())
        )
    );
    let p = parse::<Perforators>(text, Some(&scene)).expect("parses");
    assert_eq!(
        p.fidelity,
        Some(crate::model::shaft::Fidelity::Elastodynamic)
    );
    assert_eq!(p.speed, Some(130.0), "the scene's constant speed");
    assert_eq!(p.step, StepSize::PerTurn(720));
    assert_eq!(p.runs(), 2);
    // the scene names its file: without its text the sweep is refused
    let e = parse::<Perforators>(text, None)
        .expect_err("refused")
        .to_string();
    assert!(e.contains("scene"), "{e}");
    // both a model and a scene: refused
    let e = super::file::model_of(&format!("model = \"Perforators\"\n{text}"))
        .expect_err("refused")
        .to_string();
    assert!(e.contains("not `model` and `scene`"), "{e}");
}

#[test]
fn a_machine_sweep_sets_component_parameters_and_measures_the_machine() {
    let machine = || {
        crate::ssp::machines()
            .into_iter()
            .find(|m| m.name == "ThreadSewingMachine")
            .expect("the sewing machine")
    };
    let text = r#"
machine = "ThreadSewingMachine"
[fixed]
"drive.gear.i" = 12.0
[swept]
"drive.fly.J" = { values = [0.05, 0.5] }
[experiment]
stop = 1.5
[metrics]
delta = { quantity = "delta", turns = 2 }
tau = { quantity = "tau_peak" }
"#;
    assert_eq!(
        super::file::target_of(text).expect("names a machine"),
        super::file::Target::Machine("ThreadSewingMachine".into())
    );
    let p = crate::machines::sweep::parse(text, machine()).expect("parses");
    assert_eq!(p.columns(), ["drive.fly.J", "delta", "tau"]);
    assert_eq!(p.metrics[1].unit, "N.m");
    let rows: Vec<_> = (0..p.runs()).map(|k| p.run(k)).collect();
    // the same numbers as the machine simulated directly
    for r in &rows {
        assert!(r.error.is_empty(), "{}", r.error);
        let tr = crate::machines::simulate(
            &machine(),
            &[("drive", "gear.i", 12.0), ("drive", "fly.J", r.params[0])],
            1.5,
            machine().step,
        )
        .expect("runs");
        assert_eq!(
            r.metrics[0].to_bits(),
            crate::machines::steady(&tr, 2.0).delta.to_bits()
        );
        assert_eq!(
            r.metrics[1].to_bits(),
            crate::machines::steady(&tr, 1.0).tau_peak.to_bits()
        );
    }
    // a larger flywheel smooths the speed
    assert!(rows[1].metrics[0] < rows[0].metrics[0], "{rows:?}");
    // names are checked against the machine's components and their parameters
    for (bad, words) in [
        (
            "\"motor.x\" = { values",
            vec!["component.variable", "drive, table, perforators"],
        ),
        (
            "\"drive.fly.K\" = { values",
            vec!["no parameter \"fly.K\"", "fly.J"],
        ),
    ] {
        let t = text.replace("\"drive.fly.J\" = { values", bad);
        let e = crate::machines::sweep::parse(&t, machine())
            .expect_err("refused")
            .to_string();
        let line = t
            .lines()
            .position(|l| l.contains("{ values"))
            .expect("there")
            + 1;
        assert!(e.starts_with(&format!("line {line}:")), "{e}");
        for w in words {
            assert!(e.contains(w), "{e:?} does not say {w:?}");
        }
    }
    let e = crate::machines::sweep::parse(
        &text.replace("\"delta\", turns", "\"sigma\", turns"),
        machine(),
    )
    .expect_err("refused")
    .to_string();
    assert!(
        e.contains("unknown quantity") && e.contains("tau_rms"),
        "{e}"
    );
}
