//! Progress of the long commands: a bar on a terminal, and a line per finished item either
//! way, so a log that is not a terminal (CI) says what was done and written.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;

pub struct Progress {
    bar: ProgressBar,
}

impl Progress {
    /// A bar of `len` items with `template` (indicatif), shown on a terminal only.
    pub fn new(len: u64, template: &str) -> Result<Self, String> {
        let bar = if std::io::stderr().is_terminal() {
            ProgressBar::new(len)
        } else {
            ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::hidden())
        };
        bar.set_style(ProgressStyle::with_template(template).map_err(|e| e.to_string())?);
        Ok(Progress { bar })
    }

    /// Prints a line above the bar (on stderr, also when there is no bar).
    pub fn line(&self, text: impl AsRef<str>) {
        if self.bar.is_hidden() {
            eprintln!("{}", text.as_ref());
        } else {
            self.bar.println(text.as_ref());
        }
    }

    /// What is running now (shown in the bar).
    pub fn doing(&self, what: impl Into<String>) {
        self.bar.set_message(what.into());
    }

    pub fn inc(&self) {
        self.bar.inc(1);
    }

    /// Items done so far.
    pub fn done(&self) -> u64 {
        self.bar.position()
    }

    pub fn len(&self) -> u64 {
        self.bar.length().unwrap_or(0)
    }

    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
