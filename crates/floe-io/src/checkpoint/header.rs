//! The 32 bytes before the payload: magic, format version, payload length
//! and its checksum.

use super::bytes::ReadResult;

/// First bytes of every checkpoint.
pub const MAGIC: &[u8; 8] = b"FLOECKPT";
/// Version of the encoding written for a state with a welding ledger.
pub const FORMAT_VERSION: u32 = 11;
/// Version written for a state that has ridged but not welded: 11 without
/// its last section.
pub const WITHOUT_WELDING_VERSION: u32 = 10;
/// Version written for a state with bonds but no ridging: 10 without its
/// last section.
pub const WITHOUT_RIDGING_VERSION: u32 = 9;
/// Version written for a state with the life cycle (floe stress or a next
/// floe id) but no bonds: 9 without its last section.
pub const WITHOUT_BONDS_VERSION: u32 = 8;
/// Version written for a state without the life cycle: 8 without its last
/// section.
pub const WITHOUT_LIFE_CYCLE_VERSION: u32 = 7;
/// The oldest version read; older and newer ones are refused.
pub const OLDEST_READABLE_VERSION: u32 = 1;
/// Bytes before the payload.
pub const HEADER_LEN: usize = 32;

/// FNV-1a, 64 bit.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The checkpoint: the header of `payload` in format `version`, then
/// `payload`.
pub(super) fn write(payload: &[u8], version: u32) -> Vec<u8> {
    let mut out = Vec::with_capacity(HEADER_LEN + payload.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&version.to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&fnv1a64(payload).to_le_bytes());
    out.extend_from_slice(payload);
    out
}

/// Checks the header and checksum only; returns the payload.
pub fn verify(bytes: &[u8]) -> ReadResult<&[u8]> {
    if bytes.len() < HEADER_LEN {
        return Err(format!("{} bytes, shorter than the header", bytes.len()));
    }
    if &bytes[..8] != MAGIC {
        return Err("bad magic (not a floe checkpoint)".into());
    }
    let word = |at: usize| {
        let mut b = [0; 8];
        b.copy_from_slice(&bytes[at..at + 8]);
        u64::from_le_bytes(b)
    };
    let version = version_of(bytes);
    if !(OLDEST_READABLE_VERSION..=FORMAT_VERSION).contains(&version) {
        return Err(format!(
            "format version {version}; this floe reads versions {OLDEST_READABLE_VERSION} to {FORMAT_VERSION}"
        ));
    }
    let len = word(16);
    let available = (bytes.len() - HEADER_LEN) as u64;
    if len > available {
        return Err(format!(
            "payload of {len} bytes but only {available} stored"
        ));
    }
    let payload = &bytes[HEADER_LEN..HEADER_LEN + len as usize];
    let (stored, actual) = (word(24), fnv1a64(payload));
    if stored != actual {
        return Err(format!(
            "checksum mismatch (stored {stored:016x}, computed {actual:016x})"
        ));
    }
    Ok(payload)
}

/// The format version in a header that [`verify`] accepted.
pub(super) fn version_of(bytes: &[u8]) -> u32 {
    u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]])
}
