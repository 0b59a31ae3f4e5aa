//! What a streamed view's background job shares with the window while it
//! refines in steps ([`super::streaming`]): the slot the newest step's model
//! waits in until the window takes it, and the window's frame time, which
//! paces the steps (no faster than the window draws them, 250 ms at least).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use super::model::Model;

/// The newest model of a view still refining, for the window to take.
pub(super) type Interim = Arc<Mutex<Option<Model>>>;

/// The time of the window's last frame of the view, in microseconds.
pub(super) type FramePace = Arc<AtomicU64>;

/// The least time between two steps of a view shown while it refines.
const LEAST_PACE: Duration = Duration::from_millis(250);

/// How long a step waits after the last one shown: the window's last frame time, 250 ms at least.
pub(super) fn pace(frame: &FramePace) -> Duration {
    Duration::from_micros(frame.load(Ordering::Relaxed)).max(LEAST_PACE)
}

/// Records a frame of the view that took `ms` milliseconds.
pub(super) fn record_frame(frame: &FramePace, ms: f64) {
    frame.store((ms * 1e3) as u64, Ordering::Relaxed);
}
