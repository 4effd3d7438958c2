//! Large arrays in a checkpoint as base64 of their little-endian bytes: exact, a third of the
//! decimal text's size and written without formatting each number (the matrix of a reused
//! factor or multigrid hierarchy: 12 M values and their pattern at 10⁶ MEs; a rotation per ME).
//! Encoded piece by piece straight into the output (no copy of the whole array or its text).
//! Read from either form, so checkpoints written before still load.
//! `#[serde(with = "crate::packed")]` on a `Vec<f64>`, `crate::packed::u32s` on a `Vec<u32>`,
//! `crate::packed::mat3s` on a `Vec<Mat3>`. [`LittleEndian`] is also the VTU writer's.

use std::fmt;
use std::marker::PhantomData;

use base64::engine::general_purpose::STANDARD as BASE64;
use base64::Engine as _;
use nmm3d_geom::Mat3;
use serde::de::{self, Deserialize, SeqAccess, Visitor};
use serde::{Deserializer, Serializer};

/// A value stored as its little-endian bytes.
pub trait LittleEndian: Copy {
    /// Bytes per value.
    const SIZE: usize;
    /// Append the bytes.
    fn put(self, out: &mut Vec<u8>);
    /// The value of `SIZE` bytes.
    fn take(bytes: &[u8]) -> Self;
}

macro_rules! little_endian {
    ($($t:ty),*) => {$(
        impl LittleEndian for $t {
            const SIZE: usize = std::mem::size_of::<$t>();
            fn put(self, out: &mut Vec<u8>) {
                out.extend_from_slice(&self.to_le_bytes());
            }
            fn take(bytes: &[u8]) -> Self {
                <$t>::from_le_bytes(bytes.try_into().expect("SIZE bytes"))
            }
        }
    )*};
}
little_endian!(f64, i64, i32, u32, u8);

/// A 3 × 3 matrix as its nine entries, column-major (as nalgebra stores them).
impl LittleEndian for Mat3 {
    const SIZE: usize = 72;
    fn put(self, out: &mut Vec<u8>) {
        self.iter().for_each(|x| x.put(out));
    }
    fn take(bytes: &[u8]) -> Self {
        let e: Vec<f64> = bytes.chunks_exact(8).map(f64::take).collect();
        Mat3::from_column_slice(&e)
    }
}

/// Base64 of `bytes` handed to `sink` piece by piece, each piece a multiple of three bytes but
/// the last (so the pieces' encodings join into the whole's).
pub fn base64_pieces<E>(bytes: &[u8], mut sink: impl FnMut(&str) -> Result<(), E>) -> Result<(), E> {
    const PIECE: usize = 3 << 14;
    let mut text = vec![0u8; bytes.len().min(PIECE).div_ceil(3) * 4];
    for piece in bytes.chunks(PIECE) {
        let n = BASE64.encode_slice(piece, &mut text).expect("the buffer holds a piece's encoding");
        sink(std::str::from_utf8(&text[..n]).expect("base64 is ASCII"))?;
    }
    Ok(())
}

/// Base64 of the values' bytes, converted and written a few thousand values at a time.
pub struct Base64Of<'a, T>(pub &'a [T]);

impl<T: LittleEndian> fmt::Display for Base64Of<'_, T> {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        // A multiple of three values: every piece's bytes a multiple of three.
        const VALUES: usize = 3 << 10;
        let mut bytes = Vec::with_capacity(VALUES * T::SIZE);
        for piece in self.0.chunks(VALUES) {
            bytes.clear();
            piece.iter().for_each(|v| v.put(&mut bytes));
            base64_pieces(&bytes, |s| f.write_str(s))?;
        }
        Ok(())
    }
}

fn serialize_values<T: LittleEndian, S: Serializer>(values: &[T], s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(&Base64Of(values))
}

/// Reads base64 of the values' bytes, or an array of the values (the former form).
struct Packed<T>(PhantomData<T>);

impl<'de, T: LittleEndian + Deserialize<'de>> Visitor<'de> for Packed<T> {
    type Value = Vec<T>;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "an array or base64 of values of {} little-endian bytes", T::SIZE)
    }

    fn visit_str<E: de::Error>(self, text: &str) -> Result<Vec<T>, E> {
        let bytes = BASE64.decode(text).map_err(E::custom)?;
        if bytes.len() % T::SIZE != 0 {
            return Err(E::custom(format!("{} bytes are not whole values of {} bytes", bytes.len(), T::SIZE)));
        }
        Ok(bytes.chunks_exact(T::SIZE).map(T::take).collect())
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<T>, A::Error> {
        let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0));
        while let Some(v) = seq.next_element::<T>()? {
            out.push(v);
        }
        Ok(out)
    }
}

