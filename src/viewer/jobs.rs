//! Background jobs of the viewer: loading a model, grouping it, rendering the
//! exact reference. Each runs on its own thread with a [`Tracker`] the panel
//! reads for its progress bar; Cancel sets the tracker's flag, long loops stop
//! early, and the job's result is dropped, so the window never waits.

use std::sync::Arc;
use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::time::Instant;

use crate::progress::{self, Tracker};

/// A job running on a worker thread, producing one `T`.
pub struct Job<T> {
    label: String,
    tracker: Arc<Tracker>,
    receiver: Receiver<T>,
    started: Instant,
}

impl<T: Send + 'static> Job<T> {
    /// Starts `work` on a new thread; `repaint` is woken when it ends.
    pub fn spawn(label: impl Into<String>, repaint: egui::Context, work: impl FnOnce() -> T + Send + 'static) -> Self {
        let label = label.into();
        let tracker = Tracker::new();
        let (sender, receiver) = mpsc::channel();
        let worker_tracker = Arc::clone(&tracker);
        let spawned = std::thread::Builder::new().name(format!("pointblend {label}")).spawn(move || {
            let result = progress::track(Arc::clone(&worker_tracker), work);
            if !worker_tracker.is_cancelled() {
                let _ = sender.send(result);
            }
            repaint.request_repaint();
        });
        if let Err(e) = spawned {
            log::error!("could not start the {label} thread: {e}");
        }
        Self { label, tracker, receiver, started: Instant::now() }
    }
}

impl<T> Job<T> {
    /// The result once the job is done; `Err` when its thread stopped without one.
    pub fn poll(&self) -> Option<Result<T, String>> {
        match self.receiver.try_recv() {
            Ok(value) => Some(Ok(value)),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some(Err(format!("the {} worker stopped without a result", self.label))),
        }
    }

    pub fn cancel(&self) {
        self.tracker.cancel();
    }

    pub fn label(&self) -> &str {
        &self.label
    }

    /// The current stage and its fraction done, if known.
    pub fn progress(&self) -> (String, Option<f32>) {
        self.tracker.snapshot()
    }

    pub fn seconds(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }
}
