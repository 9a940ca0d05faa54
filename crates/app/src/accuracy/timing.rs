//! Timing renders so their ratios mean something on a shared machine:
//! a render on one thread is timed by that thread's CPU time, which other
//! processes disturb far less than the wall clock (they still share its
//! caches and memory bandwidth); every setting is timed once per
//! repetition, in an order drawn afresh for each repetition
//! ([`shuffled`]), so a slow spell of the machine slows all of them alike
//! and no setting always runs first (warmest or coldest); the cost of one
//! setting against another is the median over repetitions of the ratio of
//! their times in the same repetition, with the smallest and largest such
//! ratio as its spread.

use cpu_time::ThreadTime;

/// A frame shorter than this is repeated within its measurement, and the
/// time divided by the count, so a sub-millisecond frame is not timed by
/// the clock's resolution alone.
pub const MIN_MEASUREMENT_SECONDS: f64 = 0.02;

/// CPU seconds of the calling thread per run of `work`, repeated until
/// the runs take at least [`MIN_MEASUREMENT_SECONDS`]. `work` must run on
/// the calling thread (a one-thread rayon pool's `install` does).
pub fn seconds_per_run(mut work: impl FnMut()) -> f64 {
    let start = ThreadTime::now();
    let mut runs = 0u32;
    loop {
        work();
        runs += 1;
        let elapsed = start.elapsed().as_secs_f64();
        if elapsed >= MIN_MEASUREMENT_SECONDS {
            return elapsed / f64::from(runs);
        }
    }
}

/// `0..n` in a random order, drawn afresh on every call: a Fisher–Yates
/// shuffle driven by SplitMix64 from std's per-process random hasher
/// keys and a call counter (an order, not a secret, needs no more).
pub fn shuffled(n: usize) -> Vec<usize> {
    use std::hash::{BuildHasher, RandomState};
    use std::sync::atomic::{AtomicU64, Ordering};
    static CALLS: AtomicU64 = AtomicU64::new(0);
    let call = CALLS.fetch_add(1, Ordering::Relaxed);
    let mut state = RandomState::new().hash_one(call);
    let mut next = move || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    let mut order: Vec<usize> = (0..n).collect();
    for i in (1..n).rev() {
        order.swap(i, (next() % (i as u64 + 1)) as usize);
    }
    order
}

/// A median with the smallest and largest value it was taken over.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Spread {
    pub median: f64,
    pub min: f64,
    pub max: f64,
}

impl Spread {
    /// The spread of `values` (not empty).
    pub fn of(values: &[f64]) -> Spread {
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        let n = sorted.len();
        let median = if n % 2 == 1 {
            sorted[n / 2]
        } else {
            (sorted[n / 2 - 1] + sorted[n / 2]) / 2.0
        };
        Spread {
            median,
            min: sorted[0],
            max: sorted[n - 1],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_median_of_an_even_count_is_the_middle_pair_mean() {
        let spread = Spread::of(&[4.0, 1.0, 3.0, 2.0]);
        assert_eq!(
            spread,
            Spread {
                median: 2.5,
                min: 1.0,
                max: 4.0
            }
        );
        assert_eq!(Spread::of(&[3.0, 9.0, 1.0]).median, 3.0);
    }

    #[test]
    fn every_order_is_a_permutation_and_the_orders_vary() {
        let orders: Vec<Vec<usize>> = (0..20).map(|_| shuffled(9)).collect();
        for order in &orders {
            let mut sorted = order.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, (0..9).collect::<Vec<_>>());
        }
        let firsts: std::collections::BTreeSet<usize> = orders.iter().map(|o| o[0]).collect();
        // 20 draws of 9 first places all alike: chance 9^-19.
        assert!(firsts.len() > 1, "{orders:?}");
        assert_eq!(shuffled(0), Vec::<usize>::new());
    }
}
