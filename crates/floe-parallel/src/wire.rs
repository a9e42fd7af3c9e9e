//! What processes send each other when floes migrate and when the whole
//! world is gathered: floes with their forces, and contact and bond
//! records named by their floes' ids (handles differ between processes). Encoded with
//! bincode, which keeps every `f64`'s bits.

use floe_dem::bonds::Bond;
use floe_dem::contacts::{BrokenContact, ContactRecord};
use floe_dem::floes::Floe;
use floe_dem::Vec2;
use serde::{de::DeserializeOwned, Deserialize, Serialize};

use crate::error::ParallelError;

/// A floe on its way to a process, with the forces of the last evaluation
/// and its stress.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(crate) struct Migrant {
    pub(crate) floe: Floe,
    pub(crate) force: Vec2,
    pub(crate) torque: f64,
    pub(crate) external_force: Vec2,
    pub(crate) external_torque: f64,
    /// Its time-averaged stress (`[xx, xy, yy]`, Pa), when floe stress is on.
    pub(crate) stress: Option<[f64; 3]>,
    /// The process that owns it from now on.
    pub(crate) owner: u32,
    /// Every process that holds it (owner and ghosts); sent to the owner.
    pub(crate) holders: Vec<u32>,
}

/// Floes and contact records for one process.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub(crate) struct Packet {
    pub(crate) floes: Vec<Migrant>,
    pub(crate) contacts: Vec<([u64; 2], ContactRecord)>,
    pub(crate) broken: Vec<([u64; 2], BrokenContact)>,
    pub(crate) bonds: Vec<([u64; 2], Bond)>,
}

/// `value` as bytes.
pub(crate) fn encode<T: Serialize>(value: &T) -> Vec<u8> {
    bincode::serialize(value).expect("in-memory encoding of plain data cannot fail")
}

/// A value from `encode`'s bytes.
pub(crate) fn decode<T: DeserializeOwned>(bytes: &[u8]) -> Result<T, ParallelError> {
    bincode::deserialize(bytes).map_err(|e| ParallelError::Wire(e.to_string()))
}

/// Writes `values` as little-endian `f64` bits (the halo's fixed records).
pub(crate) fn put_f64s(out: &mut Vec<u8>, values: &[f64]) {
    for v in values {
        out.extend_from_slice(&v.to_le_bytes());
    }
}

/// Reads `N` `f64`s from the front of `bytes`, advancing it.
pub(crate) fn take_f64s<const N: usize>(bytes: &mut &[u8]) -> Option<[f64; N]> {
    if bytes.len() < 8 * N {
        return None;
    }
    let mut out = [0.0; N];
    for (k, v) in out.iter_mut().enumerate() {
        *v = f64::from_le_bytes(bytes[8 * k..8 * k + 8].try_into().ok()?);
    }
    *bytes = &bytes[8 * N..];
    Some(out)
}
