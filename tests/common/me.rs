//! Model Exchange calls of the test host: the functions of FMI 2.0's Model Exchange table on a
//! [`Slave`] instantiated as Model Exchange, each returning its status (and its array).

use super::Slave;
use bindery_fmu::fmi2::runtime::me::EventInfo;
use bindery_fmu::fmi2::types::*;

type GetArr = unsafe extern "C" fn(Component, *mut Real, usize) -> Status;
type SetArr = unsafe extern "C" fn(Component, *const Real, usize) -> Status;
type SetTime = unsafe extern "C" fn(Component, Real) -> Status;
type Completed = unsafe extern "C" fn(Component, Boolean, *mut Boolean, *mut Boolean) -> Status;
type NewDiscrete = unsafe extern "C" fn(Component, *mut EventInfo) -> Status;

impl Slave<'_> {
    /// `fmi2GetContinuousStates`, `fmi2GetDerivatives`, `fmi2GetEventIndicators`,
    /// `fmi2GetNominalsOfContinuousStates` (by name) into `n` reals.
    pub fn get_array(&self, name: &str, n: usize) -> (Status, Vec<f64>) {
        let mut x = vec![f64::NAN; n];
        // SAFETY: the FMI function with an array of n reals.
        let st = unsafe { self.fmu.sym::<GetArr>(name)(self.c, x.as_mut_ptr(), n) };
        (st, x)
    }

    pub fn set_states(&self, x: &[f64]) -> Status {
        // SAFETY: the FMI function with an array of x.len() reals.
        unsafe { self.fmu.sym::<SetArr>("fmi2SetContinuousStates")(self.c, x.as_ptr(), x.len()) }
    }

    pub fn set_time(&self, t: f64) -> Status {
        // SAFETY: the FMI function.
        unsafe { self.fmu.sym::<SetTime>("fmi2SetTime")(self.c, t) }
    }

    /// `fmi2CompletedIntegratorStep`: the status, and whether the FMU asks for an event.
    pub fn completed_step(&self) -> (Status, bool) {
        let (mut enter, mut terminate) = (FALSE, FALSE);
        // SAFETY: the FMI function with two valid result pointers.
        let st = unsafe {
            self.fmu.sym::<Completed>("fmi2CompletedIntegratorStep")(
                self.c,
                TRUE,
                &mut enter,
                &mut terminate,
            )
        };
        assert_eq!(terminate, FALSE);
        (st, enter == TRUE)
    }

    /// In event mode: `fmi2NewDiscreteStates` until none are needed, each asserted fmi2OK.
    pub fn event_iteration(&self) {
        for _ in 0..10 {
            let mut info = EventInfo::default();
            // SAFETY: the FMI function with a valid fmi2EventInfo.
            let st =
                unsafe { self.fmu.sym::<NewDiscrete>("fmi2NewDiscreteStates")(self.c, &mut info) };
            self.ok(st, "fmi2NewDiscreteStates");
            assert_eq!(info.terminate_simulation, FALSE);
            if info.new_discrete_states_needed == FALSE {
                return;
            }
        }
        panic!("the event iteration does not end: {:?}", self.logs());
    }

    /// An event: `fmi2EnterEventMode`, the event iteration, `fmi2EnterContinuousTimeMode`.
    pub fn event(&self) {
        self.ok(self.call0("fmi2EnterEventMode"), "fmi2EnterEventMode");
        self.event_iteration();
        self.ok(
            self.call0("fmi2EnterContinuousTimeMode"),
            "fmi2EnterContinuousTimeMode",
        );
    }

    /// A Model Exchange instance after `set` (the variables before initialization),
    /// `fmi2SetupExperiment` from 0, initialization and the initial event iteration: in
    /// continuous-time mode.
    pub fn me_start(&self, set: impl Fn(&Slave)) {
        set(self);
        self.ok(self.setup(0.0, None), "fmi2SetupExperiment");
        self.ok(
            self.call0("fmi2EnterInitializationMode"),
            "fmi2EnterInitializationMode",
        );
        self.ok(
            self.call0("fmi2ExitInitializationMode"),
            "fmi2ExitInitializationMode",
        );
        self.event_iteration();
        self.ok(
            self.call0("fmi2EnterContinuousTimeMode"),
            "fmi2EnterContinuousTimeMode",
        );
    }
}
