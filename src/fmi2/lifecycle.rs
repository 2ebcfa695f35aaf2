//! The instance's life: `fmi2Instantiate` (the scene a tailored FMU reads, the GUID),
//! `fmi2FreeInstance`, `fmi2SetDebugLogging`, `fmi2SetupExperiment`, initialization,
//! `fmi2Terminate`, `fmi2Reset`.

use super::*;

/// The scene an FMU is tailored to: `scene.toml` in its resources, if there is one.
fn load_scene<M: Model>(
    resources: Option<&PathBuf>,
) -> Result<Option<std::sync::Arc<crate::scene::Tailored>>, String> {
    let Some(path) = resources.map(|r| r.join(crate::scene::RESOURCE_NAME)) else {
        return Ok(None);
    };
    match std::fs::read_to_string(&path) {
        Ok(text) => crate::scene::cached::<M>(&text)
            .map(Some)
            .map_err(|e| format!("{}: {e}", path.display())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(format!("{}: {e}", path.display())),
    }
}

/// `fmi2Instantiate` as a C host calls it: `fmuType` is whatever `int` the host passed, and a
/// value that is no `fmi2Type` is refused with a log line (turning it into the Rust enum
/// [`FmuType`] first would be undefined behaviour).
///
/// # Safety
/// As [`instantiate`].
pub unsafe fn instantiate_c<M: Model>(
    instance_name: FmiString,
    fmu_type: std::ffi::c_int,
    guid: FmiString,
    resource_location: FmiString,
    functions: *const CallbackFunctions,
    visible: Boolean,
    logging_on: Boolean,
) -> Component {
    if let Some(ty) = FmuType::from_c(fmu_type) {
        // SAFETY: as this function.
        return unsafe {
            instantiate::<M>(
                instance_name,
                ty,
                guid,
                resource_location,
                functions,
                visible,
                logging_on,
            )
        };
    }
    let why = format!(
        "fmi2Instantiate: fmuType {fmu_type} is not an fmi2Type (0 = ModelExchange, 1 = CoSimulation); refused"
    );
    // SAFETY: NULL or a valid struct, per the standard.
    match unsafe { functions.as_ref() } {
        Some(f) if f.logger.is_some() => {
            // SAFETY: NULL or valid C string.
            let name = unsafe { c_str(instance_name) }
                .filter(|n| !n.is_empty())
                .unwrap_or(M::IDENTIFIER);
            Logger {
                sink: logger::Sink::Fmi2(f.logger),
                env: f.component_environment,
                name: CString::new(name).unwrap_or_default(),
                on: false,
                categories: u32::MAX,
            }
            .emit(Status::Error, "logStatusError", &why)
        }
        _ => eprintln!("{}: {why}", M::IDENTIFIER),
    }
    std::ptr::null_mut()
}

/// `fmi2Instantiate`.
///
/// # Safety
/// Pointer arguments must be NULL or valid per the FMI 2.0 standard.
pub unsafe fn instantiate<M: Model>(
    instance_name: FmiString,
    fmu_type: FmuType,
    guid: FmiString,
    resource_location: FmiString,
    functions: *const CallbackFunctions,
    _visible: Boolean,
    logging_on: Boolean,
) -> Component {
    instantiating::<M>("fmi2Instantiate", || {
        if functions.is_null() {
            eprintln!(
                "{}: fmi2Instantiate: callback functions are NULL; refused",
                M::IDENTIFIER
            );
            return std::ptr::null_mut();
        }
        // SAFETY: non-NULL, per the standard a valid struct.
        let f = unsafe { *functions };
        // SAFETY: NULL or valid C string.
        let name = unsafe { c_str(instance_name) }.unwrap_or("");
        let logger = Logger {
            sink: logger::Sink::Fmi2(f.logger),
            env: f.component_environment,
            name: CString::new(if name.is_empty() { M::IDENTIFIER } else { name })
                .unwrap_or_default(),
            on: logging_on != FALSE,
            categories: u32::MAX,
        };
        let refuse = |why: String| {
            logger.emit(
                Status::Error,
                "logStatusError",
                &format!("fmi2Instantiate: {why}; refused"),
            );
            std::ptr::null_mut()
        };
        if f.logger.is_none() {
            eprintln!(
                "{}: fmi2Instantiate: the logger callback is NULL; refused",
                M::IDENTIFIER
            );
            return std::ptr::null_mut();
        }
        if name.is_empty() {
            return refuse("instanceName is NULL or empty".into());
        }
        let model_exchange = fmu_type as i32 == FmuType::ModelExchange as i32 && M::STATES > 0;
        if fmu_type as i32 != FmuType::CoSimulation as i32 && !model_exchange {
            return refuse(format!(
                "fmuType {} requested; this FMU provides Co-Simulation (1) only",
                fmu_type as i32
            ));
        }
        // SAFETY: NULL or valid C string.
        let resources = unsafe { c_str(resource_location) }.and_then(resource_path);
        // SAFETY: NULL or valid C string.
        let guid = unsafe { c_str(guid) };
        match create::<M>(logger, model_exchange, guid, resources) {
            Ok(c) => c,
            Err((logger, why)) => {
                logger.emit(
                    Status::Error,
                    "logStatusError",
                    &format!("fmi2Instantiate: {why}; refused"),
                );
                std::ptr::null_mut()
            }
        }
    })
}

/// An instantiation through either FMI version (`call` names it) with its panics caught: a
/// panic gives NULL and a line on standard error (the host's logger may be what failed).
pub fn instantiating<M: Model>(call: &str, f: impl FnOnce() -> Component) -> Component {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|p| {
        eprintln!(
            "{}: {call}: internal error: {}",
            M::IDENTIFIER,
            panic_text(&*p)
        );
        std::ptr::null_mut()
    })
}

