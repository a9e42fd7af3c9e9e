//! [`Exact`]: a TOML array that must have exactly `N` elements.

use serde::Deserialize;

/// A TOML array of exactly `N` elements. (serde's own arrays take the
/// first `N` and drop the rest without a word.)
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Exact<T, const N: usize>(pub [T; N]);

impl<'de, T: Deserialize<'de>, const N: usize> Deserialize<'de> for Exact<T, N> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = Vec::<T>::deserialize(d)?;
        let n = v.len();
        let expected = format!("an array of {N} elements");
        v.try_into()
            .map(Exact)
            .map_err(|_| serde::de::Error::invalid_length(n, &expected.as_str()))
    }
}
