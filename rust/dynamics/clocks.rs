//! The sample times of the parts' laws, asked for as a run goes: sample `i` of a clock of
//! `period` and `phase` is at `phase + i · period` (in float64, `i` counted from 0, those
//! before the run's start skipped), found from `t` by a division and a step or two, so that a
//! 1 kHz law over 10⁶ s needs no list of its 10⁹ times. The times are the ones a list would
//! hold, bit for bit: runs and batch rows end their steps on the same floats.

use super::part::Sampling;

/// The clocks of a model's sampled parts, each with its part's index among them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Clocks {
    clocks: Vec<(Sampling, usize)>,
}

impl Clocks {
    /// The clocks of `samplings` (a part's index is its place among them); a part whose
    /// period is not positive and finite, or whose phase is not finite, is never sampled.
    pub fn of(samplings: impl IntoIterator<Item = Option<Sampling>>) -> Self {
        let clocks = (samplings.into_iter().enumerate())
            .filter_map(|(k, s)| s.map(|s| (s, k)))
            .filter(|(s, _)| s.period > 0.0 && s.period.is_finite() && s.phase.is_finite())
            .collect();
        Self { clocks }
    }

    /// Whether no part is ever sampled.
    pub fn is_empty(&self) -> bool {
        self.clocks.is_empty()
    }

    /// The first sample time of any clock at or after `t` (infinity if none).
    #[inline]
    pub fn next_from(&self, t: f64) -> f64 {
        (self.clocks.iter())
            .map(|(s, _)| first_from(*s, t))
            .fold(f64::INFINITY, f64::min)
    }

    /// The parts (their indices, in order) with a sample time exactly at `t`.
    pub fn at(&self, t: f64) -> impl Iterator<Item = usize> + '_ {
        (self.clocks.iter())
            .filter(move |(s, _)| first_from(*s, t) == t)
            .map(|&(_, k)| k)
    }
}

/// Sample `i` of `s`: `phase + i · period`, as a list laid out one by one held it.
#[inline(always)]
fn time(s: Sampling, i: f64) -> f64 {
    s.phase + i * s.period
}

/// The first sample time of `s` at or after `t` and at or after 0. `time` grows with `i`
/// (each operation rounds monotonically), so the division's guess is corrected by stepping
/// down while the time before it still qualifies and up while it does not; where consecutive
/// `i` give the same float (a period under its spacing) the steps double, so the walk stays
/// short whatever the period.
#[inline]
fn first_from(s: Sampling, t: f64) -> f64 {
    let lo = t.max(0.0);
    let mut i = ((lo - s.phase) / s.period).ceil().max(0.0);
    if !i.is_finite() {
        return f64::INFINITY;
    }
    // down: the least i whose time is at or after `lo` (a bracket, then bisection down to adjacent floats)
    if i > 0.0 && time(s, i - 1.0) >= lo {
        let mut step = 1.0;
        let mut below = i - 1.0;
        while below > 0.0 && time(s, below) >= lo {
            step *= 2.0;
            below = (i - step).max(0.0);
        }
        if time(s, below) >= lo {
            return time(s, below);
        }
        // time(below) < lo <= time(i - 1)
        let mut high = i - 1.0;
        loop {
            let mid = (below + (high - below) / 2.0).floor();
            if mid <= below || mid >= high {
                break;
            }
            match time(s, mid) >= lo {
                true => high = mid,
                false => below = mid,
            }
        }
        return time(s, high);
    }
    // up: the first i whose time reaches `lo`
    let mut step = 1.0;
    let mut low = i;
    while time(s, i) < lo {
        low = i;
        i += step;
        step *= 2.0;
        if !i.is_finite() {
            return f64::INFINITY;
        }
    }
    // time(low) < lo <= time(i), or i never moved
    loop {
        let mid = (low + (i - low) / 2.0).floor();
        if mid <= low || mid >= i {
            break;
        }
        match time(s, mid) >= lo {
            true => i = mid,
            false => low = mid,
        }
    }
    time(s, i)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sample times a list laid out one by one holds in `[0, t_end]`.
    fn listed(s: Sampling, t_end: f64) -> Vec<f64> {
        let mut out = Vec::new();
        let mut i = 0.0_f64;
        loop {
            let t = time(s, i);
            if t > t_end {
                return out;
            }
            if t >= 0.0 {
                out.push(t);
            }
            i += 1.0;
        }
    }

    /// The times the clock gives, walked from 0 as a driver does (each the first at or after
    /// the float just past the last).
    fn walked(c: &Clocks, t_end: f64) -> Vec<f64> {
        let mut out = Vec::new();
        let mut t = c.next_from(0.0);
        while t <= t_end {
            out.push(t);
            t = c.next_from(t.next_up());
        }
        out
    }

    #[test]
    fn the_clock_gives_the_times_a_list_holds_bit_for_bit() {
        for (period, phase, t_end) in [
            (0.25, 0.1, 10.0),
            (0.1, 0.0, 50.0),
            (1e-3, 0.0, 3.0),
            (0.3, -1.0, 20.0),
            (1.0 / 3.0, 2.5, 40.0),
            (7e-4, 1e3, 1e3 + 1.0),
        ] {
            let s = Sampling { period, phase };
            let c = Clocks::of([Some(s)]);
            let list = listed(s, t_end);
            assert!(list.len() > 5);
            let walk = walked(&c, t_end);
            assert_eq!(
                walk.iter().map(|t| t.to_bits()).collect::<Vec<_>>(),
                list.iter().map(|t| t.to_bits()).collect::<Vec<_>>(),
                "period {period}, phase {phase}"
            );
            for &t in &list {
                assert_eq!(c.at(t).collect::<Vec<_>>(), vec![0], "{t}");
                assert_eq!(c.at(t.next_up()).count(), 0, "{t}");
            }
        }
    }

    #[test]
    fn a_far_sample_time_is_found_without_walking_there() {
        // the 10⁹-th time of a 1 kHz clock: found at once, and it is what i · period gives
        let s = Sampling {
            period: 1e-3,
            phase: 0.0,
        };
        let c = Clocks::of([Some(s)]);
        let t = 1e9 * 1e-3;
        assert_eq!(c.next_from(t), t);
        assert_eq!(c.next_from(t.next_up()), (1e9 + 1.0) * 1e-3);
        // a period far below the times' spacing: the first time at or after `t`, found
        let tiny = Clocks::of([Some(Sampling {
            period: 5e-324,
            phase: 0.0,
        })]);
        // (every float near 1e-17 is some i · 2⁻¹⁰⁷⁴), and none where i would leave float64
        assert_eq!(tiny.next_from(1e-17), 1e-17);
        assert_eq!(tiny.next_from(1e-17f64.next_up()), 1e-17f64.next_up());
        assert_eq!(tiny.next_from(1.0), f64::INFINITY);
    }

    #[test]
    fn clocks_merge_and_name_their_parts() {
        let c = Clocks::of([
            Some(Sampling {
                period: 0.5,
                phase: 0.0,
            }),
            None,
            Some(Sampling {
                period: 0.75,
                phase: 0.0,
            }),
            Some(Sampling {
                period: f64::INFINITY,
                phase: 0.0,
            }),
        ]);
        assert_eq!(
            walked(&c, 3.0),
            vec![0.0, 0.5, 0.75, 1.0, 1.5, 2.0, 2.25, 2.5, 3.0]
        );
        assert_eq!(c.at(1.5).collect::<Vec<_>>(), vec![0, 2]);
        assert_eq!(c.at(0.5).collect::<Vec<_>>(), vec![0]);
        assert!(Clocks::of([None]).is_empty());
    }
}
