//! Counter-based noise for the sensors: a draw is a pure function of a key and a counter, so
//! that sample `k` of a sensor draws the same noise whatever the run's length, the number of
//! runs in a study, the threads or the chunks (DESIGN.md §14). The key is the run's seed and a
//! stream (which part, which sensor); the counter is the sample's index and a block number.
//!
//! The generator is Philox4x64-10 (Salmon, Moraes, Dror & Shaw, "Parallel random numbers: as
//! easy as 1, 2, 3", SC'11), the one `numpy.random.Philox` implements: ten rounds of two
//! 64 × 64 → 128-bit multiplications and a Weyl sequence of keys. Its four 64-bit outputs make
//! four standard normal deviates by the Box–Muller transform (Box & Muller, *Ann. Math.
//! Statist.* 29, 1958).

use nalgebra::Vector3;

/// Philox4x64's multipliers and key increments (Salmon et al., 2011, Table 2; Random123).
const MULTIPLIERS: [u64; 2] = [0xD2E7_470E_E14C_6C93, 0xCA5A_8263_9512_1157];
const WEYL: [u64; 2] = [0x9E37_79B9_7F4A_7C15, 0xBB67_AE85_84CA_A73B];
/// `2^−53`: a 53-bit integer times it is a float64 in `[0, 1)` without rounding.
const UNIT: f64 = 1.0 / 9_007_199_254_740_992.0;

/// Philox4x64-10 of `counter` under `key`: four 64-bit words, uniform and independent over
/// counters and keys.
///
/// # Example
/// ```
/// use dzhanibekov::dynamics::control::philox4x64;
/// // Random123's known answer for a zero counter and key
/// assert_eq!(philox4x64([0; 4], [0; 2])[0], 0x16554d9eca36314c);
/// ```
#[inline]
pub fn philox4x64(counter: [u64; 4], key: [u64; 2]) -> [u64; 4] {
    let (mut c, mut k) = (counter, key);
    for round in 0..10 {
        if round > 0 {
            k = [k[0].wrapping_add(WEYL[0]), k[1].wrapping_add(WEYL[1])];
        }
        let p0 = u128::from(MULTIPLIERS[0]) * u128::from(c[0]);
        let p1 = u128::from(MULTIPLIERS[1]) * u128::from(c[2]);
        let (hi0, lo0) = ((p0 >> 64) as u64, p0 as u64);
        let (hi1, lo1) = ((p1 >> 64) as u64, p1 as u64);
        c = [hi1 ^ c[1] ^ k[0], lo1, hi0 ^ c[3] ^ k[1], lo0];
    }
    c
}

/// A stream of normal deviates indexed by sample and block (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Noise {
    key: [u64; 2],
}

impl Noise {
    /// The stream `stream` of the run seeded with `seed`.
    pub fn new(seed: u64, stream: u64) -> Self {
        Self {
            key: [seed, stream],
        }
    }

    /// Four independent standard normal deviates, block `block` of sample `sample`.
    #[inline]
    pub fn normals(&self, sample: u64, block: u64) -> [f64; 4] {
        let [a, b, c, d] = philox4x64([sample, block, 0, 0], self.key);
        let [z0, z1] = box_muller(a, b);
        let [z2, z3] = box_muller(c, d);
        [z0, z1, z2, z3]
    }

    /// A vector of three independent standard normal deviates (block `block` of sample
    /// `sample`; the fourth deviate is not used).
    #[inline]
    pub fn vector(&self, sample: u64, block: u64) -> Vector3<f64> {
        let [x, y, z, _] = self.normals(sample, block);
        Vector3::new(x, y, z)
    }
}

