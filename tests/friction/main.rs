//! floe-friction: the contact laws against analytic solutions, property
//! tests of the per-contact update, no allocation in it, and fitting.

#[path = "../support/counting_allocator.rs"]
mod counting_allocator;
mod fit;
mod kernel_properties;
mod no_alloc;
mod physics;
#[path = "../support/proptest_settings.rs"]
mod proptest_settings;
