//! Per-floe fields for maps, from one snapshot's floes and contacts.

use floe_analysis::love_weber::{stress_moments, ContactForces};

/// One snapshot's contacts, as stored in the output file.
#[derive(Debug, Clone, Copy)]
pub struct ContactView<'a> {
    /// Floe indices `(a, b)` of each contact.
    pub pair: &'a [[u32; 2]],
    /// Unit normal from `a` to `b`.
    pub normal: &'a [[f64; 2]],
    /// Normal force on `b`, N (>= 0).
    pub normal_force_n: &'a [f64],
    /// Tangential force on `b` along `perp(normal)`, N.
    pub tangential_force_n: &'a [f64],
    /// Contact point (in the frame where `a` sits at its stored position), m.
    pub point: &'a [[f64; 2]],
    /// Rate-and-state state variable.
    pub theta: &'a [f64],
}

/// Mean `theta` over each floe's contacts; `None` for floes without contacts.
pub fn mean_theta(n_floes: usize, contacts: &ContactView) -> Vec<Option<f64>> {
    let mut sum = vec![(0.0, 0usize); n_floes];
    for (pair, &theta) in contacts.pair.iter().zip(contacts.theta) {
        for &i in pair {
            sum[i as usize].0 += theta;
            sum[i as usize].1 += 1;
        }
    }
    sum.into_iter()
        .map(|(s, n)| (n > 0).then(|| s / n as f64))
        .collect()
}

/// Vertically integrated pressure of each floe, N/m, compression positive:
/// `p = -tr(sigma)/2` with the floe's Love-Weber stress
/// `sigma = (1/A) sum over its contacts of (x_c - x) (x) f`, `f` the contact
/// force on the floe. `period` gives the domain's period along each axis
/// (for floes whose contact lies across a periodic boundary). `None` for
/// floes without contacts.
pub fn pressure(
    position: &[[f64; 2]],
    area_m2: &[f64],
    contacts: &ContactView,
    period: [Option<f64>; 2],
) -> Vec<Option<f64>> {
    let forces = ContactForces {
        pair: contacts.pair,
        point: contacts.point,
        normal: contacts.normal,
        normal_force_n: contacts.normal_force_n,
        tangential_force_n: contacts.tangential_force_n,
    };
    let moments = stress_moments(position, &forces, period);
    let mut touched = vec![false; position.len()];
    for &i in contacts.pair.iter().flatten() {
        touched[i as usize] = true;
    }
    moments
        .iter()
        .zip(area_m2)
        .zip(touched)
        .map(|((m, &area), touched)| touched.then(|| -0.5 * (m[0] + m[3]) / area))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_floe_squeezed_from_both_sides_is_in_compression_by_force_times_arm_over_area() {
        // Floe 1 (area 4 m^2, centre 0) pressed by floes 0 and 2 at x = -1
        // and x = +1 with 10 N: sigma_xx = (1/4)(2 * (-1 * 10)) = -5 N/m,
        // sigma_yy = 0, pressure = 2.5 N/m.
        let pair = [[0, 1], [1, 2]];
        let normal = [[1.0, 0.0], [1.0, 0.0]];
        let view = ContactView {
            pair: &pair,
            normal: &normal,
            normal_force_n: &[10.0, 10.0],
            tangential_force_n: &[0.0, 0.0],
            point: &[[-1.0, 0.0], [1.0, 0.0]],
            theta: &[0.1, 0.3],
        };
        let p = pressure(
            &[[-2.0, 0.0], [0.0, 0.0], [2.0, 0.0]],
            &[4.0, 4.0, 4.0],
            &view,
            [None, None],
        );
        assert!((p[1].unwrap() - 2.5).abs() < 1e-12);
        assert!((p[0].unwrap() - 1.25).abs() < 1e-12);
        assert_eq!(
            mean_theta(4, &view),
            vec![Some(0.1), Some(0.2), Some(0.3), None]
        );
        // Across a periodic boundary of period 10: floe 2 stored at x = 12.
        let p = pressure(
            &[[-2.0, 0.0], [0.0, 0.0], [12.0, 0.0]],
            &[4.0, 4.0, 4.0],
            &view,
            [Some(10.0), None],
        );
        assert!((p[2].unwrap() - 1.25).abs() < 1e-12);
    }
}
