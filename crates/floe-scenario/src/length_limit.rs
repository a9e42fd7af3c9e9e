//! The largest length a scenario may give (shared by the key checks and the
//! builders of land and floe sizes).

/// Largest length or coordinate a file may give, m: beyond any basin (the
/// Earth's circumference is 4e7 m), and small enough that areas, masses
/// and the broad phase's cells stay finite.
pub const MAX_LENGTH_M: f64 = 1e8;