/// The instance of `M` a host asked for through either FMI version (`fmi2Instantiate`,
/// `fmi3InstantiateCoSimulation`, ...), registered: the scene of a tailored FMU read from
/// `resources`, the GUID or instantiation token checked against the declarations'. A refusal
/// gives the logger back with the reason, for the caller to say it in its version's words.
pub fn create<M: Model>(
    logger: Logger,
    model_exchange: bool,
    token: Option<&str>,
    resources: Option<PathBuf>,
) -> Result<Component, (Logger, String)> {
    let scene = match load_scene::<M>(resources.as_ref()) {
        Ok(s) => s,
        Err(why) => return Err((logger, format!("scene refused: {why}"))),
    };
    if model_exchange
        && scene
            .as_ref()
            .is_some_and(|t| !t.variables.iter().any(|(_, v)| v.derivative.is_some()))
    {
        return Err((
            logger,
            "fmuType 0 (ModelExchange) requested; this scene's FMU has no states and provides Co-Simulation (1) only"
                .into(),
        ));
    }
    // the GUID of what the description states, from the declarations (no XML written)
    let our_guid = match &scene {
        Some(t) => t.guid.clone(),
        None => md::guid::guid_of::<M>(),
    };
    if token != Some(our_guid.as_str()) {
        let why = format!(
            "GUID {:?} does not match this binary's {our_guid}",
            token.unwrap_or("NULL")
        );
        return Err((logger, why));
    }
    let mut inst = Box::new(Instance::<M>::new(logger, resources, &our_guid, scene));
    inst.me.is_me = model_exchange;
    crate::lifetime::instance_created();
    let c = Box::into_raw(inst) as Component;
    registry::add::<M>(c);
    Ok(c)
}

/// `fmi2FreeInstance`.
///
/// # Safety
/// As [`entry`].
pub unsafe fn free_instance<M: Model>(c: Component) {
    // SAFETY: as this function.
    unsafe { free_instance_as::<M, _>(c, Call::FreeInstance) }
}

/// `fmi2FreeInstance` or `fmi3FreeInstance` (`call`).
///
/// # Safety
/// As [`entry`].
pub unsafe fn free_instance_as<M: Model, C: Api>(c: Component, call: C) {
    // SAFETY: as entry.
    let ok = unsafe { entry::<M, _>(c, call, |_| Ok(Status::Ok)) };
    if ok == Status::Ok && registry::remove::<M>(c) {
        // SAFETY: entry checked the pointer is a live instance of ours; no longer registered,
        // no other call reaches it.
        drop(unsafe { Box::from_raw(c as *mut Instance<M>) });
        crate::lifetime::instance_freed();
    }
}

/// `fmi2SetDebugLogging`.
///
/// # Safety
/// As [`entry`]; `categories` holds `n` C strings.
pub unsafe fn set_debug_logging<M: Model>(
    c: Component,
    on: Boolean,
    n: usize,
    categories: *const FmiString,
) -> Status {
    // SAFETY: as this function.
    unsafe { set_debug_logging_as::<M, _>(c, Call::SetDebugLogging, on != FALSE, n, categories) }
}

