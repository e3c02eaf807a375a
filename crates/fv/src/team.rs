//! A persistent team of helper threads for the solvers' short parallel loops.
//!
//! The fluid's step is a chain of short loops (a vector update over 110,000 cells takes
//! 30–60 µs) separated by short sequential stretches. Rayon's fork-join costs many
//! microseconds per loop on this kind of machine: the idle worker has gone to sleep and must be
//! woken, and the loop is split into tasks that are stolen one by one
//! (`examples/fork_join.rs`: a 110,000-element loop ran 1.32× faster on two threads than on one
//! with rayon, 1.93× with a team whose helper waits by spinning). [`run`] hands the loop's
//! chunks to helpers that wait for work by spinning, then yielding, then parking.
//!
//! Chunks are claimed from one shared counter, the caller claiming too: a helper that is late,
//! asleep or busy never holds the caller up (the caller then does every chunk itself), and the
//! caller returns only when every chunk it did not run itself has finished. Which thread runs
//! a chunk never changes what the chunk computes, so callers that fix their chunks (the
//! reductions of [`crate::reduce`] sum fixed blocks in order) get the same bits on any number
//! of threads. At most `rayon::current_num_threads()` threads work on a loop (the `--np` of a
//! run); one team serves the whole process, one loop at a time: a loop started while another
//! runs (another thread's, or a chunk's own inner loop) runs on its caller alone.
//!
//! A chunk that panics does not leave anything hanging: the caller stops handing out chunks,
//! waits for the ones already running, and then panics with the chunk's message.
//!
//! The claim protocol: one 64-bit word holds the loop's epoch (32 bits), the number of helpers
//! allowed to join (8), the next unclaimed chunk (12) and the number of chunks (12). A helper
//! reads the word, then the loop's job, then claims with a compare-and-swap on the word as it
//! read it: the swap succeeds only while that loop still has unclaimed chunks, and the caller
//! neither returns nor publishes the next job before every claimed chunk has finished, so a job
//! a successful claim uses is alive.

use std::cell::UnsafeCell;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicPtr, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock};
use std::thread::Thread;
use std::time::{Duration, Instant};

/// The most chunks one loop may have (the word's 12-bit fields).
pub(crate) const MAX_CHUNKS: usize = (1 << 12) - 1;

/// How long an idle helper spins (then yields) before it parks. Gaps between two loops of a
/// step are mostly shorter; a parked helper costs a wake-up the caller does not wait for.
const SPIN: Duration = Duration::from_micros(200);

/// One loop: its chunk function.
struct Job<'a> {
    f: &'a (dyn Fn(usize) + Sync),
}

/// The team: the claim word, the job, the count of chunks the helpers finished, the helpers.
struct Team {
    word: AtomicU64,
    job: AtomicPtr<Job<'static>>,
    done: AtomicUsize,
    panicked: AtomicBool,
    /// A panic message of a helper's chunk in the current loop.
    message: Mutex<Option<String>>,
    busy: AtomicBool,
    sleepers: AtomicUsize,
    helpers: Mutex<Vec<Thread>>,
    n_helpers: AtomicUsize,
}

fn team() -> &'static Team {
    static TEAM: OnceLock<Team> = OnceLock::new();
    TEAM.get_or_init(|| Team {
        word: AtomicU64::new(0),
        job: AtomicPtr::new(std::ptr::null_mut()),
        done: AtomicUsize::new(0),
        panicked: AtomicBool::new(false),
        message: Mutex::new(None),
        busy: AtomicBool::new(false),
        sleepers: AtomicUsize::new(0),
        helpers: Mutex::new(Vec::new()),
        n_helpers: AtomicUsize::new(0),
    })
}

/// The claim word's fields.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
struct Word {
    epoch: u32,
    allowed: u8,
    next: u16,
    n: u16,
}

impl Word {
    fn pack(self) -> u64 {
        (u64::from(self.epoch) << 32)
            | (u64::from(self.allowed) << 24)
            | (u64::from(self.next) << 12)
            | u64::from(self.n)
    }

    fn unpack(w: u64) -> Word {
        Word {
            epoch: (w >> 32) as u32,
            allowed: (w >> 24) as u8,
            next: ((w >> 12) & 0xfff) as u16,
            n: (w & 0xfff) as u16,
        }
    }
}

