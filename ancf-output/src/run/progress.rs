//! A run's progress bar on the terminal: indicatif's with the `progress`
//! feature (the command line), nothing without it (the Python package).

/// Steps done of a run's total, with the simulated time as its message.
pub(super) struct Bar {
    #[cfg(feature = "progress")]
    bar: indicatif::ProgressBar,
}

impl Bar {
    /// A bar of `total` steps; `hidden`: draws nothing.
    #[cfg_attr(not(feature = "progress"), allow(unused_variables))]
    pub(super) fn new(total: u64, hidden: bool) -> Self {
        #[cfg(feature = "progress")]
        {
            let bar = if hidden {
                indicatif::ProgressBar::hidden()
            } else {
                let bar = indicatif::ProgressBar::new(total);
                bar.set_style(
                    indicatif::ProgressStyle::with_template(
                        "{bar:40} {pos}/{len} steps  t = {msg}  {per_sec}  ETA {eta}",
                    )
                    .expect("valid template"),
                );
                bar
            };
            Bar { bar }
        }
        #[cfg(not(feature = "progress"))]
        Bar {}
    }

    /// `steps` done.
    #[cfg_attr(not(feature = "progress"), allow(unused_variables))]
    pub(super) fn set_position(&self, steps: u64) {
        #[cfg(feature = "progress")]
        self.bar.set_position(steps);
    }

    /// The message after the counts.
    #[cfg_attr(not(feature = "progress"), allow(unused_variables))]
    pub(super) fn set_message(&self, message: String) {
        #[cfg(feature = "progress")]
        self.bar.set_message(message);
    }

    /// Remove the bar from the terminal.
    pub(super) fn finish_and_clear(&self) {
        #[cfg(feature = "progress")]
        self.bar.finish_and_clear();
    }
}
