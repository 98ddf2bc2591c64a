//! Ligament force–length laws of PredSim (PREDSIM.md §3.7): the exponential fit of
//! Gefen (2002) for every ligament and the hyperelastic law of Natali et al. (2010) for
//! the plantar fascia. Both are smooth (no branch on the length), so the same function
//! runs on `f64` and on derivative types.

use stride_ad::Scalar;

/// Which force–length law a ligament follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LigamentLaw {
    /// `ligamentGefen2002`: σ = 7.9884 (e^{8.2061(λ − 1.0018)} − 1) MPa, F = A σ, with the
    /// negative stresses switched off smoothly by ½(1 + tanh(π(20σ − 1))).
    Gefen2002,
    /// `plantarFasciaNatali2010`: A' = A λ^−0.8,
    /// σ = 14.449 (λ² − λ⁻¹) + 254.02 / (2 · 10.397) (e^{10.397(λ² − 1)} − 1) λ² MPa,
    /// F = σ A' · ½(1 + tanh(4000 (l − l_s) − 1.1)).
    PlantarFasciaNatali2010,
}

impl LigamentLaw {
    /// PredSim's default law for a ligament name: Natali for names containing
    /// `PlantarFascia`, Gefen otherwise.
    pub fn for_name(name: &str) -> Self {
        if name.contains("PlantarFascia") {
            Self::PlantarFasciaNatali2010
        } else {
            Self::Gefen2002
        }
    }

    /// Tension [N] of a ligament of cross-section `area` [mm²] and slack length `slack`
    /// [m] at path length `length` [m] (MPa × mm² = N).
    pub fn force<T: Scalar>(self, area: f64, slack: f64, length: T) -> T {
        let stretch = length * (1.0 / slack);
        match self {
            Self::Gefen2002 => {
                let sigma = (((stretch - 1.0018) * 8.2061).exp() - 1.0) * 7.9884;
                let on = (((sigma * 20.0) - 1.0) * std::f64::consts::PI).tanh() + 1.0;
                sigma * on * (0.5 * area)
            }
            Self::PlantarFasciaNatali2010 => {
                let s2 = stretch.sq();
                let sigma = (s2 - stretch.recip()) * 14.449
                    + (((s2 - 1.0) * 10.397).exp() - 1.0) * s2 * (254.02 / (2.0 * 10.397));
                let area = stretch.powf(-0.8) * area;
                let on = ((length - slack) * 4000.0 - 1.1).tanh() + 1.0;
                sigma * area * on * 0.5
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The laws against values worked out by hand from the published formulas.
    #[test]
    fn forces_at_a_few_stretches_match_the_formulas_by_hand() {
        let (area, slack) = (70.0, 0.146);
        // Gefen at λ = 1.03: σ = 7.9884 (e^{8.2061·0.0282} − 1) = 7.9884 · 0.260380 = 2.08001 MPa;
        // the switch is 1 to 1e-9 at σ ≈ 2.08 MPa.
        let l = 1.03 * slack;
        let sigma = 7.9884 * ((8.2061f64 * 0.0282).exp() - 1.0);
        assert!((sigma - 2.08001).abs() < 1e-4, "{sigma}");
        let f = LigamentLaw::Gefen2002.force(area, slack, l);
        assert!((f - sigma * area).abs() < 1e-6 * f, "{f}");
        // slack at λ = 0.98: σ < 0, F ≈ 0 (switch ½(1 + tanh(π(20σ − 1))) ≈ e^{−2π(1+20|σ|)})
        let f = LigamentLaw::Gefen2002.force(area, slack, 0.98 * slack);
        assert!(f.abs() < 1e-12, "{f}");
        // at σ = 0.05 MPa the switch is exactly ½
        let lam = 1.0018 + (1.0 + 0.05 / 7.9884f64).ln() / 8.2061;
        let f = LigamentLaw::Gefen2002.force(area, slack, lam * slack);
        assert!((f - 0.05 * area * 0.5).abs() < 1e-12, "{f}");
        // Natali at λ = 1.02: λ² = 1.0404, σ = 14.449 (1.0404 − 1/1.02)
        // + 12.21602 (e^{0.4200388} − 1) · 1.0404 = 0.86706 + 6.63464 MPa, A' = 70 · 1.02^−0.8, switch 1 − 7e-10.
        let lam: f64 = 1.02;
        let sigma = 14.449 * (1.0404 - 1.0 / 1.02)
            + 254.02 / 20.794 * ((10.397 * 0.0404f64).exp() - 1.0) * 1.0404;
        assert!((sigma - 7.50170).abs() < 1e-4, "{sigma}");
        let switch = 0.5 * (1.0 + (4000.0 * 0.02 * slack - 1.1f64).tanh());
        assert!(switch > 1.0 - 1e-9);
        let f = LigamentLaw::PlantarFasciaNatali2010.force(area, slack, lam * slack);
        let want = sigma * area * lam.powf(-0.8) * switch;
        assert!((f - want).abs() < 1e-9 * want, "{f} vs {want}");
        // at l = l_s + 1.1/4000 the switch is ½ (σ at that stretch)
        let l = slack + 1.1 / 4000.0;
        let lam = l / slack;
        let sigma = 14.449 * (lam * lam - 1.0 / lam)
            + 254.02 / 20.794 * ((10.397 * (lam * lam - 1.0)).exp() - 1.0) * lam * lam;
        let f = LigamentLaw::PlantarFasciaNatali2010.force(area, slack, l);
        assert!(
            (f - 0.5 * sigma * area * lam.powf(-0.8)).abs() < 1e-9,
            "{f}"
        );
    }

    #[test]
    fn plantar_fascia_takes_natalis_law() {
        assert_eq!(
            LigamentLaw::for_name("PlantarFascia_r"),
            LigamentLaw::PlantarFasciaNatali2010
        );
        assert_eq!(
            LigamentLaw::for_name("LongPlantar1_l"),
            LigamentLaw::Gefen2002
        );
    }
}
