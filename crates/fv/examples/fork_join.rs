//! What one short parallel loop costs on two threads: rayon's fork-join, called from inside
//! its pool as the fluid's step calls it, against a two-thread team whose helper waits by
//! spinning on an atomic counter (docs/speed.md, seventh pass). The loop is x ← 1.0001 x + y/2
//! over N doubles, repeated, with GAP nanoseconds of sequential work between two loops (the
//! step's sequential stretches, during which an idle rayon worker goes to sleep). Prints the
//! wall microseconds per loop for 1 and 2 threads, both ways (the team on 1 thread is the
//! loop alone).
//!
//! `cargo run --release -p fv --example fork_join -- [N] [GAP_NS] [LOOPS]`
//! (default 110000 0 20000; the 48³ cavity has 110,592 cells).

use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// One loop over `x` and `y` (the same arithmetic both ways).
fn kernel(x: &mut [f64], y: &[f64]) {
    for (x, y) in x.iter_mut().zip(y) {
        *x = 1.0001 * *x + 0.5 * *y;
    }
}

/// Busy work for `ns` nanoseconds (the sequential stretch between two loops).
fn gap(ns: u64) {
    let t = Instant::now();
    while (t.elapsed().as_nanos() as u64) < ns {
        std::hint::spin_loop();
    }
}

/// Microseconds per loop with rayon on `threads` threads, from inside the pool.
fn rayon_loop(n: usize, threads: usize, gap_ns: u64, loops: usize) -> f64 {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let y: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let mut x = vec![0.0; n];
    pool.install(|| {
        let t = Instant::now();
        for _ in 0..loops {
            x.par_chunks_mut(4096)
                .zip(y.par_chunks(4096))
                .for_each(|(x, y)| kernel(x, y));
            gap(gap_ns);
        }
        t.elapsed().as_secs_f64() / loops as f64 * 1e6
    })
}

/// Microseconds per loop with a two-thread team (`threads` 2) or the loop alone (1): the
/// helper owns the second half of x and waits for each loop's epoch by spinning.
fn team_loop(n: usize, threads: usize, gap_ns: u64, loops: usize) -> f64 {
    let y: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let mut x = vec![0.0; n];
    if threads == 1 {
        let t = Instant::now();
        for _ in 0..loops {
            kernel(&mut x, &y);
            gap(gap_ns);
        }
        return t.elapsed().as_secs_f64() / loops as f64 * 1e6;
    }
    let (epoch, done) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let (x0, x1) = x.split_at_mut(n / 2);
    let (y0, y1) = y.split_at(n / 2);
    std::thread::scope(|s| {
        s.spawn(|| {
            for e in 1..=loops {
                while epoch.load(Ordering::Acquire) < e {
                    std::hint::spin_loop();
                }
                kernel(x1, y1);
                done.store(e, Ordering::Release);
            }
        });
        let t = Instant::now();
        for e in 1..=loops {
            epoch.store(e, Ordering::Release);
            kernel(x0, y0);
            while done.load(Ordering::Acquire) < e {
                std::hint::spin_loop();
            }
            gap(gap_ns);
        }
        t.elapsed().as_secs_f64() / loops as f64 * 1e6
    })
}

fn main() {
    let arg = |i: usize, d: u64| {
        std::env::args()
            .nth(i)
            .and_then(|a| a.parse().ok())
            .unwrap_or(d)
    };
    let (n, gap_ns, loops) = (arg(1, 110_000) as usize, arg(2, 0), arg(3, 20_000) as usize);
    println!("{n} doubles per loop, {gap_ns} ns between loops, {loops} loops: µs per loop");
    for threads in [1, 2] {
        let r = rayon_loop(n, threads, gap_ns, loops);
        let t = team_loop(n, threads, gap_ns, loops);
        println!("{threads} thread(s): rayon {r:8.2}   spinning team {t:8.2}");
    }
}
