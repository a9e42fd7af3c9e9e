//! The floe life cycle's fracture: when a floe's stress breaks it
//! ([`criteria`], [`rule`]) and the pieces it breaks into ([`split`]);
//! [`World::fracture`](crate::world::World::fracture) applies them.

pub mod criteria;
pub mod rule;
pub mod split;
