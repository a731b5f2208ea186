//! Progress bars (indicatif) for long work: light paths traced and samples rendered, with rates.
//! Bars draw on stderr only when it is a terminal, so scripts and CI logs stay clean.
//! [`TraceProgress`] is what the dataset jobs of `opticks_io` report to: a bar while tracing,
//! and Ctrl-C or the end of `--time` as the request to stop.

use indicatif::{HumanCount, ProgressBar, ProgressState, ProgressStyle};
use opticks_io::dataset_job::JobProgress;
use std::cell::{Cell, RefCell};
use std::time::{Duration, Instant};

/// A bar counting `total` items of `unit` (e.g. "paths"), showing the rate per second as a
/// whole number ("458,006/s"). Hidden with `--quiet`.
pub fn bar(total: u64, what: &str, unit: &str) -> ProgressBar {
    if crate::output::is_quiet() {
        return ProgressBar::hidden();
    }
    let pb = ProgressBar::new(total);
    let template = format!(
        "{what:>9} [{{elapsed_precise}}] {{bar:40.cyan/blue}} {{human_pos}}/{{human_len}} {unit} ({{rate}}, eta {{eta}})"
    );
    let style = ProgressStyle::with_template(&template)
        .expect("static template is valid")
        .with_key("rate", |state: &ProgressState, w: &mut dyn std::fmt::Write| {
            let _ = write!(w, "{}/s", HumanCount(state.per_sec().max(0.0) as u64));
        })
        .progress_chars("=> ");
    pb.set_style(style);
    pb
}

/// A bar over `seconds` of wall-clock time, with a message (a progressive render's passes and
/// error estimate).
pub fn seconds_bar(seconds: f64) -> ProgressBar {
    let pb = ProgressBar::new(seconds.ceil() as u64);
    pb.set_style(
        ProgressStyle::with_template("rendering [{elapsed_precise}] {bar:40.cyan/blue} {pos}/{len} s {msg}")
            .expect("static template is valid")
            .progress_chars("=> "),
    );
    pb
}

/// A "tracing … paths" bar for a dataset job, which stops on a signal (and, for tests, once
/// `$OPTICKS_INTERRUPT_AFTER_PATHS` paths are traced: see `crate::interrupt`).
#[derive(Default)]
pub struct TraceProgress {
    bar: RefCell<Option<ProgressBar>>,
    /// The `--time` limit (none: never), counted from the start of tracing: copying a dataset's
    /// existing chunks is bounded work, and a stop during it would save nothing.
    limit: Option<Duration>,
    /// When the limit is up, once tracing started.
    deadline: Cell<Option<Instant>>,
    /// Whether the stop asked for was the deadline's.
    time_up: Cell<bool>,
}

impl TraceProgress {
    /// A bar that also asks to stop once `limit` has passed since tracing started (`--time`;
    /// `None`: never).
    pub fn with_time_limit(limit: Option<Duration>) -> Self {
        TraceProgress { limit, ..Default::default() }
    }

    /// Whether tracing stopped because the time limit was reached (not because of a signal).
    pub fn time_was_up(&self) -> bool {
        self.time_up.get() && !crate::interrupt::requested()
    }
}

impl JobProgress for TraceProgress {
    fn tracing(&self, paths: u64) {
        self.deadline.set(self.limit.map(|d| Instant::now() + d));
        *self.bar.borrow_mut() = Some(bar(paths, "tracing", "paths"));
    }

    fn traced(&self, done: u64) {
        if let Some(pb) = &*self.bar.borrow() {
            pb.set_position(done);
        }
        crate::interrupt::simulate_after(done);
    }

    fn traced_all(&self) {
        if let Some(pb) = self.bar.borrow_mut().take() {
            pb.finish_and_clear();
        }
    }

    fn stop(&self) -> bool {
        if self.deadline.get().is_some_and(|d| Instant::now() >= d) {
            self.time_up.set(true);
        }
        crate::interrupt::requested() || self.time_up.get()
    }

    fn time_is_up(&self) -> bool {
        self.time_was_up()
    }
}
