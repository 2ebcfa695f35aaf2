//! The host's logger of an instance: categories, and what reaches the host.

use super::*;

/// Log categories as bits (see [`md::LOG_CATEGORIES`]).
pub(super) fn category_bit(name: &str) -> Option<u32> {
    md::LOG_CATEGORIES
        .iter()
        .position(|(n, _)| *n == name)
        .map(|i| 1 << i)
}

/// Where an instance's messages go: the logger of the FMI version it was instantiated through.
#[derive(Clone, Copy)]
pub(super) enum Sink {
    /// `fmi2CallbackLogger`: variadic, the message a printf format (so `%` is escaped).
    Fmi2(CallbackLogger),
    /// `fmi3LogMessageCallback`: the message as it is (no instance name: the environment
    /// tells the host which instance speaks).
    Fmi3(LogMessage3),
}

/// The host's logger, with the instance name and the enabled categories.
pub struct Logger {
    pub(super) sink: Sink,
    pub(super) env: ComponentEnvironment,
    pub(super) name: CString,
    pub(super) on: bool,
    pub(super) categories: u32,
}

impl Logger {
    /// Sends one message; `%` is escaped because hosts treat the message as a printf format.
    pub fn emit(&self, status: Status, category: &str, message: &str) {
        if !self.enabled(status, category) {
            return;
        }
        let cat = CString::new(category).unwrap_or_default();
        match self.sink {
            Sink::Fmi2(Some(cb)) => {
                let msg =
                    CString::new(message.replace('%', "%%").replace('\0', " ")).unwrap_or_default();
                // SAFETY: the host gave us this logger for this environment; all strings are
                // valid C strings.
                unsafe {
                    cb(
                        self.env,
                        self.name.as_ptr(),
                        status,
                        cat.as_ptr(),
                        msg.as_ptr(),
                    )
                };
            }
            Sink::Fmi3(Some(cb)) => {
                let msg = CString::new(message.replace('\0', " ")).unwrap_or_default();
                // SAFETY: as above; FMI 3.0 has no fmi3Pending (never emitted: debug
                // messages go out as fmi3OK).
                unsafe { cb(self.env, status, cat.as_ptr(), msg.as_ptr()) };
            }
            Sink::Fmi2(None) | Sink::Fmi3(None) => {}
        }
    }

    /// The logger of an FMI 3.0 instance (`fmi3Instantiate*`), all categories enabled.
    pub fn fmi3(callback: LogMessage3, env: ComponentEnvironment, name: &str, on: bool) -> Self {
        Logger {
            sink: Sink::Fmi3(callback),
            env,
            name: CString::new(name).unwrap_or_default(),
            on,
            categories: u32::MAX,
        }
    }

    /// Has the host given a callback?
    pub fn has_callback(&self) -> bool {
        !matches!(self.sink, Sink::Fmi2(None) | Sink::Fmi3(None))
    }
}

impl Logger {
    /// Would a message of this status and category reach the host? Warnings and errors always
    /// do; debug messages when logging is on for their category.
    #[inline]
    pub fn enabled(&self, status: Status, category: &str) -> bool {
        let debug = matches!(status, Status::Ok | Status::Pending);
        !debug || (self.on && category_bit(category).is_some_and(|b| self.categories & b != 0))
    }
}

impl Log for Logger {
    fn log(&mut self, severity: Severity, message: &str) {
        match severity {
            Severity::Info => self.emit(Status::Ok, "logEvents", message),
            Severity::Warning => self.emit(Status::Warning, "logStatusWarning", message),
        }
    }
}