fn deserialize_values<'de, T: LittleEndian + Deserialize<'de>, D: Deserializer<'de>>(d: D) -> Result<Vec<T>, D::Error> {
    d.deserialize_any(Packed(PhantomData))
}

/// Serialize `Vec<f64>` as one base64 string.
pub fn serialize<S: Serializer>(values: &[f64], s: S) -> Result<S::Ok, S::Error> {
    serialize_values(values, s)
}

/// Deserialize `Vec<f64>` from a base64 string or an array of numbers.
pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
    deserialize_values(d)
}

/// A `Vec<u32>` (a sparsity pattern's indices) as base64.
pub mod u32s {
    use serde::{Deserializer, Serializer};

    /// Serialize as one base64 string.
    pub fn serialize<S: Serializer>(values: &[u32], s: S) -> Result<S::Ok, S::Error> {
        super::serialize_values(values, s)
    }

    /// Deserialize from that string or an array of numbers.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<u32>, D::Error> {
        super::deserialize_values(d)
    }
}

/// A `Vec<Mat3>` as base64 of the matrices' entries (column-major).
pub mod mat3s {
    use nmm3d_geom::Mat3;
    use serde::{Deserializer, Serializer};

    /// Serialize as one base64 string of 9 f64 per matrix.
    pub fn serialize<S: Serializer>(values: &[Mat3], s: S) -> Result<S::Ok, S::Error> {
        super::serialize_values(values, s)
    }

    /// Deserialize from that string or from a sequence of matrices (the former layout).
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Mat3>, D::Error> {
        super::deserialize_values(d)
    }
}

#[cfg(test)]
mod tests {
    use serde::{Deserialize, Serialize};

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct Holder {
        #[serde(with = "super")]
        values: Vec<f64>,
    }

    #[test]
    fn values_round_trip_bit_for_bit_and_the_old_array_form_still_reads() {
        let h = Holder { values: vec![0.1, -3.5e300, f64::MIN_POSITIVE, -0.0, 1.0 / 3.0] };
        let text = serde_json::to_string(&h).unwrap();
        assert!(text.contains("\"values\":\""), "{text}");
        let back: Holder = serde_json::from_str(&text).unwrap();
        assert!(back.values.iter().zip(&h.values).all(|(a, b)| a.to_bits() == b.to_bits()));
        let old: Holder = serde_json::from_str("{\"values\": [0.1, -2.0, 1e-300]}").unwrap();
        assert_eq!(old.values, vec![0.1, -2.0, 1e-300]);
        assert!(serde_json::from_str::<Holder>("{\"values\": \"AAA=\"}").is_err());
    }

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct Rotations {
        #[serde(with = "super::mat3s")]
        r: Vec<nmm3d_geom::Mat3>,
    }

    #[test]
    fn matrices_round_trip_and_the_former_layout_still_reads() {
        let m = nmm3d_geom::Mat3::new(1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 0.1);
        let h = Rotations { r: vec![m, m.transpose()] };
        let back: Rotations = serde_json::from_str(&serde_json::to_string(&h).unwrap()).unwrap();
        assert_eq!(back, h);
        #[derive(Serialize)]
        struct Former {
            r: Vec<nmm3d_geom::Mat3>,
        }
        let former = serde_json::to_string(&Former { r: h.r.clone() }).unwrap();
        assert_eq!(serde_json::from_str::<Rotations>(&former).unwrap(), h);
    }

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct Indices {
        #[serde(with = "super::u32s")]
        i: Vec<u32>,
    }

    /// Longer than one encoding piece: the pieces join into the whole array's encoding.
    #[test]
    fn long_index_arrays_round_trip_and_the_array_form_still_reads() {
        let h = Indices { i: (0..10_007u32).map(|k| k.wrapping_mul(2_654_435_761)).collect() };
        let text = serde_json::to_string(&h).unwrap();
        assert_eq!(text.len(), "{\"i\":\"\"}".len() + (4 * h.i.len()).div_ceil(3) * 4);
        assert_eq!(serde_json::from_str::<Indices>(&text).unwrap(), h);
        assert_eq!(serde_json::from_str::<Indices>("{\"i\": [3, 0, 7]}").unwrap().i, vec![3, 0, 7]);
        assert!(serde_json::from_str::<Indices>("{\"i\": \"AAA=\"}").is_err());
    }
}
