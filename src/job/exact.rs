//! Fixed-length number arrays that refuse extra or missing numbers. Serde reads
//! `[f64; 2]` from the first two elements of a longer TOML array and silently
//! drops the rest (`origin = [1.0, 2.0, 3.0]` was accepted); these read the whole
//! array and name its length when it is wrong.

use serde::{de::Error, Deserialize, Deserializer};

/// Exactly `N` numbers.
struct Exact<const N: usize>([f64; N]);

impl<'de, const N: usize> Deserialize<'de> for Exact<N> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = Vec::<f64>::deserialize(d)?;
        let expected = match N {
            2 => "2 numbers [x, y]".to_string(),
            3 => "3 numbers [x, y, z]".to_string(),
            n => format!("{n} numbers"),
        };
        <[f64; N]>::try_from(v.as_slice())
            .map(Exact)
            .map_err(|_| D::Error::invalid_length(v.len(), &expected.as_str()))
    }
}

/// `Option<[f64; N]>` with exactly `N` numbers (`#[serde(default, deserialize_with)]`).
pub(crate) fn opt<'de, D: Deserializer<'de>, const N: usize>(
    d: D,
) -> Result<Option<[f64; N]>, D::Error> {
    Ok(Option::<Exact<N>>::deserialize(d)?.map(|e| e.0))
}

/// `Option<Vec<[f64; N]>>`, every element exactly `N` numbers.
pub(crate) fn opt_vec<'de, D: Deserializer<'de>, const N: usize>(
    d: D,
) -> Result<Option<Vec<[f64; N]>>, D::Error> {
    Ok(Option::<Vec<Exact<N>>>::deserialize(d)?.map(|v| v.into_iter().map(|e| e.0).collect()))
}
