//! Large arrays of f64 in a checkpoint as base64 of their little-endian bytes: exact, a third
//! of the decimal text's size and written without formatting each number (the matrix of a
//! reused factor or multigrid hierarchy: 12 M values at 10⁶ MEs; a rotation per ME). Read from
//! either form, so checkpoints written before still load. `#[serde(with = "crate::packed")]`
//! on a `Vec<f64>`, `crate::packed::mat3s` on a `Vec<Mat3>`.

use base64::engine::general_purpose::STANDARD as BASE64;
use base64::Engine as _;
use serde::de::{self, SeqAccess, Visitor};
use serde::{Deserializer, Serializer};

/// Serialize as one base64 string.
pub fn serialize<S: Serializer>(values: &[f64], s: S) -> Result<S::Ok, S::Error> {
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    s.serialize_str(&BASE64.encode(bytes))
}

/// Deserialize from a base64 string or an array of numbers.
pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
    d.deserialize_any(Packed)
}

struct Packed;

impl<'de> Visitor<'de> for Packed {
    type Value = Vec<f64>;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("an array of numbers or base64 of little-endian f64")
    }

    fn visit_str<E: de::Error>(self, text: &str) -> Result<Vec<f64>, E> {
        let bytes = BASE64.decode(text).map_err(E::custom)?;
        if bytes.len() % 8 != 0 {
            return Err(E::custom(format!("{} bytes are not whole f64 values", bytes.len())));
        }
        Ok(bytes.chunks_exact(8).map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes"))).collect())
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<f64>, A::Error> {
        let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0));
        while let Some(v) = seq.next_element()? {
            out.push(v);
        }
        Ok(out)
    }
}

/// A `Vec<Mat3>` as the base64 of its matrices' entries (column-major, as nalgebra stores them).
pub mod mat3s {
    use nmm3d_geom::Mat3;
    use serde::de::{self, SeqAccess, Visitor};
    use serde::{Deserializer, Serializer};

    /// Serialize as one base64 string of 9 f64 per matrix.
    pub fn serialize<S: Serializer>(values: &[Mat3], s: S) -> Result<S::Ok, S::Error> {
        let flat: Vec<f64> = values.iter().flat_map(|m| m.iter().copied()).collect();
        super::serialize(&flat, s)
    }

    /// Deserialize from that string or from a sequence of matrices (the former layout).
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Mat3>, D::Error> {
        d.deserialize_any(Matrices)
    }

    struct Matrices;

    impl<'de> Visitor<'de> for Matrices {
        type Value = Vec<Mat3>;

        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a sequence of 3 × 3 matrices or base64 of their entries")
        }

        fn visit_str<E: de::Error>(self, text: &str) -> Result<Vec<Mat3>, E> {
            let flat = super::Packed.visit_str::<E>(text)?;
            if flat.len() % 9 != 0 {
                return Err(E::custom(format!("{} values are not whole 3 × 3 matrices", flat.len())));
            }
            Ok(flat.chunks_exact(9).map(Mat3::from_column_slice).collect())
        }

        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<Mat3>, A::Error> {
            let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0));
            while let Some(m) = seq.next_element::<Mat3>()? {
                out.push(m);
            }
            Ok(out)
        }
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
}
