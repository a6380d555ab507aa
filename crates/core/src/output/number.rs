//! Numbers in the CSV files a run writes: the shortest text that reads back as the same f64
//! (Schubfach-style shortest round trip, the `zmij` crate), about a tenth of the cost of
//! `{:.12e}` and exact. NaN is written `NaN` and infinities `inf` / `-inf`, as `std::fmt`
//! writes them; `str::parse::<f64>` reads every form back.

use std::io::Write;

/// A formatter of f64 values: its buffer is reused for each number.
#[derive(Default)]
pub struct Numbers(zmij::Buffer);

impl Numbers {
    /// A formatter with an empty buffer.
    pub fn new() -> Self {
        Self::default()
    }

    /// The shortest text that parses back to `x` bit for bit (NaN: `NaN`).
    pub fn format(&mut self, x: f64) -> &str {
        self.0.format(x)
    }

    /// Writes `x` to `w`.
    pub fn write<W: Write>(&mut self, w: &mut W, x: f64) -> std::io::Result<()> {
        w.write_all(self.0.format(x).as_bytes())
    }

    /// Writes `,` then `x` to `w`.
    pub(crate) fn write_field<W: Write>(&mut self, w: &mut W, x: f64) -> std::io::Result<()> {
        w.write_all(b",")?;
        self.write(w, x)
    }

    /// The shortest text that parses back to `x` as an f32.
    pub fn format_single(&mut self, x: f32) -> &str {
        self.0.format(x)
    }

    /// Appends `x` to `s`.
    pub fn push(&mut self, s: &mut String, x: f64) {
        s.push_str(self.0.format(x));
    }
}

/// The most bytes [`Numbers`] writes for one f64: a sign, 17 digits, a point, `e`, an
/// exponent sign and three exponent digits (`-1.2345678901234567e-308`).
pub(crate) const MAX_NUMBER_BYTES: usize = 24;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_back_exactly() {
        let mut n = Numbers::new();
        // values whose 13-digit text would not read back, and the edges of the format
        let xs = [
            0.1 + 0.2,
            1.0 / 3.0,
            -2.0f64.sqrt() * 1e-300,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            -f64::MAX,
            0.0,
            -0.0,
            1.0,
            123456789012345680.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for x in xs {
            let s = n.format(x).to_string();
            let back: f64 = s.parse().unwrap();
            assert_eq!(back.to_bits(), x.to_bits(), "{x:e} written {s}");
            assert!(s.len() <= MAX_NUMBER_BYTES, "{s}");
        }
        assert_eq!(n.format(f64::NAN), "NaN");
        assert!(n.format(f64::NAN).parse::<f64>().unwrap().is_nan());
        // 0.1 + 0.2 needs 17 digits; 1/3 and 0.5 fewer than {:.12e} writes
        assert_eq!(n.format(0.1 + 0.2), "0.30000000000000004");
        assert_eq!(n.format(0.5), "0.5");
    }

    #[test]
    fn the_widest_number_fits_the_bound() {
        let mut n = Numbers::new();
        let x = -1.2345678901234567e-308;
        let s = n.format(x).to_string();
        assert_eq!(s.len(), MAX_NUMBER_BYTES, "{s}");
    }
}
