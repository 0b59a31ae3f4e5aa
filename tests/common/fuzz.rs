//! Helpers of the loaders' fuzz tests: an allocator that records the peak
//! of live bytes (so a test can bound what one load allocates) and a small
//! seeded generator.

/// Defines the test binary's global allocator, which counts the bytes live
/// now (`CURRENT`) and their peak since the last reset (`PEAK`).
#[macro_export]
macro_rules! counting_allocator {
    () => {
        struct CountingAllocator;

        static CURRENT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        static PEAK: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

        unsafe impl std::alloc::GlobalAlloc for CountingAllocator {
            unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
                let p = unsafe { <std::alloc::System as std::alloc::GlobalAlloc>::alloc(&std::alloc::System, layout) };
                if !p.is_null() {
                    let now = CURRENT.fetch_add(layout.size(), std::sync::atomic::Ordering::Relaxed) + layout.size();
                    PEAK.fetch_max(now, std::sync::atomic::Ordering::Relaxed);
                }
                p
            }

            unsafe fn dealloc(&self, ptr: *mut u8, layout: std::alloc::Layout) {
                unsafe { <std::alloc::System as std::alloc::GlobalAlloc>::dealloc(&std::alloc::System, ptr, layout) };
                CURRENT.fetch_sub(layout.size(), std::sync::atomic::Ordering::Relaxed);
            }
        }

        #[global_allocator]
        static ALLOCATOR: CountingAllocator = CountingAllocator;

        /// Loads `path` as `pointblend::cloud::load` does, catching a panic;
        /// checks what it gave, its time and its peak allocation
        /// ([`common::fuzz::check`]), and returns the peak.
        fn checked_load(path: &std::path::Path, tally: &mut common::fuzz::Tally) {
            use std::sync::atomic::Ordering;
            let base = CURRENT.load(Ordering::Relaxed);
            PEAK.store(base, Ordering::Relaxed);
            let started = std::time::Instant::now();
            let result = std::panic::catch_unwind(|| pointblend::cloud::load(path));
            let elapsed = started.elapsed();
            let peak = PEAK.load(Ordering::Relaxed).saturating_sub(base);
            common::fuzz::check(path, result, elapsed, peak, tally);
        }
    };
}

/// Most memory one load of a small fuzzed file may hold at once. A lying
/// count that was believed would ask for gigabytes.
pub const MAX_PEAK_BYTES: usize = 64 << 20;

/// Longest one load may take before it counts as a hang.
pub const MAX_SECONDS_PER_FILE: u64 = 20;

/// What the variants came to.
#[derive(Debug, Default)]
pub struct Tally {
    pub loaded: usize,
    pub refused: usize,
    pub worst_peak: usize,
}

impl Tally {
    /// Prints the tally and checks that the mutations reached both outcomes.
    pub fn finish(self, started: std::time::Instant) {
        let Tally { loaded, refused, worst_peak } = self;
        println!(
            "{} variants: {loaded} loaded, {refused} refused, largest allocation peak {:.1} MB, {:.1} s",
            loaded + refused,
            worst_peak as f64 / 1e6,
            started.elapsed().as_secs_f64()
        );
        assert!(loaded > 100 && refused > 100, "the mutations reach both outcomes: {loaded} loaded, {refused} refused");
    }
}

/// One variant's load: a consistent cloud of finite splats, or one error
/// line naming the file; never a panic, more than [`MAX_PEAK_BYTES`] at
/// once, or more than [`MAX_SECONDS_PER_FILE`]. A failing file is kept
/// outside the test's folder (removed when the test fails).
pub fn check(
    path: &std::path::Path,
    result: std::thread::Result<
        Result<(pointblend::cloud::PointCloud, pointblend::cloud::LoadReport), pointblend::cloud::CloudError>,
    >,
    elapsed: std::time::Duration,
    peak: usize,
    tally: &mut Tally,
) {
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    let keep = std::env::temp_dir().join(format!("pointblend-failing-{name}"));
    let fail = |what: String| {
        let _ = std::fs::copy(path, &keep);
        panic!("{name}: {what} (kept as {})", keep.display());
    };
    match result {
        Err(_) => fail("the loader panicked".into()),
        Ok(Ok((cloud, _))) => {
            assert!(cloud.is_consistent(), "{name}: inconsistent cloud");
            assert!(cloud.positions.iter().all(|p| p.is_finite()), "{name}: non-finite position");
            assert!(cloud.radii.iter().all(|r| r.is_finite() && *r > 0.0), "{name}: bad radius");
            tally.loaded += 1;
        }
        Ok(Err(e)) => {
            let text = e.to_string();
            assert!(!text.contains('\n') && text.contains(&name), "{text}");
            tally.refused += 1;
        }
    }
    tally.worst_peak = tally.worst_peak.max(peak);
    if peak > MAX_PEAK_BYTES {
        let size = std::fs::metadata(path).map_or(0, |m| m.len());
        fail(format!("a load of {size} bytes allocated {peak} bytes at once"));
    }
    if elapsed > std::time::Duration::from_secs(MAX_SECONDS_PER_FILE) {
        fail(format!("a load took {elapsed:?}"));
    }
}

/// A xorshift generator: the same variants on every run.
pub struct Rng(pub u64);
impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}
