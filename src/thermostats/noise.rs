//! The random numbers of the stochastic thermostats: ChaCha20 seeded from a
//! `u64` on its own stream, [`THERMOSTAT_STREAM`] (a scene's random initial
//! state draws from stream 0 of the same seed, so the two never share
//! numbers), drawn in a fixed order (rotor by rotor, axis by axis, one thread)
//! so that a run is reproducible from its seed whatever the number of
//! threads. A checkpoint stores the position in the stream, so a restart
//! continues with the same numbers. [`HeatNoise`] is what a stochastic
//! thermostat records: its noise and the heat it has put into the rotors.

use crate::thermostat_hook::{BadCheckpoint, ThermostatState};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha20Rng;
use rand_distr::{Distribution, StandardNormal};

/// The ChaCha20 stream of the thermostats' numbers.
pub const THERMOSTAT_STREAM: u64 = 1;

/// Bits of the stream position stored in the low checkpoint value (an exact
/// integer in an `f64`); the position has 68 bits, so the high value holds
/// at most 16.
const LOW_BITS: u32 = 52;

/// A seeded stream of random numbers whose position can be saved.
#[derive(Clone, Debug)]
pub struct Noise {
    rng: ChaCha20Rng,
}

impl Noise {
    /// The number of values [`Noise::write_checkpoint`] appends.
    pub const CHECKPOINT_LEN: usize = 2;

    /// The stream of `seed`, at its start.
    pub fn new(seed: u64) -> Self {
        let mut rng = ChaCha20Rng::seed_from_u64(seed);
        rng.set_stream(THERMOSTAT_STREAM);
        Noise { rng }
    }

    /// A standard normal number.
    pub fn normal(&mut self) -> f64 {
        self.rng.sample(StandardNormal)
    }

    /// A number from `distribution`.
    pub fn sample(&mut self, distribution: &impl Distribution<f64>) -> f64 {
        distribution.sample(&mut self.rng)
    }

    /// Appends the position in the stream (in 32-bit words) as two exact
    /// integers: the bits above the lowest 52, then those 52.
    pub fn write_checkpoint(&self, out: &mut Vec<f64>) {
        let position = self.rng.get_word_pos();
        out.push((position >> LOW_BITS) as f64);
        out.push((position & ((1u128 << LOW_BITS) - 1)) as f64);
    }

    /// Moves to the position written by [`Noise::write_checkpoint`]
    /// (`data` holds exactly [`Noise::CHECKPOINT_LEN`] values).
    pub fn read_checkpoint(&mut self, data: &[f64]) -> Result<(), BadCheckpoint> {
        let word = |x: f64, bits: u32| {
            (x.is_finite() && x >= 0.0 && x.fract() == 0.0 && x < (1u64 << bits) as f64)
                .then_some(x as u128)
        };
        match data {
            [high, low] => match (word(*high, 68 - LOW_BITS), word(*low, LOW_BITS)) {
                (Some(high), Some(low)) => {
                    self.rng.set_word_pos((high << LOW_BITS) | low);
                    Ok(())
                }
                _ => Err(BadCheckpoint(format!(
                    "thermostat noise position must be two integers, got {high} and {low}"
                ))),
            },
            _ => Err(BadCheckpoint(format!(
                "thermostat noise position must be 2 values, got {}",
                data.len()
            ))),
        }
    }
}

/// The state of a stochastic thermostat (Bussi, Langevin): its noise and
/// the kinetic energy it has put into the rotors, `heat`; its share of the
/// conserved energy is `-heat`.
#[derive(Clone, Debug)]
pub struct HeatNoise {
    seed: u64,
    /// The stream of the thermostat's numbers.
    pub noise: Noise,
    /// Kinetic energy the thermostat has put into the rotors.
    pub heat: f64,
}

