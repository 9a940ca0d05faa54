//! Timing renders so their ratios mean something on a shared machine:
//! a render on one thread is timed by that thread's CPU time, which other
//! processes disturb far less than the wall clock (they still share its
//! caches and memory bandwidth); every setting is timed once per
//! repetition, the settings interleaved, so a slow spell of the machine
//! slows all of them alike; a setting's
//! cost is the median over repetitions of its time divided by the
//! default's time in the same repetition, with the smallest and largest
//! such ratio as its spread.

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
}
