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

    /// `vr` is a known (`known`) or an unknown of a partial derivative: a Real input or a
    /// continuous Real output, and in Model Exchange also a continuous state or a state
    /// derivative.
    fn check_role(&self, vr: u32, known: bool) -> Result<(), String> {
        let v = self.variable(vr)?;
        let real = matches!(v.ty, VarType::Real);
        let (ok, role, what, me_too) = if known {
            let input = real && v.causality == Causality::Input;
            (
                input || self.is_state(vr),
                "known",
                "Real inputs",
                "continuous states",
            )
        } else {
            let output = real
                && v.causality == Causality::Output
                && v.variability == Variability::Continuous;
            let derivative = self.me.is_me && v.derivative.is_some();
            (
                output || derivative,
                "unknown",
                "continuous Real outputs",
                "state derivatives",
            )
        };
        if ok {
            return Ok(());
        }
        let also = if self.me.is_me {
            format!(" and the {me_too}")
        } else {
            String::new()
        };
        Err(format!(
            "{} is no {role} of a partial derivative: the {role}s are the {what}{also}",
            v.name
        ))
    }

    /// Before a partial derivative is computed: the FMU offers them (`flag` names the
    /// capability), every known and unknown is one, and the seed (whose values belong to the
    /// variables `seed.1`) is finite.
    fn check_partials(
        &self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: (&[f64], &[u32]),
        flag: &str,
    ) -> Result<(), String> {
        if !M::PARTIALS {
            return Err(format!(
                "not supported: {flag} is false (this FMU offers no partial derivatives)"
            ));
        }
        for &k in knowns {
            self.check_role(k, true)?;
        }
        for &u in unknowns {
            self.check_role(u, false)?;
        }
        match seed.0.iter().position(|x| !x.is_finite()) {
            Some(i) => Err(format!(
                "the seed of {} is {}, not finite",
                Self::table()[seed.1[i] as usize].name,
                seed.0[i]
            )),
            None => Ok(()),
        }
    }

    /// The partial derivatives of `unknowns` with respect to `knowns`, into `out`. Directional
    /// (`adjoint` false): along the direction `seed` (one value per known), one value per
    /// unknown. Adjoint (FMI 3.0): `out[j] = Σ_i seed[i]·∂unknowns[i]/∂knowns[j]` (one seed per
    /// unknown, one value per known), from one direction per known. Every argument is checked
    /// before the model computes anything; a refused call changes nothing.
    pub fn partial_derivatives(
        &mut self,
        adjoint: bool,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        out: &mut [f64],
    ) -> Result<(), String> {
        let (of, flag) = if adjoint {
            (unknowns, "providesAdjointDerivatives")
        } else {
            (knowns, "providesDirectionalDerivative")
        };
        self.check_partials(unknowns, knowns, (seed, of), flag)?;
        if !adjoint {
            return self.along(unknowns, knowns, seed, out);
        }
        let mut column = vec![0.0; unknowns.len()];
        for (o, &k) in out.iter_mut().zip(knowns) {
            self.along(unknowns, &[k], &[1.0], &mut column)?;
            *o = seed.iter().zip(&column).map(|(s, c)| s * c).sum();
        }
        Ok(())
    }

    /// The derivatives of `unknowns` along `seed` over `knowns` (checked), into `out`.
    fn along(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        out: &mut [f64],
    ) -> Result<(), String> {
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
        self.partial_derivatives(false, u, k, seed, out)?;
        Ok(Status::Ok)
    }
}
