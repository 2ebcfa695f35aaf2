//! Exact partial derivatives over the C ABI: FMI 2.0's `fmi2GetDirectionalDerivative`, FMI 3.0's
//! directional and adjoint derivatives, all from the model's dual numbers
//! ([`Model::partials`]). The knowns are the continuous inputs, and in Model Exchange also the
//! continuous states; the unknowns the continuous outputs, and in Model Exchange also the state
//! derivatives.

use super::*;
use crate::model::partials::Seeded;
use crate::model::{Causality, Variability};

impl<M: Model> Instance<M> {
    /// The variable `vr` if this FMU lists it (a tailored one lists some).
    fn variable(&self, vr: u32) -> Result<&'static Var, String> {
        match Self::table().get(vr as usize) {
            Some(v) if self.listed(vr) => Ok(v),
            _ => Err(self.unlisted(vr)),
        }
    }

    /// Is `vr` a continuous state (Model Exchange)?
    fn is_state(&self, vr: u32) -> bool {
        self.me.is_me && Self::table().iter().any(|v| v.derivative == Some(vr))
    }

    fn check_known(&self, vr: u32) -> Result<(), String> {
        let v = self.variable(vr)?;
        let input = v.causality == Causality::Input && matches!(v.ty, VarType::Real);
        if input || self.is_state(vr) {
            return Ok(());
        }
        Err(format!(
            "{} is no known of a partial derivative: the knowns are the Real inputs{}",
            v.name,
            if self.me.is_me {
                " and the continuous states"
            } else {
                ""
            }
        ))
    }

    fn check_unknown(&self, vr: u32) -> Result<(), String> {
        let v = self.variable(vr)?;
        let output = v.causality == Causality::Output
            && matches!(v.ty, VarType::Real)
            && v.variability == Variability::Continuous;
        if output || (self.me.is_me && v.derivative.is_some()) {
            return Ok(());
        }
        Err(format!(
            "{} is no unknown of a partial derivative: the unknowns are the continuous Real outputs{}",
            v.name,
            if self.me.is_me {
                " and the state derivatives"
            } else {
                ""
            }
        ))
    }

    /// The derivatives of `unknowns` along the direction `seed` over `knowns`, into `out`
    /// (`out.len() == unknowns.len()`, `seed.len() == knowns.len()`). Every argument is checked
    /// before the model computes anything; a refused call changes nothing.
    pub fn partials_along(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        out: &mut [f64],
    ) -> Result<(), String> {
        if !M::PARTIALS {
            return Err("not supported: providesDirectionalDerivative is false (this FMU offers no partial derivatives)".into());
        }
        for &k in knowns {
            self.check_known(k)?;
        }
        for &u in unknowns {
            self.check_unknown(u)?;
        }
        if let Some(i) = seed.iter().position(|x| !x.is_finite()) {
            return Err(format!(
                "the seed of {} is {}, not finite",
                Self::table()[knowns[i] as usize].name,
                seed[i]
            ));
        }
        self.refresh()?;
        let n = Self::table().len();
        let mut s = vec![0.0; n];
        for (&k, &x) in knowns.iter().zip(seed) {
            // a known named twice: the derivative is linear in the seed
            s[k as usize] += x;
        }
        let mut got: Vec<Option<f64>> = vec![None; n];
        let model = self.model.as_mut().expect("prepared by refresh");
        model.partials(&Seeded::new(&self.values, &s), self.time, &mut |v, d| {
            got[v.vr() as usize] = Some(d.eps);
        })?;
        for (o, &u) in out.iter_mut().zip(unknowns) {
            let name = Self::table()[u as usize].name;
            *o = got[u as usize]
                .ok_or_else(|| format!("the model computed no partial derivative of {name}"))?;
            if !o.is_finite() {
                return Err(format!(
                    "the partial derivative of {name} at t = {} is {o}: the model has no finite derivative here",
                    self.time
                ));
            }
        }
        Ok(())
    }

    /// `fmi2GetDirectionalDerivative`.
    ///
    /// # Safety
    /// The arrays hold `nu`, `nk`, `nk` and `nu` elements (checked for NULL).
    pub unsafe fn directional_derivative(
        &mut self,
        unknown: *const ValueReference,
        nu: usize,
        known: *const ValueReference,
        nk: usize,
        dv_known: *const Real,
        dv_unknown: *mut Real,
    ) -> Outcome {
        // SAFETY: as this function.
        let (u, k, seed, out) = unsafe {
            (
                slice(unknown, nu, "vUnknown_ref")?,
                slice(known, nk, "vKnown_ref")?,
                slice(dv_known, nk, "dvKnown")?,
                slice_mut(dv_unknown, nu, "dvUnknown")?,
            )
        };
        self.partials_along(u, k, seed, out)?;
        Ok(Status::Ok)
    }

    /// FMI 3.0's adjoint derivatives: `out[j] = Σ_i seed[i]·∂unknowns[i]/∂knowns[j]`, one
    /// direction per known (`seed.len() == unknowns.len()`, `out.len() == knowns.len()`).
    pub fn adjoint_along(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        out: &mut [f64],
    ) -> Result<(), String> {
        if !M::PARTIALS {
            return Err("not supported: providesAdjointDerivatives is false (this FMU offers no partial derivatives)".into());
        }
        for &k in knowns {
            self.check_known(k)?;
        }
        for &u in unknowns {
            self.check_unknown(u)?;
        }
        if let Some(i) = seed.iter().position(|x| !x.is_finite()) {
            return Err(format!(
                "the seed of {} is {}, not finite",
                Self::table()[unknowns[i] as usize].name,
                seed[i]
            ));
        }
        let mut column = vec![0.0; unknowns.len()];
        let mut o = vec![0.0; knowns.len()];
        for (j, &k) in knowns.iter().enumerate() {
            self.partials_along(unknowns, &[k], &[1.0], &mut column)?;
            o[j] = seed.iter().zip(&column).map(|(s, c)| s * c).sum();
        }
        out.copy_from_slice(&o);
        Ok(())
    }
}
