//! floe-dem: physics of the engine (conservation, forcing, contacts, order
//! in time), its geometry (clipping, tessellations, broad phase) and
//! bitwise continuation.

mod broad_phase;
mod checkpoint;
mod clip;
mod cohesion;
mod contact_symmetry;
#[path = "../support/counting_allocator.rs"]
mod counting_allocator;
mod floe_edits;
mod floe_split;
mod floe_stress;
mod forcing;
mod fracture;
mod fracture_criteria;
mod fracture_split;
mod load_point;
mod physics;
mod power_law_floes;
#[path = "../support/proptest_settings.rs"]
mod proptest_settings;
mod ridging;
#[path = "../support/shape.rs"]
mod shape_support;
mod tessellation;
mod time_order;
mod welding;
