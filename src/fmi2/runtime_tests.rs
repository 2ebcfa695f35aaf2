//! Tests of `runtime.rs`.

use super::*;

#[test]
fn snapshot_bytes_round_trip_and_refuse_garbage() {
    let s = Snapshot {
        state: State::StepComplete,
        time: 0.1 + 0.2,
        start_time: 0.0,
        stop_time: Some(4.0),
        values: vec![1.0, -0.0, f64::MIN_POSITIVE, 3.5],
        model_state: vec![2.0],
        input_derivatives: vec![(0, 1, 3.25), (1, 1, -0.5)],
        continuous_time: true,
        inputs_at: 0.25,
    };
    let b = s.to_bytes(42);
    let back = Snapshot::from_bytes(&b, 42, 4).unwrap();
    assert_eq!(back.to_bytes(42), b);
    assert_eq!(back.values[1].to_bits(), (-0.0f64).to_bits());
    assert!(
        Snapshot::from_bytes(&b, 43, 4)
            .unwrap_err()
            .contains("GUID")
    );
    assert!(
        Snapshot::from_bytes(&b[..b.len() - 1], 42, 4)
            .unwrap_err()
            .contains("truncated")
    );
    assert!(Snapshot::from_bytes(&b, 42, 5).is_err());
    let mut longer = b.clone();
    longer.push(0);
    assert!(
        Snapshot::from_bytes(&longer, 42, 4)
            .unwrap_err()
            .contains("trailing")
    );
}

// ---- the runtime over a tiny model, called as a host would, without a cdylib ----------

use crate::model::{Experiment, Outcome, ParamError};
use std::sync::Mutex;

crate::model_variables! {
    enum TV (nominal_rpm = 60.0) {
        boom = Var::bool_parameter("test.boom", false, "panic in evaluate"),
        fail = Var::bool_parameter("test.fail", false, "do_step cannot complete"),
        y = Var::output("test.y", "rad", "shaft angle").depends(crate::model::shaft::ON_PHI),
    }
}

struct Tiny;
impl Model for Tiny {
    type Var = TV;
    const IDENTIFIER: &'static str = "Tiny";
    const DESCRIPTION: &'static str = "test model";
    const EXPERIMENT: Experiment = Experiment::until(1.0, 0.1);
    fn prepare(_: &Values<TV>) -> Result<Self, ParamError> {
        Ok(Tiny)
    }
    fn evaluate(&mut self, v: &mut Values<TV>, time: f64, _: &mut dyn Log) {
        if v.flag(TV::boom) {
            panic!("model failure at t = {time}");
        }
        v[TV::y] = crate::model::shaft::state(v, time).phi;
    }
}

impl crate::model::Dynamics<TV> for Tiny {
    fn do_step(&mut self, v: &mut Values<TV>, time: f64, _: f64, _: &mut dyn Log) -> Outcome {
        if v.flag(TV::fail) {
            return Err(format!("solver gave up at t = {time}"));
        }
        Ok(())
    }
}

static LOG: Mutex<Vec<(Status, String)>> = Mutex::new(Vec::new());

/// The tests' variadic C logger (`tests/c_host/logger.c`, as the integration tests use it).
#[path = "../../tests/common/c_logger.rs"]
mod c_logger;

fn record(_: usize, status: Status, _: Option<&str>, _: Option<&str>, text: Option<&str>) {
    LOG.lock()
        .unwrap()
        .push((status, text.unwrap_or_default().to_string()));
}

fn tiny() -> Component {
    let f = CallbackFunctions {
        logger: c_logger::logger(record),
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: std::ptr::null_mut(),
    };
    let guid = CString::new(md::describe::<Tiny>().1).unwrap();
    let c = unsafe {
        instantiate::<Tiny>(
            c"tiny".as_ptr(),
            FmuType::CoSimulation,
            guid.as_ptr(),
            std::ptr::null(),
            &f,
            FALSE,
            FALSE,
        )
    };
    assert!(!c.is_null());
    c
}

/// Enters and exits initialization mode, both asserted fmi2OK.
#[track_caller]
unsafe fn initialize(c: Component) {
    unsafe {
        let enter = entry::<Tiny, _>(c, Call::EnterInitializationMode, |i| {
            i.enter_initialization_mode()
        });
        assert_eq!(enter, Status::Ok);
        let exit = entry::<Tiny, _>(c, Call::ExitInitializationMode, |i| {
            i.exit_initialization_mode()
        });
        assert_eq!(exit, Status::Ok);
    }
}

