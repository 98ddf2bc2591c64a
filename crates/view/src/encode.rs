//! Compact encodings of the page's arrays: values quantised to 16-bit integers (offset and
//! step per array) or to bytes, little-endian, in base64; short series as JSON numbers
//! rounded to 4 significant digits.

use base64::Engine as _;
use serde::Serialize;

/// An array of reals quantised to 16-bit integers: value = `offset + step · k`,
/// `k` in −32767…32767, stored little-endian in base64 (`data`).
#[derive(Clone, Debug, Serialize)]
pub struct Quantised {
    /// Value of k = 0 (the middle of the range).
    pub offset: f64,
    /// Value of one integer step (half the range / 32767; 1 for a constant array).
    pub step: f64,
    /// Number of values.
    pub len: usize,
    /// Base64 of the little-endian `i16` values.
    pub data: String,
}

impl Quantised {
    /// Quantise `values` (finite) over their own range: the error is at most half a step,
    /// range / 131068.
    pub fn new(values: &[f64]) -> Self {
        let (lo, hi) = values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        let (offset, half) = if lo <= hi {
            (0.5 * (lo + hi), 0.5 * (hi - lo))
        } else {
            (0.0, 0.0)
        };
        let step = if half > 0.0 { half / 32767.0 } else { 1.0 };
        let mut bytes = Vec::with_capacity(2 * values.len());
        for &v in values {
            let k = ((v - offset) / step).round().clamp(-32767.0, 32767.0) as i16;
            bytes.extend_from_slice(&k.to_le_bytes());
        }
        Self {
            offset: sig(offset, 9),
            step,
            len: values.len(),
            data: base64(&bytes),
        }
    }

    /// The values back (as the page decodes them).
    pub fn decode(&self) -> Vec<f64> {
        let bytes = base64::engine::general_purpose::STANDARD
            .decode(&self.data)
            .unwrap_or_default();
        bytes
            .chunks_exact(2)
            .map(|b| self.offset + self.step * f64::from(i16::from_le_bytes([b[0], b[1]])))
            .collect()
    }
}

/// Fractions in [0, 1] as bytes 0…254 in base64; `None` (unknown) as 255.
pub fn fractions_u8(values: impl IntoIterator<Item = Option<f64>>) -> String {
    let bytes: Vec<u8> = values
        .into_iter()
        .map(|v| match v {
            Some(x) if x.is_finite() => (x.clamp(0.0, 1.0) * 254.0).round() as u8,
            _ => 255,
        })
        .collect();
    base64(&bytes)
}

/// Standard base64 of `bytes`.
pub fn base64(bytes: &[u8]) -> String {
    base64::engine::general_purpose::STANDARD.encode(bytes)
}

/// `x` rounded to `digits` significant digits (non-finite values become 0, which JSON
/// cannot hold otherwise).
pub fn sig(x: f64, digits: usize) -> f64 {
    if !x.is_finite() {
        return 0.0;
    }
    if x == 0.0 {
        return 0.0;
    }
    format!("{:.*e}", digits.saturating_sub(1), x)
        .parse()
        .unwrap_or(x)
}

/// `x` rounded to 4 significant digits (curves drawn in the page).
pub fn sig4(x: f64) -> f64 {
    sig(x, 4)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantised_values_come_back_within_half_a_step() {
        let v: Vec<f64> = (0..200)
            .map(|i| (i as f64 * 0.37).sin() * 1.7 + 0.4)
            .collect();
        let q = Quantised::new(&v);
        let back = q.decode();
        assert_eq!(back.len(), v.len());
        let range = 2.0 * 1.7;
        for (a, b) in v.iter().zip(&back) {
            assert!((a - b).abs() <= range / 131068.0 * 1.01, "{a} {b}");
        }
        // a constant array decodes exactly
        let c = Quantised::new(&[2.5; 4]);
        assert_eq!(c.decode(), vec![2.5; 4]);
    }

    #[test]
    fn fractions_map_to_bytes_and_unknown_to_255() {
        let s = fractions_u8([Some(0.0), Some(1.0), Some(0.5), None, Some(2.0)]);
        let b = base64::engine::general_purpose::STANDARD.decode(s).unwrap();
        assert_eq!(b, vec![0, 254, 127, 255, 254]);
    }

    #[test]
    fn sig_rounds_to_significant_digits() {
        assert_eq!(sig4(123.456), 123.5);
        assert_eq!(sig4(-0.00123456), -0.001235);
        assert_eq!(sig4(f64::NAN), 0.0);
    }
}