impl Team {
    /// Claims the next chunk of the loop whose word read `w`; `None` when it has none left or
    /// the word changed (another claim or another loop: read it again).
    fn claim(&self, w: u64) -> Option<usize> {
        let mut word = Word::unpack(w);
        if word.next >= word.n {
            return None;
        }
        let k = word.next;
        word.next += 1;
        self.word
            .compare_exchange(w, word.pack(), Ordering::AcqRel, Ordering::Acquire)
            .ok()
            .map(|_| k as usize)
    }

    /// Makes sure at least `helpers` helper threads exist.
    fn ensure_helpers(&'static self, helpers: usize) {
        if self.n_helpers.load(Ordering::Acquire) >= helpers {
            return;
        }
        let mut list = self.helpers.lock().unwrap_or_else(|e| e.into_inner());
        while list.len() < helpers {
            let index = list.len();
            let spawned = std::thread::Builder::new()
                .name(format!("fv-team-{}", index + 1))
                .spawn(move || self.helper(index));
            match spawned {
                Ok(h) => list.push(h.thread().clone()),
                // No thread: the loops run with the helpers there are.
                Err(_) => break,
            }
        }
        self.n_helpers.store(list.len(), Ordering::Release);
    }

    /// A helper's life: wait for a loop it may join, claim and run its chunks, wait again.
    fn helper(&self, index: usize) {
        let mut seen = 0u32;
        loop {
            let w = self.wait_for_work(seen, index);
            let word = Word::unpack(w);
            seen = word.epoch;
            let mut w = w;
            loop {
                let job = self.job.load(Ordering::Acquire);
                match self.claim(w) {
                    Some(k) => {
                        // SAFETY: the claim succeeded on the word of the loop `job` belongs
                        // to (the caller stores the job before the loop's word), and that
                        // loop's caller does not return before this chunk is counted done.
                        let f = unsafe { (*job).f };
                        if let Err(e) = catch_unwind(AssertUnwindSafe(|| f(k))) {
                            let mut m = self.message.lock().unwrap_or_else(|e| e.into_inner());
                            m.get_or_insert_with(|| panic_message(&e));
                            self.panicked.store(true, Ordering::Release);
                        }
                        self.done.fetch_add(1, Ordering::AcqRel);
                    }
                    None => {
                        let now = Word::unpack(self.word.load(Ordering::Acquire));
                        if now.epoch != seen || now.next >= now.n {
                            break;
                        }
                    }
                }
                w = self.word.load(Ordering::Acquire);
                if Word::unpack(w).epoch != seen {
                    break;
                }
            }
        }
    }

    /// Waits until the word shows a loop after `seen` that helper `index` may join and that
    /// has unclaimed chunks; spins, then yields, then parks.
    fn wait_for_work(&self, seen: u32, index: usize) -> u64 {
        let open = |w: u64| {
            let word = Word::unpack(w);
            word.epoch != seen && (index as u8) < word.allowed && word.next < word.n
        };
        let start = Instant::now();
        let mut spins = 0u32;
        loop {
            let w = self.word.load(Ordering::Acquire);
            if open(w) {
                return w;
            }
            spins += 1;
            if spins.is_multiple_of(64) {
                if start.elapsed() > SPIN {
                    self.sleepers.fetch_add(1, Ordering::SeqCst);
                    let w = self.word.load(Ordering::SeqCst);
                    if !open(w) {
                        std::thread::park();
                    }
                    self.sleepers.fetch_sub(1, Ordering::SeqCst);
                    continue;
                }
                if spins.is_multiple_of(1024) {
                    std::thread::yield_now();
                }
            }
            std::hint::spin_loop();
        }
    }

    /// Wakes the parked helpers (after a new loop's word was stored).
    fn wake(&self) {
        if self.sleepers.load(Ordering::SeqCst) > 0 {
            for t in self
                .helpers
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .iter()
            {
                t.unpark();
            }
        }
    }
}

/// The message of a caught panic.
fn panic_message(e: &Box<dyn std::any::Any + Send>) -> String {
    if let Some(s) = e.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = e.downcast_ref::<String>() {
        s.clone()
    } else {
        "a parallel chunk panicked".to_string()
    }
}

