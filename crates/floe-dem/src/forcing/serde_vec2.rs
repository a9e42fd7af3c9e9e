//! Serde helpers: a [`Vec2`] is written as the two-element array `[x, y]`
//! (TOML `[10.0, 0.0]`, JSON `[10.0, 0.0]`), without enabling glam's own
//! serde feature.

use serde::{Deserialize, Deserializer, Serializer};

use crate::Vec2;

/// `#[serde(with = "vec2")]` for one vector.
pub(crate) mod vec2 {
    use super::*;

    pub(crate) fn serialize<S: Serializer>(v: &Vec2, s: S) -> Result<S::Ok, S::Error> {
        serde::Serialize::serialize(&[v.x, v.y], s)
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec2, D::Error> {
        let [x, y] = <[f64; 2]>::deserialize(d)?;
        Ok(Vec2::new(x, y))
    }
}

/// `#[serde(with = "vec2_seq")]` for a list of vectors.
pub(crate) mod vec2_seq {
    use super::*;

    pub(crate) fn serialize<S: Serializer>(v: &[Vec2], s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(v.iter().map(|p| [p.x, p.y]))
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Vec2>, D::Error> {
        let raw = Vec::<[f64; 2]>::deserialize(d)?;
        Ok(raw.into_iter().map(|[x, y]| Vec2::new(x, y)).collect())
    }
}