/// `fmi2SetDebugLogging` or `fmi3SetDebugLogging` (`call`).
///
/// # Safety
/// As [`entry`]; `categories` holds `n` C strings.
pub unsafe fn set_debug_logging_as<M: Model, C: Api>(
    c: Component,
    call: C,
    on: bool,
    n: usize,
    categories: *const FmiString,
) -> Status {
    // SAFETY: as entry.
    unsafe {
        entry::<M, _>(c, call, |inst| {
            let cats = slice(categories, n, "categories")?;
            let mut bits = 0;
            for &p in cats {
                let name = c_str(p).ok_or("a category is NULL")?;
                bits |=
                    category_bit(name).ok_or_else(|| format!("unknown log category {name:?}"))?;
            }
            // No list: everything on or off. A list: exactly those on, or those off.
            match (n, on) {
                (0, on) => (inst.logger.on, inst.logger.categories) = (on, u32::MAX),
                (_, true) => (inst.logger.on, inst.logger.categories) = (true, bits),
                (_, false) => inst.logger.categories &= !bits,
            }
            Ok(Status::Ok)
        })
    }
}

/// The life of an instance, the same through either FMI version.
impl<M: Model> Instance<M> {
    /// `fmi2SetupExperiment` (`B` the version's Boolean): the start and stop time; the
    /// tolerance is not used (the elastodynamic level has its own: `solver.rtol`, `solver.atol`).
    pub fn experiment<B: PartialEq + From<bool>>(
        &mut self,
        _tolerance_defined: B,
        _tolerance: f64,
        start: f64,
        stop_defined: B,
        stop: f64,
    ) -> Outcome {
        let stop_defined = stop_defined != B::from(false);
        self.setup_experiment(start, stop_defined.then_some(stop))
    }

    /// `fmi3EnterInitializationMode`: the experiment, as [`Instance::experiment`], then
    /// initialization mode; a bad start or stop time changes nothing.
    pub fn experiment_and_initialization<B: PartialEq + From<bool>>(
        &mut self,
        tolerance_defined: B,
        tolerance: f64,
        start: f64,
        stop_defined: B,
        stop: f64,
    ) -> Outcome {
        self.experiment(tolerance_defined, tolerance, start, stop_defined, stop)?;
        self.enter_initialization_mode()
    }

    /// The experiment's start and stop time.
    pub fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Outcome {
        if !start.is_finite() {
            return Err(format!("startTime = {start} is not finite"));
        }
        if let Some(stop) = stop
            && !(stop.is_finite() && stop >= start)
        {
            return Err(format!(
                "stopTime = {stop} must be finite and not before startTime = {start}"
            ));
        }
        self.start_time = start;
        self.time = start;
        self.values.inputs_at = start;
        self.stop_time = stop;
        self.dirty = true;
        Ok(Status::Ok)
    }

    /// Into initialization mode.
    pub fn enter_initialization_mode(&mut self) -> Outcome {
        self.state = State::InitializationMode;
        self.dirty = true;
        Ok(Status::Ok)
    }

    /// Out of initialization mode: the parameters are final; a set the mechanism cannot work
    /// with is refused, naming the parameter, and the instance stays in initialization mode so
    /// the host can correct it.
    pub fn exit_initialization_mode(&mut self) -> Outcome {
        self.params_changed = true;
        self.refresh()
            .map_err(|e| format!("parameters refused: {e}"))?;
        self.state = State::StepComplete;
        self.me.mode = me::Mode::Event;
        self.logger.emit(Status::Ok, "logEvents", "initialized");
        Ok(Status::Ok)
    }

    /// The end of the run: the model reports what it gathered (the last turn's warnings).
    pub fn terminate(&mut self) -> Outcome {
        if let Some(m) = self.model.as_mut() {
            m.finish(&self.values, &mut self.logger);
        }
        self.state = State::Terminated;
        Ok(Status::Ok)
    }

    /// Back to a freshly instantiated state (start values, no experiment).
    pub fn reset(&mut self) -> Outcome {
        self.state = State::Instantiated;
        self.me.mode = me::Mode::Event;
        self.values = start_values::<M>(self.scene.as_deref());
        self.model = None;
        self.dirty = true;
        self.params_changed = true;
        self.time = 0.0;
        self.start_time = 0.0;
        self.stop_time = None;
        Ok(Status::Ok)
    }
}
