//! The contact numbers of the double-shear set-up: its overlap depth and
//! stiffnesses from the contact model, the block and the load.

use floe_dem::contact_model::ContactModel;

/// Contact numbers of the double-shear set-up, for a block of thickness
/// `h` (m), plan size `block` = [along the push, across] (m), a pusher plate
/// `pusher` (m) and `load` (N) on each sliding face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DoubleShearGeometry {
    /// Normal force per unit overlap area against a fixed block,
    /// `E h / sqrt(block area)`, Pa.
    pub kappa_pa: f64,
    /// Overlap depth of each side block giving `load`, m.
    pub depth_m: f64,
    /// Normal stiffness of the pusher contact (the loading spring), N/m.
    pub pusher_stiffness_n_per_m: f64,
    /// Tangential stiffness of one side contact, N/m.
    pub side_tangential_stiffness_n_per_m: f64,
    /// The pusher in series with the two side contacts in parallel, N/m.
    pub series_stiffness_n_per_m: f64,
}

/// See [`DoubleShearGeometry`].
pub fn double_shear_geometry(
    model: &ContactModel,
    thickness_m: f64,
    block: [f64; 2],
    pusher: [f64; 2],
    load_per_face_n: f64,
) -> DoubleShearGeometry {
    let kappa = model.youngs_modulus_pa * thickness_m / (block[0] * block[1]).sqrt();
    let k_pusher = kappa * pusher[1].min(block[1]);
    let k_t = kappa * block[0] / (2.0 * (1.0 + model.poisson_ratio));
    DoubleShearGeometry {
        kappa_pa: kappa,
        depth_m: load_per_face_n / (kappa * block[0]),
        pusher_stiffness_n_per_m: k_pusher,
        side_tangential_stiffness_n_per_m: k_t,
        series_stiffness_n_per_m: 1.0 / (1.0 / k_pusher + 1.0 / (2.0 * k_t)),
    }
}