impl HeatNoise {
    /// No heat, the stream of `seed` at its start.
    pub fn new(seed: u64) -> Self {
        HeatNoise {
            seed,
            noise: Noise::new(seed),
            heat: 0.0,
        }
    }

    /// Back to no heat and the start of the stream (at setup).
    pub fn reset(&mut self) {
        *self = HeatNoise::new(self.seed);
    }
}

impl ThermostatState for HeatNoise {
    /// Minus the heat put into the rotors.
    fn energy(&self) -> f64 {
        -self.heat
    }

    fn checkpoint_len(&self) -> usize {
        1 + Noise::CHECKPOINT_LEN
    }

    /// The heat, then the noise position.
    fn write_checkpoint(&self, out: &mut Vec<f64>) {
        out.push(self.heat);
        self.noise.write_checkpoint(out);
    }

    /// The heat must be finite.
    fn read_checkpoint(&mut self, data: &[f64]) -> Result<(), BadCheckpoint> {
        let (heat, noise) = data.split_at(1);
        if !heat[0].is_finite() {
            return Err(BadCheckpoint(format!(
                "thermostat heat must be finite, got {}",
                heat[0]
            )));
        }
        self.heat = heat[0];
        self.noise.read_checkpoint(noise)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A restored stream continues with exactly the numbers the original
    /// draws next; another seed draws others.
    #[test]
    fn restored_stream_continues_bit_for_bit() {
        let mut a = Noise::new(7);
        for _ in 0..13 {
            let _ = a.normal();
        }
        let mut saved = Vec::new();
        a.write_checkpoint(&mut saved);
        let mut b = Noise::new(7);
        b.read_checkpoint(&saved).expect("valid position");
        let next: Vec<u64> = (0..50).map(|_| a.normal().to_bits()).collect();
        let restored: Vec<u64> = (0..50).map(|_| b.normal().to_bits()).collect();
        assert_eq!(next, restored);
        let mut other = Noise::new(8);
        assert_ne!(other.normal().to_bits(), Noise::new(7).normal().to_bits());
        assert!(b.read_checkpoint(&[0.5, 1.0]).is_err());
        assert!(b.read_checkpoint(&[1.0]).is_err());
    }

    /// Positions beyond 2^52 words, where the low value alone would lose
    /// the high bits, and the last position of the stream (2^68 - 1) come
    /// back exactly from the two values; values outside their ranges
    /// (negative, the high one at 2^16, the low one at 2^52) are refused.
    #[test]
    fn positions_beyond_52_bits_round_trip() {
        let last = (1u128 << 68) - 1;
        for position in [
            (1u128 << 52) - 3,
            (1u128 << 52) + 5,
            (3u128 << 60) + 7,
            last,
        ] {
            let mut a = Noise::new(11);
            a.rng.set_word_pos(position);
            let mut saved = Vec::new();
            a.write_checkpoint(&mut saved);
            assert_eq!(saved.len(), Noise::CHECKPOINT_LEN);
            let mut b = Noise::new(11);
            b.read_checkpoint(&saved).expect("valid position");
            assert_eq!(b.rng.get_word_pos(), position, "{saved:?}");
        }
        let mut b = Noise::new(11);
        let largest_low = ((1u64 << 52) - 1) as f64;
        assert!(b.read_checkpoint(&[65535.0, largest_low]).is_ok());
        for bad in [
            [65536.0, 0.0],
            [0.0, 2f64.powi(52)],
            [-1.0, 0.0],
            [0.0, -1.0],
        ] {
            assert!(b.read_checkpoint(&bad).is_err(), "{bad:?}");
        }
    }

    /// The thermostat's stream is not the initial state's (stream 0 of the
    /// same seed).
    #[test]
    fn thermostat_stream_differs_from_stream_zero() {
        let mut zero = ChaCha20Rng::seed_from_u64(3);
        let first: f64 = zero.sample(StandardNormal);
        assert_ne!(first.to_bits(), Noise::new(3).normal().to_bits());
    }
}
