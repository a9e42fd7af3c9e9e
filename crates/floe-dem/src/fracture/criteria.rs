//! Fracture criteria as closed-form inequalities on a floe's principal
//! stresses (Pa, tension positive), the two of the anchors (SubZero,
//! Manucharyan & Montemuro 2022; Subzero.jl `fractures.jl`): a
//! Mohr-Coulomb cone with a compressive cap, and Hibler's (1979) elliptical
//! yield curve. The anchors draw each as a polygon in principal-stress
//! space and test the point against it; here each is its own inequality,
//! so there is no polygon resolution to converge.

/// The principal stresses `(sigma_1, sigma_2)`, `sigma_1 >= sigma_2`, of
/// the symmetric part of `[xx, xy, yx, yy]` (Pa).
pub fn principal_stresses(sigma: [f64; 4]) -> (f64, f64) {
    let mean = 0.5 * (sigma[0] + sigma[3]);
    let half_diff = 0.5 * (sigma[0] - sigma[3]);
    let shear = 0.5 * (sigma[1] + sigma[2]);
    let radius = half_diff.hypot(shear);
    (mean + radius, mean - radius)
}

/// Which criterion breaks floes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FractureCriterion {
    /// The Mohr-Coulomb cone with a compressive cap.
    MohrCoulomb(MohrCoulomb),
    /// Hibler's elliptical yield curve.
    Hibler(HiblerEllipse),
}

impl FractureCriterion {
    /// Whether principal stresses `(s1, s2)` (Pa) of a floe `thickness_m`
    /// thick in ice of concentration `concentration` lie outside the
    /// criterion (the floe breaks). Mohr-Coulomb uses neither. A
    /// non-finite stress is not judged (`false`): the engine stops a run
    /// whose state is not finite before this is asked.
    pub fn breaks(&self, (s1, s2): (f64, f64), thickness_m: f64, concentration: f64) -> bool {
        match self {
            Self::MohrCoulomb(m) => m.breaks((s1, s2)),
            Self::Hibler(h) => h.breaks((s1, s2), h.strength_pa(thickness_m, concentration)),
        }
    }
}

/// SubZero's Mohr-Coulomb cone: in principal-stress space the triangle
/// whose apex is the biaxial tensile strength and whose base, the
/// compressive cap, joins `(-sigma_11, -sigma_22)` to its mirror image.
/// With `q = (sqrt(mu_i^2 + 1) + mu_i)^2` from the internal friction
/// `mu_i`, the uniaxial compressive strength `sigma_c`:
/// `sigma_1 = (1/q + 1) sigma_c / (1/q - q)`, `sigma_2 = q sigma_1 +
/// sigma_c`, `sigma_22 = q sigma_11 + sigma_c` (SubZero's equations, its
/// signs: the vertices are their negatives).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MohrCoulomb {
    /// `q`, from the internal friction.
    pub q: f64,
    /// `sigma_c`, Pa.
    pub sigma_c_pa: f64,
    /// `sigma_11`, Pa: where the cap meets the cone.
    pub sigma_11_pa: f64,
}

impl Default for MohrCoulomb {
    /// SubZero's defaults: `q = 5.2`, `sigma_c = 250 kPa`, `sigma_11 =
    /// -33.75 kPa`.
    fn default() -> Self {
        Self {
            q: 5.2,
            sigma_c_pa: 2.5e5,
            sigma_11_pa: -3.375e4,
        }
    }
}

impl MohrCoulomb {
    /// Checks the parameters: `q > 1` (a positive internal friction),
    /// `sigma_c > 0`, and a cap on the compressive side of the apex
    /// (`sigma_11 > sigma_c / (1 - q)`), so that an unstressed floe is
    /// inside. Names the first parameter that is not.
    pub fn check(&self) -> Result<(), String> {
        let (q, sc, s11) = (self.q, self.sigma_c_pa, self.sigma_11_pa);
        if !(q.is_finite() && q > 1.0) {
            return Err(format!("q = {q}: must be finite and > 1"));
        }
        if !(sc.is_finite() && sc > 0.0) {
            return Err(format!("sigma_c = {sc} Pa: must be finite and > 0"));
        }
        let apex = sc / (1.0 - q);
        if !(s11.is_finite() && s11 > apex) {
            return Err(format!(
                "sigma_11 = {s11} Pa: must be finite and > sigma_c / (1 - q) = {apex} Pa, or the unstressed floe lies outside the cone"
            ));
        }
        Ok(())
    }