/// Releases the team when the loop ends, by return or by panic.
struct Busy(&'static Team);

impl Drop for Busy {
    fn drop(&mut self) {
        self.0.busy.store(false, Ordering::Release);
    }
}

/// Runs `f(0)`, …, `f(n − 1)`, each once, on the calling thread and up to
/// `rayon::current_num_threads() − 1` helpers of the team (module doc), and returns when all
/// have returned. On one thread, for one chunk, or while the team runs another loop, the
/// chunks run in order on the caller.
pub(crate) fn run(n: usize, f: &(dyn Fn(usize) + Sync)) {
    let threads = rayon::current_num_threads().min(256);
    if threads <= 1 || n <= 1 || n > MAX_CHUNKS {
        return (0..n).for_each(f);
    }
    let team = team();
    if team
        .busy
        .compare_exchange(false, true, Ordering::Acquire, Ordering::Relaxed)
        .is_err()
    {
        return (0..n).for_each(f);
    }
    let _busy = Busy(team);
    team.ensure_helpers(threads - 1);
    let job = Job { f };
    // SAFETY (of the lifetime extension): the job is read by helpers only through a claim of
    // this loop, and this function returns only after every claimed chunk has finished.
    let job_ptr = &job as *const Job<'_> as *mut Job<'static>;
    team.done.store(0, Ordering::Relaxed);
    team.panicked.store(false, Ordering::Relaxed);
    team.job.store(job_ptr, Ordering::Release);
    let epoch = Word::unpack(team.word.load(Ordering::Relaxed))
        .epoch
        .wrapping_add(1);
    let start = Word {
        epoch,
        allowed: (threads - 1) as u8,
        next: 0,
        n: n as u16,
    };
    team.word.store(start.pack(), Ordering::SeqCst);
    team.wake();
    let mut mine = 0usize;
    let mut failure = None;
    loop {
        let w = team.word.load(Ordering::Acquire);
        let word = Word::unpack(w);
        if word.next >= word.n {
            break;
        }
        if let Some(k) = team.claim(w) {
            mine += 1;
            if let Err(e) = catch_unwind(AssertUnwindSafe(|| f(k))) {
                failure = Some(e);
                // No more chunks for anyone: close the loop at the chunk count claimed.
                let mut w = team.word.load(Ordering::Acquire);
                loop {
                    let mut word = Word::unpack(w);
                    word.n = word.next;
                    match team.word.compare_exchange(
                        w,
                        word.pack(),
                        Ordering::AcqRel,
                        Ordering::Acquire,
                    ) {
                        Ok(_) => break,
                        Err(now) => w = now,
                    }
                }
                break;
            }
        }
    }
    let claimed = Word::unpack(team.word.load(Ordering::Acquire)).next as usize;
    let theirs = claimed - mine;
    let mut spins = 0u32;
    while team.done.load(Ordering::Acquire) < theirs {
        spins += 1;
        if spins.is_multiple_of(1024) {
            std::thread::yield_now();
        }
        std::hint::spin_loop();
    }
    let helper_failed = team.panicked.load(Ordering::Acquire);
    let message = if failure.is_some() || helper_failed {
        team.message
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .take()
    } else {
        None
    };
    if let Some(e) = failure {
        std::panic::resume_unwind(e);
    }
    if helper_failed {
        panic!(
            "{}",
            message.unwrap_or_else(|| "a parallel chunk panicked".into())
        );
    }
}

/// `f(0)`, …, `f(n − 1)` by [`run`], in index order.
pub(crate) fn map<T: Send>(n: usize, f: impl Fn(usize) -> T + Sync) -> Vec<T> {
    let out = Slots::new(n);
    run(n, &|k| out.put(k, f(k)));
    out.into_vec()
}

/// `(0..n).map(f)` collected, by [`run`] in chunks of `block` indices (each value computed
/// on its own: the same values on any number of threads).
pub(crate) fn collect<T: Send>(n: usize, block: usize, f: impl Fn(usize) -> T + Sync) -> Vec<T> {
    let mut out = Vec::new();
    collect_into(&mut out, n, block, f);
    out
}

/// [`collect`]'s values appended to `out`, written in place.
pub(crate) fn collect_into<T: Send>(
    out: &mut Vec<T>,
    n: usize,
    block: usize,
    f: impl Fn(usize) -> T + Sync,
) {
    out.reserve(n);
    let old = out.len();
    let blocks = Blocks::new(&mut out.spare_capacity_mut()[..n], block);
    run(blocks.count(), &|k| {
        // SAFETY: block k by chunk k alone.
        for (i, o) in unsafe { blocks.get(k) }.iter_mut().enumerate() {
            o.write(f(k * block + i));
        }
    });
    // SAFETY: every one of the n elements was written (all chunks ran, or `run` panicked
    // before this line and the vector keeps its old length).
    unsafe { out.set_len(old + n) };
}

/// [`collect`] of pairs, unzipped: the first and the second values, each in index order.
pub(crate) fn collect_unzip<A: Send, B: Send>(
    n: usize,
    block: usize,
    f: impl Fn(usize) -> (A, B) + Sync,
) -> (Vec<A>, Vec<B>) {
    let (mut a, mut b) = (Vec::with_capacity(n), Vec::with_capacity(n));
    {
        let ba = Blocks::new(&mut a.spare_capacity_mut()[..n], block);
        let bb = Blocks::new(&mut b.spare_capacity_mut()[..n], block);
        run(ba.count(), &|k| {
            // SAFETY: block k by chunk k alone.
            let (ba, bb) = unsafe { (ba.get(k), bb.get(k)) };
            for (i, (x, y)) in ba.iter_mut().zip(bb.iter_mut()).enumerate() {
                let (p, q) = f(k * block + i);
                x.write(p);
                y.write(q);
            }
        });
    }
    // SAFETY: as in collect_into, for both.
    unsafe {
        a.set_len(n);
        b.set_len(n);
    }
    (a, b)
}

/// `f(i, &mut v[i])` for every element, by [`run`] in chunks of `block` elements.
pub(crate) fn each_mut<T: Send>(v: &mut [T], block: usize, f: impl Fn(usize, &mut T) + Sync) {
    let blocks = Blocks::new(v, block);
    run(blocks.count(), &|k| {
        // SAFETY: block k by chunk k alone.
        for (i, x) in unsafe { blocks.get(k) }.iter_mut().enumerate() {
            f(k * block + i, x);
        }
    });
}

/// `f(item)` for every item of `items` by [`run`] (one chunk per item).
pub(crate) fn each<T: Send>(items: Vec<T>, f: impl Fn(T) + Sync) {
    let slots = Slots {
        v: items
            .into_iter()
            .map(|t| UnsafeCell::new(Some(t)))
            .collect(),
    };
    let slots = &slots;
    // SAFETY: chunk k alone takes item k.
    run(slots.v.len(), &|k| {
        f(unsafe { (*slots.v[k].get()).take() }.expect("once"))
    });
}

/// One result slot per chunk, each written by its chunk alone.
struct Slots<T> {
    v: Vec<UnsafeCell<Option<T>>>,
}

// SAFETY: slot k is written only by chunk k, which runs once; read after the loop.
unsafe impl<T: Send> Sync for Slots<T> {}

impl<T> Slots<T> {
    fn new(n: usize) -> Self {
        Slots {
            v: (0..n).map(|_| UnsafeCell::new(None)).collect(),
        }
    }

    fn put(&self, k: usize, value: T) {
        // SAFETY: chunk k alone writes slot k (see the Sync impl).
        unsafe { *self.v[k].get() = Some(value) };
    }

    fn into_vec(self) -> Vec<T> {
        self.v
            .into_iter()
            .map(|c| c.into_inner().expect("every chunk ran"))
            .collect()
    }
}

/// A mutable slice cut into blocks of `len` elements (the last one shorter) that the chunks
/// of one [`run`] take, block k by chunk k.
pub(crate) struct Blocks<'a, T> {
    ptr: *mut T,
    total: usize,
    len: usize,
    _slice: std::marker::PhantomData<&'a mut [T]>,
}

