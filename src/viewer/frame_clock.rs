//! The window's frame rate and its slowest frame of the last two seconds,
//! for the statistics. An interval counts only when the frame before asked
//! for the next one at once (the window was repainting: the camera moved,
//! a frame arrived, an animation played). Otherwise the window sat idle,
//! waiting for input or a timer, and the wait is no frame's cost: counted,
//! half a second of reading the panel showed as a 500 ms frame.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

/// The UI frames' clock.
#[derive(Debug, Default)]
pub struct FrameClock {
    last: Option<Instant>,
    /// The intervals counted in the last two seconds, in ms, with when each ended.
    recent: VecDeque<(Instant, f32)>,
    fps: f32,
}

impl FrameClock {
    /// A UI frame begins at `now`; `repainting`: the frame before asked for it at once.
    pub fn tick(&mut self, now: Instant, repainting: bool) {
        if let Some(last) = self.last.filter(|_| repainting) {
            let seconds = now.duration_since(last).as_secs_f32().max(1e-4);
            let fps = 1.0 / seconds;
            self.fps = if self.fps == 0.0 { fps } else { 0.9 * self.fps + 0.1 * fps };
            self.recent.push_back((now, seconds * 1e3));
            log::debug!("UI frame {:.1} ms", seconds * 1e3);
        }
        while self.recent.front().is_some_and(|(t, _)| now.duration_since(*t) > Duration::from_secs(2)) {
            self.recent.pop_front();
        }
        self.last = Some(now);
    }

    /// Frames per second while the window repaints (a running mean).
    pub fn fps(&self) -> f32 {
        self.fps
    }

    /// The slowest frame counted in the last two seconds, in ms (0: none).
    pub fn slowest_ms(&self) -> f32 {
        self.recent.iter().map(|(_, ms)| *ms).fold(0.0, f32::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_idle_wait_is_not_a_frame_but_a_repainting_ones_interval_is() {
        let start = Instant::now();
        let at = |ms: u64| start + Duration::from_millis(ms);
        let mut clock = FrameClock::default();
        clock.tick(at(0), true);
        clock.tick(at(20), true);
        clock.tick(at(520), false);
        assert_eq!(clock.slowest_ms(), 20.0, "the half second waited idle is not a frame");
        clock.tick(at(560), true);
        assert_eq!(clock.slowest_ms(), 40.0);
        assert!((clock.fps() - 47.5).abs() < 1e-3, "a running mean of 50 and 25 fps: {}", clock.fps());
        clock.tick(at(3000), true);
        assert_eq!(clock.slowest_ms(), 2440.0, "a slow frame while repainting is counted");
        clock.tick(at(5500), false);
        assert_eq!(clock.slowest_ms(), 0.0, "what is older than two seconds is dropped");
    }
}