/// The instance behind a component of [`tiny`] (the back door a model bug would take).
unsafe fn instance<'a>(c: Component) -> &'a mut Instance<Tiny> {
    unsafe { &mut *(c as *mut Instance<Tiny>) }
}

#[test]
fn a_panic_in_the_model_is_caught_at_the_boundary() {
    let c = tiny();
    unsafe {
        initialize(c);
        let mut y = 0.0;
        let vr = [TV::y.vr()];
        assert_eq!(
            set_real::<Tiny>(c, [TV::shaft_phi.vr()].as_ptr(), 1, &0.5),
            Status::Ok
        );
        assert_eq!(get_real::<Tiny>(c, vr.as_ptr(), 1, &mut y), Status::Ok);
        assert_eq!(y, 0.5);
        // make the model panic: set the flag through the back door, as a model bug would
        let inst = instance(c);
        inst.values.set_flag(TV::boom, true);
        inst.dirty = true;
        assert_eq!(get_real::<Tiny>(c, vr.as_ptr(), 1, &mut y), Status::Error);
        assert_eq!(inst.state, State::Error);
        let last = LOG.lock().unwrap().last().cloned().unwrap();
        assert!(
            last.1.contains("panic caught") && last.1.contains("model failure at t = 0"),
            "{last:?}"
        );
        // in the error state only what FMI 2.0 allows works; reset brings it back
        assert_eq!(do_step::<Tiny>(c, 0.0, 0.1, FALSE), Status::Error);
        assert_eq!(entry::<Tiny, _>(c, Call::Reset, |i| i.reset()), Status::Ok);
        initialize(c);
        assert_eq!(get_real::<Tiny>(c, vr.as_ptr(), 1, &mut y), Status::Ok);
        assert_eq!(y, 0.0, "reset restored the start values");
        free_instance::<Tiny>(c);
    }
}

#[test]
fn a_discarded_step_keeps_the_time_and_the_instance_restorable() {
    let c = tiny();
    unsafe {
        initialize(c);
        assert_eq!(do_step::<Tiny>(c, 0.0, 0.1, TRUE), Status::Ok);
        let mut saved: FMUstate = std::ptr::null_mut();
        let status = entry::<Tiny, _>(c, Call::GetFMUstate, |i| i.get_fmu_state(&mut saved));
        assert_eq!(status, Status::Ok);
        // the model cannot complete the next step (as a solver that gives up)
        let inst = instance(c);
        inst.values.set_flag(TV::fail, true);
        assert_eq!(do_step::<Tiny>(c, 0.1, 0.1, TRUE), Status::Discard);
        assert_eq!(inst.state, State::StepFailed);
        assert_eq!(inst.time, 0.1, "a discarded step does not advance the time");
        let last = LOG.lock().unwrap().last().cloned().unwrap();
        assert!(
            last.0 == Status::Discard && last.1.contains("solver gave up at t = 0.1"),
            "{last:?}"
        );
        let mut t = 0.0;
        assert_eq!(get_real_status::<Tiny>(c, 2, &mut t), Status::Ok);
        assert_eq!(t, 0.1, "fmi2LastSuccessfulTime");
        let mut y = 0.0;
        let vr = [TV::y.vr()];
        assert_eq!(get_real::<Tiny>(c, vr.as_ptr(), 1, &mut y), Status::Ok);
        assert_eq!(do_step::<Tiny>(c, 0.1, 0.05, TRUE), Status::Error);
        // restorable: the saved state is StepComplete again, and the run goes on
        let status = entry::<Tiny, _>(c, Call::SetFMUstate, |i| i.set_fmu_state(saved));
        assert_eq!(status, Status::Ok);
        assert_eq!(inst.state, State::StepComplete);
        assert!(!inst.values.flag(TV::fail));
        assert_eq!(do_step::<Tiny>(c, 0.1, 0.05, TRUE), Status::Ok);
        let status = entry::<Tiny, _>(c, Call::FreeFMUstate, |i| i.free_fmu_state(&mut saved));
        assert_eq!(status, Status::Ok);
        free_instance::<Tiny>(c);
    }
}