// SAFETY: distinct blocks are disjoint; `get`'s contract gives each block to one chunk.
unsafe impl<T: Send> Sync for Blocks<'_, T> {}

impl<'a, T> Blocks<'a, T> {
    pub(crate) fn new(slice: &'a mut [T], len: usize) -> Self {
        Blocks {
            ptr: slice.as_mut_ptr(),
            total: slice.len(),
            len: len.max(1),
            _slice: std::marker::PhantomData,
        }
    }

    /// The number of blocks.
    pub(crate) fn count(&self) -> usize {
        self.total.div_ceil(self.len)
    }

    /// Block `k`.
    ///
    /// # Safety
    /// Each block is taken at most once while the slice is borrowed (one chunk per block).
    #[allow(clippy::mut_from_ref)]
    pub(crate) unsafe fn get(&self, k: usize) -> &'a mut [T] {
        let lo = (k * self.len).min(self.total);
        let hi = ((k + 1) * self.len).min(self.total);
        // SAFETY: in bounds; disjoint from every other block (the caller's contract).
        unsafe { std::slice::from_raw_parts_mut(self.ptr.add(lo), hi - lo) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pool(threads: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
    }

    #[test]
    fn the_word_packs_and_unpacks() {
        let w = Word {
            epoch: 0xdead_beef,
            allowed: 3,
            next: 4000,
            n: 4095,
        };
        assert_eq!(Word::unpack(w.pack()), w);
    }

    #[test]
    fn every_chunk_runs_once_on_any_thread_count() {
        for threads in [1, 2, 3, 4] {
            pool(threads).install(|| {
                for n in [0, 1, 2, 7, 64, 1000] {
                    let count: Vec<AtomicUsize> = (0..n).map(|_| AtomicUsize::new(0)).collect();
                    for _ in 0..50 {
                        run(n, &|k| {
                            count[k].fetch_add(1, Ordering::Relaxed);
                        });
                    }
                    assert!(count.iter().all(|c| c.load(Ordering::Relaxed) == 50));
                }
            });
        }
    }

    #[test]
    fn map_keeps_the_order_and_blocks_cover_the_slice() {
        pool(2).install(|| {
            let squares = map(300, |k| k * k);
            assert_eq!(squares, (0..300).map(|k| k * k).collect::<Vec<_>>());
            let mut v = vec![0usize; 1001];
            let blocks = Blocks::new(&mut v, 64);
            assert_eq!(blocks.count(), 16);
            run(blocks.count(), &|k| {
                // SAFETY: block k by chunk k alone.
                for (i, x) in unsafe { blocks.get(k) }.iter_mut().enumerate() {
                    *x = k * 64 + i;
                }
            });
            assert_eq!(v, (0..1001).collect::<Vec<_>>());
        });
    }

    #[test]
    fn a_nested_or_concurrent_loop_runs_on_its_caller() {
        pool(2).install(|| {
            let inner: Vec<Vec<usize>> = map(8, |k| map(5, |j| k * 10 + j));
            for (k, row) in inner.iter().enumerate() {
                assert_eq!(row, &(0..5).map(|j| k * 10 + j).collect::<Vec<_>>());
            }
        });
        // Two threads starting loops at once (cargo's test threads do): each finishes.
        std::thread::scope(|s| {
            for t in 0..2 {
                s.spawn(move || {
                    pool(2).install(|| {
                        for _ in 0..200 {
                            let v = map(40, |k| k + t);
                            assert_eq!(v, (0..40).map(|k| k + t).collect::<Vec<_>>());
                        }
                    })
                });
            }
        });
    }

    #[test]
    fn a_panicking_chunk_panics_the_caller_after_the_others_finish() {
        pool(2).install(|| {
            let finished = AtomicUsize::new(0);
            let r = catch_unwind(AssertUnwindSafe(|| {
                run(64, &|k| {
                    if k == 5 {
                        panic!("chunk five failed");
                    }
                    std::thread::sleep(Duration::from_micros(50));
                    finished.fetch_add(1, Ordering::Relaxed);
                })
            }));
            let e = r.expect_err("the loop must panic");
            assert!(panic_message(&e).contains("chunk five failed"));
            // The team serves the next loop.
            assert_eq!(map(10, |k| k), (0..10).collect::<Vec<_>>());
        });
    }
}
