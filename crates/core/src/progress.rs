//! Progress reporting for long CPU work (loading, normal estimation, grouping,
//! the reference render).
//!
//! A [`Bar`] draws an `indicatif` bar on stderr when asked to (the CLI), and
//! also feeds the [`Tracker`] of the calling thread, if one is installed with
//! [`track`]. The viewer's worker threads install one, read it from the UI
//! thread for their progress bar, and set its cancel flag: long loops ask
//! [`Bar::is_cancelled`] and stop early, and the worker drops the result.
//! [`warn_once`] logs a warning once per process, for steps that run several
//! times on one model.

use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Shared progress of one background job: a stage name, done/total steps, a cancel flag.
#[derive(Debug, Default)]
pub struct Tracker {
    stage: Mutex<String>,
    done: AtomicU64,
    total: AtomicU64,
    cancelled: AtomicBool,
}

impl Tracker {
    pub fn new() -> Arc<Self> {
        Arc::new(Self::default())
    }

    /// Starts a stage of `total` steps (0: of unknown length).
    pub fn begin(&self, stage: &str, total: u64) {
        if let Ok(mut s) = self.stage.lock() {
            *s = stage.to_string();
        }
        self.done.store(0, Ordering::Relaxed);
        self.total.store(total, Ordering::Relaxed);
    }

    pub fn advance(&self, steps: u64) {
        self.done.fetch_add(steps, Ordering::Relaxed);
    }

    /// The stage name and its fraction done (`None` when its length is unknown).
    pub fn snapshot(&self) -> (String, Option<f32>) {
        let stage = self.stage.lock().map(|s| s.clone()).unwrap_or_default();
        let total = self.total.load(Ordering::Relaxed);
        let done = self.done.load(Ordering::Relaxed).min(total);
        (stage, (total > 0).then(|| done as f32 / total as f32))
    }

    pub fn cancel(&self) {
        self.cancelled.store(true, Ordering::Relaxed);
    }

    pub fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }
}

thread_local! {
    static CURRENT: RefCell<Option<Arc<Tracker>>> = const { RefCell::new(None) };
}

/// Runs `work` with `tracker` receiving the progress of every [`Bar`] and [`stage`] it starts on this thread.
pub fn track<R>(tracker: Arc<Tracker>, work: impl FnOnce() -> R) -> R {
    let previous = CURRENT.with(|c| c.replace(Some(tracker)));
    let result = work();
    CURRENT.with(|c| *c.borrow_mut() = previous);
    result
}

/// Logs `message` as a warning, once per process: steps that run several
/// times for one model (an overlap graph built for grouping, then for its
/// extension) say what they found once.
pub fn warn_once(message: String) {
    static SAID: Mutex<Vec<String>> = Mutex::new(Vec::new());
    let mut said = SAID.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    if !said.contains(&message) {
        log::warn!("{message}");
        said.push(message);
    }
}

fn current() -> Option<Arc<Tracker>> {
    CURRENT.with(|c| c.borrow().clone())
}

/// Names a step of unknown length for the current thread's tracker.
pub fn stage(name: &str) {
    if let Some(t) = current() {
        t.begin(name, 0);
    }
}

/// Whether the current thread's job was cancelled.
pub fn cancelled() -> bool {
    current().is_some_and(|t| t.is_cancelled())
}

/// A progress bar on the terminal, the current thread's tracker, both or neither.
pub struct Bar {
    terminal: Option<ProgressBar>,
    tracker: Option<Arc<Tracker>>,
}

impl Bar {
    pub fn inc(&self, steps: u64) {
        if let Some(b) = &self.terminal {
            b.inc(steps);
        }
        if let Some(t) = &self.tracker {
            t.advance(steps);
        }
    }

    /// Whether the job this bar belongs to was cancelled (always false on the CLI).
    pub fn is_cancelled(&self) -> bool {
        self.tracker.as_ref().is_some_and(|t| t.is_cancelled())
    }

    pub fn finish(self) {
        if let Some(b) = self.terminal {
            b.finish_and_clear();
        }
    }
}

/// Starts a bar over `len` steps, labelled `message`; it draws on stderr when
/// `terminal` is set (and stderr is a terminal).
pub fn bar(len: u64, message: &str, terminal: bool) -> Bar {
    let tracker = current();
    if let Some(t) = &tracker {
        t.begin(message, len);
    }
    let terminal = terminal.then(|| {
        let bar = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
        if let Ok(style) = ProgressStyle::with_template("{msg:>24} [{bar:40}] {percent:>3}% {elapsed_precise}") {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.set_message(message.to_string());
        bar
    });
    Bar { terminal, tracker }
}
