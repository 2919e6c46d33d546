//! One job on a worker thread, the one way the state derives a value off the
//! frame: spawned with a key (what it is for: a plan revision, an activity),
//! polled for its result, with a progress count, a line saying what it is
//! doing and a cancel flag its work reads ([`Signal`]). Dropping the job cancels it: nobody will read what it
//! goes on computing, so a replaced or abandoned job stops as soon as its work
//! looks at the flag.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// What a job's work and the job share: a cancel flag, a progress count and
/// what it is doing.
#[derive(Debug, Default)]
pub struct Signal {
    cancel: AtomicBool,
    done: AtomicU64,
    note: Mutex<String>,
}

impl Signal {
    /// The cancel flag, for work that takes one (set when the job is
    /// cancelled or dropped).
    pub fn cancel_flag(&self) -> &AtomicBool {
        &self.cancel
    }

    /// Counts one more unit of work done (for a progress bar).
    pub fn tick(&self) {
        self.done.fetch_add(1, Ordering::Relaxed);
    }

    /// Says what the work is doing now (for a progress line).
    pub fn say(&self, note: impl Into<String>) {
        // A worker that panicked while holding the lock poisons it: its last
        // word is kept, nothing else depends on it.
        if let Ok(mut n) = self.note.lock() {
            *n = note.into();
        }
    }
}

/// The worker stopped without a result (it panicked).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Lost;

/// A job on a worker thread: what it is for, and where its result comes.
#[derive(Debug)]
pub struct Job<K, T> {
    key: K,
    rx: Receiver<T>,
    signal: Arc<Signal>,
    started: Instant,
}

impl<K: Copy, T: Send + 'static> Job<K, T> {
    /// Runs `work` on a new thread, for `key`.
    pub fn spawn(key: K, work: impl FnOnce(&Signal) -> T + Send + 'static) -> Self {
        let (tx, rx) = mpsc::channel();
        let signal = Arc::new(Signal::default());
        let shared = Arc::clone(&signal);
        std::thread::spawn(move || {
            // A send fails only when the app let go of this job (another plan was
            // opened): nobody waits for the result, which is dropped on purpose.
            drop(tx.send(work(&shared)));
        });
        Self {
            key,
            rx,
            signal,
            started: Instant::now(),
        }
    }
}

impl<K: Copy, T> Job<K, T> {
    /// What the job is for.
    pub fn key(&self) -> K {
        self.key
    }

    /// The result if it is in: `Some(Ok)`, or `Some(Err(Lost))` when the
    /// worker stopped without one (it panicked); `None` while it runs.
    pub fn poll(&self) -> Option<Result<T, Lost>> {
        match self.rx.try_recv() {
            Ok(v) => Some(Ok(v)),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some(Err(Lost)),
        }
    }

    /// Asks the work to stop (it stops when it next looks at the flag).
    pub fn cancel(&self) {
        self.signal.cancel.store(true, Ordering::Relaxed);
    }

    /// Whether it was asked to stop.
    pub fn cancelling(&self) -> bool {
        self.signal.cancel.load(Ordering::Relaxed)
    }

    /// The units of work done so far (as the work counted them).
    pub fn done(&self) -> u64 {
        self.signal.done.load(Ordering::Relaxed)
    }

    /// What the work last said it was doing (empty before it said anything).
    pub fn note(&self) -> String {
        self.signal
            .note
            .lock()
            .map(|n| n.clone())
            .unwrap_or_default()
    }

    /// How long it has run.
    pub fn elapsed(&self) -> Duration {
        self.started.elapsed()
    }
}

impl<K, T> Drop for Job<K, T> {
    fn drop(&mut self) {
        // Nobody will read what it computes on: it stops within moments.
        self.signal.cancel.store(true, Ordering::Relaxed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Polls `job` until its result is in.
    fn wait<K: Copy, T>(job: &Job<K, T>) -> Result<T, Lost> {
        loop {
            if let Some(r) = job.poll() {
                return r;
            }
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    #[test]
    fn a_job_hands_its_result_and_progress_back_under_its_key() {
        let job = Job::spawn((7_u64, 3_usize), |s: &Signal| {
            for _ in 0..5 {
                s.tick();
            }
            s.say("finishing");
            "done"
        });
        assert_eq!(job.key(), (7, 3));
        assert_eq!(wait(&job), Ok("done"));
        assert_eq!(job.done(), 5);
        assert_eq!(job.note(), "finishing");
        assert!(!job.cancelling());
    }

    #[test]
    fn a_worker_that_panics_is_lost_not_waited_for() {
        #[allow(clippy::panic)]
        let job = Job::spawn(0_u8, |_: &Signal| -> u32 { panic!("worker failed") });
        assert_eq!(wait(&job), Err(Lost));
    }

    #[test]
    fn cancelling_or_dropping_a_job_sets_the_flag_its_work_reads() {
        let (seen_tx, seen_rx) = mpsc::channel();
        let job = Job::spawn(0_u8, move |s: &Signal| {
            while !s.cancel_flag().load(Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(1));
            }
            seen_tx.send(()).expect("the test waits");
        });
        job.cancel();
        assert!(job.cancelling());
        assert_eq!(wait(&job), Ok(()));
        // Dropped while it runs: it stops too.
        let (seen_tx2, seen_rx2) = mpsc::channel();
        let job = Job::spawn(1_u8, move |s: &Signal| {
            while !s.cancel_flag().load(Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(1));
            }
            seen_tx2.send(()).expect("the test waits");
        });
        drop(job);
        assert!(seen_rx.recv_timeout(Duration::from_secs(10)).is_ok());
        assert!(seen_rx2.recv_timeout(Duration::from_secs(10)).is_ok());
    }
}