#[test]
fn debug_logging_categories() {
    let c = tiny();
    unsafe {
        let cats = [c"logEvents".as_ptr()];
        assert_eq!(
            set_debug_logging::<Tiny>(c, TRUE, 1, cats.as_ptr()),
            Status::Ok
        );
        let inst = instance(c);
        assert!(inst.logger.enabled(Status::Ok, "logEvents"));
        assert!(!inst.logger.enabled(Status::Ok, "logAll"));
        assert!(
            inst.logger.enabled(Status::Error, "logStatusError"),
            "errors always reach the host"
        );
        let bad = [c"noSuchCategory".as_ptr()];
        assert_eq!(
            set_debug_logging::<Tiny>(c, TRUE, 1, bad.as_ptr()),
            Status::Error
        );
        assert_eq!(
            set_debug_logging::<Tiny>(c, FALSE, 0, std::ptr::null()),
            Status::Ok
        );
        assert!(!inst.logger.enabled(Status::Ok, "logEvents"));
        free_instance::<Tiny>(c);
    }
}

/// Model Exchange's rule is in the mask the fast path of `fmi2Set*` tests: in continuous-time
/// mode only inputs; a tunable parameter (settable after initialization) is not.
#[test]
fn continuous_time_mode_is_a_bit_of_the_access_mask() {
    use crate::model::{Var, Variability};
    let mut tunable = Var::parameter("test.k", 1.0, "N/m", "a tunable parameter");
    tunable.variability = Variability::Tunable;
    let a = access::of(&tunable);
    assert!(a & access::SET_RUNNING != 0);
    assert!(a & access::SET_CONTINUOUS_TIME == 0);
    let input = &TV::table()[crate::model::shaft::PHI as usize];
    let a = access::of(input);
    assert!(a & access::SET_RUNNING != 0 && a & access::SET_CONTINUOUS_TIME != 0);
    let fixed = &TV::table()[TV::boom as usize];
    assert_eq!(
        access::of(fixed) & (access::SET_RUNNING | access::SET_CONTINUOUS_TIME),
        0
    );
}

/// The tests' logger is a real C-variadic function: it formats the message with its arguments
/// as a host's printf does.
#[test]
fn the_tests_logger_formats_its_arguments() {
    let log = c_logger::logger(record).expect("the C logger");
    // SAFETY: a printf format and arguments of its conversions.
    unsafe {
        log(
            std::ptr::null_mut(),
            c"tiny".as_ptr(),
            Status::Warning,
            c"logAll".as_ptr(),
            c"%d%% of %s at %.2f".as_ptr(),
            42 as std::ffi::c_int,
            c"the turn".as_ptr(),
            0.125f64,
        )
    };
    let logged = LOG.lock().unwrap().clone();
    assert!(
        logged.contains(&(Status::Warning, "42% of the turn at 0.12".to_string())),
        "{logged:?}"
    );
}

#[test]
fn a_model_without_partials_refuses_directional_derivatives_saying_so() {
    // every FMU of the catalog offers them; a model that does not (`Model::PARTIALS` false,
    // as `Tiny`) declares `providesDirectionalDerivative="false"` and refuses the call
    let c = tiny();
    assert!(!md::ModelInfo::of::<Tiny>().partials);
    assert!(
        md::describe::<Tiny>()
            .0
            .contains("providesDirectionalDerivative=\"false\"")
    );
    unsafe {
        initialize(c);
        let (unknown, known) = ([TV::y.vr()], [TV::shaft_phi.vr()]);
        let mut out = [0.0];
        let status = entry::<Tiny, _>(c, Call::GetDirectionalDerivative, |i| {
            i.directional_derivative(
                unknown.as_ptr(),
                1,
                known.as_ptr(),
                1,
                [1.0].as_ptr(),
                out.as_mut_ptr(),
            )
        });
        assert_eq!(status, Status::Error);
        let last = LOG.lock().unwrap().last().cloned().unwrap();
        assert!(
            last.1
                .contains("not supported: providesDirectionalDerivative is false"),
            "{last:?}"
        );
        // and the instance goes on
        let mut y = f64::NAN;
        assert_eq!(get_real::<Tiny>(c, unknown.as_ptr(), 1, &mut y), Status::Ok);
        free_instance::<Tiny>(c);
    }
}