    /// The triangle's vertices in principal-stress space (Pa): the apex,
    /// then the two ends of the cap, counter-clockwise.
    pub fn vertices(&self) -> [[f64; 2]; 3] {
        let (q, sc, s11) = (self.q, self.sigma_c_pa, self.sigma_11_pa);
        let s1 = (1.0 / q + 1.0) * sc / (1.0 / q - q);
        let s2 = q * s1 + sc;
        let s22 = q * s11 + sc;
        let (apex, a, b) = ([-s1, -s2], [-s11, -s22], [-s22, -s11]);
        // Counter-clockwise whatever the parameters' signs.
        let cross = (a[0] - apex[0]) * (b[1] - apex[1]) - (a[1] - apex[1]) * (b[0] - apex[0]);
        if cross >= 0.0 {
            [apex, a, b]
        } else {
            [apex, b, a]
        }
    }

    /// Whether `(s1, s2)` lies strictly outside the triangle.
    pub fn breaks(&self, (s1, s2): (f64, f64)) -> bool {
        let v = self.vertices();
        (0..3).any(|k| {
            let (p, q) = (v[k], v[(k + 1) % 3]);
            (q[0] - p[0]) * (s2 - p[1]) - (q[1] - p[1]) * (s1 - p[0]) < 0.0
        })
    }
}

/// Hibler's (1979) elliptical yield curve as SubZero draws it: in
/// principal-stress space an ellipse centred on `(-P/2, -P/2)`, its major
/// semi-axis `P / sqrt 2` along the diagonal and its minor one half that,
/// with `P = p* h exp(-c (1 - C))`. `p*` is per metre of thickness (Pa/m),
/// so that `P` is a stress beside the floe's own (Pa).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HiblerEllipse {
    /// `p*`, Pa per metre of thickness.
    pub p_star_pa_per_m: f64,
    /// `c`, the concentration's e-folding.
    pub c: f64,
}

impl Default for HiblerEllipse {
    /// Subzero.jl's defaults: `p* = 2.25e5`, `c = 20`.
    fn default() -> Self {
        Self {
            p_star_pa_per_m: 2.25e5,
            c: 20.0,
        }
    }
}

impl HiblerEllipse {
    /// Checks the parameters: `p* > 0` and `c >= 0`, finite.
    pub fn check(&self) -> Result<(), String> {
        if !(self.p_star_pa_per_m.is_finite() && self.p_star_pa_per_m > 0.0) {
            return Err(format!(
                "p* = {}: must be finite and > 0",
                self.p_star_pa_per_m
            ));
        }
        if !(self.c.is_finite() && self.c >= 0.0) {
            return Err(format!("c = {}: must be finite and >= 0", self.c));
        }
        Ok(())
    }

    /// `P = p* h exp(-c (1 - C))`, Pa. Subzero.jl takes `h` as the mean
    /// thickness of all floes and `C = 1`; the caller chooses here (the
    /// floe's own thickness, or the pack's mean and concentration).
    pub fn strength_pa(&self, thickness_m: f64, concentration: f64) -> f64 {
        self.p_star_pa_per_m * thickness_m * (-self.c * (1.0 - concentration)).exp()
    }

    /// Whether `(s1, s2)` lies strictly outside the ellipse of strength
    /// `p > 0` (Pa). The ellipse touches the line `s1 + s2 = 0` at the
    /// origin: any pure shear or tension breaks the floe, as in SubZero.
    pub fn breaks(&self, (s1, s2): (f64, f64), p: f64) -> bool {
        let (x, y) = (s1 + 0.5 * p, s2 + 0.5 * p);
        // Along the diagonal and across it.
        let along = (x + y) / std::f64::consts::SQRT_2;
        let across = (y - x) / std::f64::consts::SQRT_2;
        let major = p / std::f64::consts::SQRT_2;
        let minor = 0.5 * major;
        (along / major).powi(2) + (across / minor).powi(2) > 1.0
    }
}