/// Two standard normal deviates from two uniform words: `r = √(−2 ln u₁)` with `u₁` in
/// `(0, 1]` (never 0), times the cosine and sine of `2π u₂`.
#[inline]
fn box_muller(a: u64, b: u64) -> [f64; 2] {
    let u1 = ((a >> 11) as f64 + 1.0) * UNIT;
    let u2 = (b >> 11) as f64 * UNIT;
    let r = (-2.0 * u1.ln()).sqrt();
    let (s, c) = (std::f64::consts::TAU * u2).sin_cos();
    [r * c, r * s]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn philox_gives_random123s_known_answers() {
        // Random123 1.14, kat_vectors, philox4x64 with 10 rounds; numpy.random.Philox gives
        // the same words for these counters and keys
        let max = u64::MAX;
        let cases = [
            (
                [0; 4],
                [0; 2],
                [
                    0x16554d9eca36314c,
                    0xdb20fe9d672d0fdc,
                    0xd7e772cee186176b,
                    0x7e68b68aec7ba23b,
                ],
            ),
            (
                [max; 4],
                [max; 2],
                [
                    0x87b092c3013fe90b,
                    0x438c3c67be8d0224,
                    0x9cc7d7c69cd777b6,
                    0xa09caebf594f0ba0,
                ],
            ),
            (
                [
                    0x243f6a8885a308d3,
                    0x13198a2e03707344,
                    0xa4093822299f31d0,
                    0x082efa98ec4e6c89,
                ],
                [0x452821e638d01377, 0xbe5466cf34e90c6c],
                [
                    0xa528f45403e61d95,
                    0x38c72dbd566e9788,
                    0xa5a1610e72fd18b5,
                    0x57bd43b5e52b7fe6,
                ],
            ),
        ];
        for (counter, key, expected) in cases {
            assert_eq!(philox4x64(counter, key), expected);
        }
    }

    /// `count` deviates of one stream, four per sample.
    fn deviates(noise: &Noise, count: u64) -> Vec<f64> {
        (0..count / 4).flat_map(|k| noise.normals(k, 0)).collect()
    }

    #[test]
    fn the_deviates_are_standard_normal() {
        // moments and the mass within one and two standard deviations, each within five of
        // its own standard errors of the normal law's
        let z = deviates(&Noise::new(2024, 7), 400_000);
        let n = z.len() as f64;
        let mean = z.iter().sum::<f64>() / n;
        let var = z.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
        let kurtosis = z.iter().map(|v| (v - mean).powi(4)).sum::<f64>() / n / (var * var);
        assert!(mean.abs() < 5.0 / n.sqrt(), "{mean}");
        assert!((var - 1.0).abs() < 5.0 * (2.0 / n).sqrt(), "{var}");
        assert!(
            (kurtosis - 3.0).abs() < 5.0 * (96.0 / n).sqrt(),
            "{kurtosis}"
        );
        // P(|Z| < 1) = erf(1/√2), P(|Z| < 2) = erf(√2)
        for (bound, p) in [
            (1.0, 0.682_689_492_137_085_9),
            (2.0, 0.954_499_736_103_641_6),
        ] {
            let inside = z.iter().filter(|v| v.abs() < bound).count() as f64 / n;
            assert!(
                (inside - p).abs() < 5.0 * (p * (1.0 - p) / n).sqrt(),
                "{inside}"
            );
        }
    }

    #[test]
    fn a_draw_is_a_function_of_its_key_and_counter_only() {
        let a = Noise::new(1, 2);
        // the same draw, whenever and however often it is asked
        assert_eq!(a.normals(1000, 3), a.normals(1000, 3));
        assert_eq!(a.normals(1000, 3), Noise::new(1, 2).normals(1000, 3));
        // another seed, stream, sample or block draws something else
        for other in [
            Noise::new(2, 2).normals(1000, 3),
            Noise::new(1, 3).normals(1000, 3),
            a.normals(1001, 3),
            a.normals(1000, 4),
        ] {
            assert!(other.iter().zip(a.normals(1000, 3)).all(|(x, y)| *x != y));
        }
    }

    #[test]
    fn neighbouring_streams_and_samples_are_uncorrelated() {
        let n = 100_000u64;
        let x: Vec<f64> = (0..n).map(|k| Noise::new(9, 0).normals(k, 0)[0]).collect();
        for y in [
            (0..n)
                .map(|k| Noise::new(9, 1).normals(k, 0)[0])
                .collect::<Vec<_>>(),
            (0..n)
                .map(|k| Noise::new(9, 0).normals(k + 1, 0)[0])
                .collect(),
            (0..n).map(|k| Noise::new(9, 0).normals(k, 1)[0]).collect(),
            (0..n).map(|k| Noise::new(9, 0).normals(k, 0)[1]).collect(),
        ] {
            let r = x.iter().zip(&y).map(|(a, b)| a * b).sum::<f64>() / n as f64;
            assert!(r.abs() < 5.0 / (n as f64).sqrt(), "{r}");
        }
    }
}
