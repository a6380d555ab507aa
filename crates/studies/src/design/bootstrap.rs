//! The bootstrap over records (Efron & Tibshirani 1993): records resampled with replacement,
//! each replicate refitted; a seeded SplitMix64 stream per replicate (Steele, Lea & Flood
//! 2014), so the replicates, and the band, do not depend on the number of threads.

use rayon::prelude::*;

/// SplitMix64: x ← x + 0x9E3779B97F4A7C15, output mixed by two xor-shift-multiplies.
#[derive(Clone, Debug)]
pub(crate) struct SplitMix64(pub u64);

impl SplitMix64 {
    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// An index in 0..n (n > 0): ⌊n·u/2⁶⁴⌋ (bias below n/2⁶⁴).
    pub fn below(&mut self, n: usize) -> usize {
        ((self.next_u64() as u128 * n as u128) >> 64) as usize
    }

    /// The generator of replicate `k` of a bootstrap seeded with `seed`.
    pub fn replicate(seed: u64, k: usize) -> Self {
        let mut base = SplitMix64(seed);
        let mut s = SplitMix64(base.next_u64() ^ (k as u64).wrapping_mul(0xD1B5_4A32_D192_ED03));
        s.next_u64();
        s
    }
}

/// The q-quantile of sorted values, linearly interpolated (Hyndman & Fan type 7):
/// h = (n − 1)q, x₍⌊h⌋₎ + (h − ⌊h⌋)(x₍⌊h⌋₊₁₎ − x₍⌊h⌋₎); NaN when empty.
pub(crate) fn quantile(sorted: &[f64], q: f64) -> f64 {
    match sorted.len() {
        0 => f64::NAN,
        1 => sorted[0],
        n => {
            let h = (n - 1) as f64 * q.clamp(0.0, 1.0);
            let i = (h.floor() as usize).min(n - 2);
            sorted[i] + (h - i as f64) * (sorted[i + 1] - sorted[i])
        }
    }
}

/// `replicates` resamplings of `records` indices with replacement, each given to `fit`;
/// the results in replicate order (`None`: the replicate could not be fitted).
pub(crate) fn resample<T: Send>(
    records: usize,
    replicates: usize,
    seed: u64,
    fit: impl Fn(&[usize]) -> Option<T> + Sync,
) -> Vec<Option<T>> {
    (0..replicates)
        .into_par_iter()
        .map(|k| {
            let mut rng = SplitMix64::replicate(seed, k);
            let pick: Vec<usize> = (0..records).map(|_| rng.below(records)).collect();
            fit(&pick)
        })
        .collect()
}
